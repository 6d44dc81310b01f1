// One libFuzzer entry point; the build compiles it once per target with AGGPACK_FUZZ_TARGET
// naming the function of fuzz_targets.hpp.
#include "fuzz_targets.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  aggpack::fuzz::AGGPACK_FUZZ_TARGET(std::string_view(reinterpret_cast<const char*>(data), size));
  return 0;
}
