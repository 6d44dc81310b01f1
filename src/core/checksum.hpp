#pragma once
// XXH64 (seed 0), the 64-bit checksum of a checkpoint's sections: it sees any damage to the
// bytes (a flipped bit, a byte changed, a length cut) but for a chance of 2^-64, at several
// GB/s, and takes its bytes in pieces of any size (a section is streamed into its file).
// The hashing is Debian's libxxhash-dev, inlined (XXH_INLINE_ALL): nothing to link, nothing
// exported. Private to the library: included by .cpp files only.
#include <cstdint>
#include <string_view>

#define XXH_INLINE_ALL
#include <xxhash.h>

namespace aggpack {

class Checksum {
 public:
  Checksum() { XXH64_reset(&state_, 0); }

  void add(std::string_view bytes) {
    if (!bytes.empty()) XXH64_update(&state_, bytes.data(), bytes.size());
  }

  [[nodiscard]] std::uint64_t value() const { return XXH64_digest(&state_); }

 private:
  XXH64_state_t state_{};
};

[[nodiscard]] inline std::uint64_t checksum(std::string_view bytes) {
  Checksum c;
  c.add(bytes);
  return c.value();
}

}  // namespace aggpack
