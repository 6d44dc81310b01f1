#pragma once
// What the parts of DemSystem (dem_system.cpp, dem_neighbour_list.cpp, dem_state.cpp) share:
// private to the dynamics module.
#include <cstdint>

namespace aggpack::dem_internal {

// Below this many particles a step is too short to pay for waking threads (and on a busy
// machine each barrier can cost a scheduler tick). Results do not depend on it.
inline constexpr std::uint32_t kThreadedFrom = 1024;
// Slots per force block. Larger blocks leave fewer pairs to the cross-block slots (48 bytes
// each); there must still be several blocks per thread to balance the load. Results depend
// on it (it fixes the summation order), the thread count does not.
inline constexpr std::uint32_t kForceBlock = 2048;

}  // namespace aggpack::dem_internal
