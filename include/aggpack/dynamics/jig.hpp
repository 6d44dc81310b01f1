#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "aggpack/dynamics/dem_system.hpp"
#include "aggpack/dynamics/settle.hpp"
#include "aggpack/dynamics/tap.hpp"

namespace aggpack {

// Jigging (ASTM C29's jigging procedure, README "Jigging"): the container (floor and walls as
// one) raised by `height` with an acceleration below g, so the bed rides with it, then
// released: it falls freely under gravity back to its rest height and stops dead there (the
// firm base); the bed rests, then the next drop. Left out: the standard raises one side and
// then the other, the measure pivoting on the opposite edge; we drop it level, every point of
// the floor from the full height, so every drop meets the base at sqrt(2 g h), the speed of the
// raised side (the largest; a level drop of h/2, the mean over the floor, would halve the
// energy). The height is a setting: a lab that lifts less, or a model of the tilt's mean, sets it.
struct JiggingSettings {
  std::size_t drops = 50;          // per layer (25 each side in the standard)
  double height = 0.05;            // m (about 2 in)
  double lift_acceleration = 4.9;  // m/s^2, below g: the bed stays on the floor while lifted
  double rest_time = 0.1;          // s after each drop, at most
  bool rest_until_quiet = false;   // end a rest early once the quiet criterion holds
};

struct JigReport {
  std::size_t drops = 0;
  double height = 0.0, lift_acceleration = 0.0, impact_speed = 0.0;  // m, m/s^2, m/s
  double rest_time = 0.0;
  bool rest_until_quiet = false;
  double density_before = 0.0;  // NaN when the boxes do not fit
  double time_before = 0.0;     // s, when the first drop began
  std::vector<TapSample> samples;  // after every drop's rest (`tap`: the drop)
  double simulated_time = 0.0;
  std::size_t steps = 0;
  double time_step = 0.0;
  double wall_clock_s = 0.0;
  bool continues_dem_system = false;
  [[nodiscard]] std::string csv() const;  // jig_drops.csv
};

// A jigging's loop (with the system's state, all it takes to continue it): inside drop `drop`
// (its steps not all run yet), or in the rest after it.
struct JigLoop {
  double start = 0.0;
  std::size_t start_steps = 0;
  std::size_t drop = 1;
  std::size_t drop_steps_left = 0;  // of the drop in progress (0: in the rest)
  double rest_end = 0.0;
  std::size_t rest_steps_left = 0;
  std::optional<double> quiet_since;
  SettleSample last;
  JigReport report;
};

// One drop's motion of the container from `start` (|g| the fall's acceleration).
ContainerMotion jig_motion(const JiggingSettings& settings, double start, double g);

JigLoop begin_jigging(const DemSystem& system, const JiggingSettings& settings, double density_before);
bool fits(const JigLoop& loop, const JiggingSettings& settings, const DemSystem& system);

// Jigs the bed of `system`: `loop` is begin_jigging's or a restored one (`resumed`), continued
// bit for bit. Fills loop.report but for its wall clock; its times are since the jigging began.
void jig(DemSystem& system, const ParticleStore& particles, const JiggingSettings& settings,
         const QuietCriterion& quiet, JigLoop& loop, bool resumed, const TapHooks& hooks);

}  // namespace aggpack
