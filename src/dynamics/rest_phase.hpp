#pragma once
// The rest that ends a compaction's cycle (rodding, jigging): private to the dynamics module.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <iterator>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "aggpack/dynamics/settle.hpp"
#include "aggpack/dynamics/tap.hpp"

namespace aggpack::dynamics_internal {

// A compaction curve as CSV (taps.csv, jig_drops.csv): row 0 the bed before the first cycle,
// then one row per cycle, counted in the first column (`counter`: "tap", "drop").
inline std::string compaction_curve_csv(std::string_view counter, double time_before, double density_before,
                                        const std::vector<TapSample>& samples) {
  std::string body = fmt::format("{},time_s,density,translational_energy_per_particle_mgd\n", counter);
  const auto density_text = [](double d) { return std::isnan(d) ? std::string() : fmt::format("{:.6f}", d); };
  fmt::format_to(std::back_inserter(body), "0,{:.9g},{},\n", time_before, density_text(density_before));
  for (const TapSample& s : samples)
    fmt::format_to(std::back_inserter(body), "{},{:.9g},{},{:.6g}\n", s.tap, s.time, density_text(s.density),
                   s.translational_per_particle_mgd);
  return body;
}

// A rest's state, as it stands in a loop's saved fields.
struct RestState {
  double& rest_end;              // s, the system's time when the rest ends
  std::size_t& rest_steps_left;  // of the sample interval in progress (0: at a sample)
  std::optional<double>& quiet_since;
  SettleSample& last;
};

// Runs the rest to rest_end, sampling every sample interval, or until quiet (the criterion's
// energy over its window) when `until_quiet`; `sample` takes a sample into rest.last,
// `safe_point` is called inside and between the blocks. Resumable: it continues from the state.
inline void rest_bed(DemSystem& system, const QuietCriterion& quiet, bool until_quiet, RestState rest,
                     const std::function<void()>& sample, const std::function<void()>& safe_point) {
  const double dt = system.time_step();
  const std::size_t steps_per_sample = quiet.steps_per_sample(dt);
  while (rest.rest_steps_left > 0 || system.time() < rest.rest_end - 0.5 * dt) {
    if (rest.rest_steps_left == 0)
      rest.rest_steps_left =
          std::min(steps_per_sample, static_cast<std::size_t>(std::llround((rest.rest_end - system.time()) / dt)));
    run_block(system, rest.rest_steps_left, safe_point);
    sample();
    if (until_quiet) {
      if (rest.last.translational_per_particle_mgd > quiet.kinetic_fraction) rest.quiet_since.reset();
      else if (!rest.quiet_since) rest.quiet_since = rest.last.time;
      if (rest.quiet_since && rest.last.time - *rest.quiet_since >= quiet.window) break;
    }
    safe_point();
  }
}

}  // namespace aggpack::dynamics_internal
