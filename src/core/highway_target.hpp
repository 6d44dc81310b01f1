// The Highway targets this machine runs, and work run on one of them: for the tests and
// benchmarks that compare a SIMD kernel's targets (the contact law's, the grains' tangent
// search). Internal to the library's modules that dispatch with Highway; header only, so that
// core itself does not link Highway.
#pragma once

#include <hwy/targets.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace aggpack::highway {

inline std::vector<std::string> target_names() {
  std::vector<std::string> names;
  for (const std::int64_t target : hwy::SupportedAndGeneratedTargets()) names.emplace_back(hwy::TargetName(target));
  return names;
}

// `work()` with Highway's dispatch held to `target` (std::invalid_argument naming `who` when it
// is not one of target_names()). The choice is the process's: restored however the work ends,
// and no other thread may dispatch meanwhile.
template <class Work>
decltype(auto) on_target(const std::string& target, const char* who, Work&& work) {
  for (const std::int64_t t : hwy::SupportedAndGeneratedTargets()) {
    if (target != hwy::TargetName(t)) continue;
    struct Restore {
      ~Restore() { hwy::SetSupportedTargetsForTest(0); }
    } restore;
    hwy::SetSupportedTargetsForTest(t);
    return work();
  }
  throw std::invalid_argument(std::string(who) + ": " + target + " is not a target of this machine");
}

}  // namespace aggpack::highway
