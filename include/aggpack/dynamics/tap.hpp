#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "aggpack/dynamics/dem_system.hpp"
#include "aggpack/dynamics/settle.hpp"

namespace aggpack {

// Tapping (README, "Tapping"): each tap moves the container (floor and walls) up and back
// through half a sine period of peak acceleration Gamma g, then the bed rests; the density is
// measured after every rest.
struct TappingSettings {
  std::size_t taps = 10;
  double intensity = 2.0;         // Gamma = A w^2 / g
  double frequency = 30.0;        // Hz
  double rest_time = 0.15;        // s after each tap, at most
  bool rest_until_quiet = false;  // end a rest early once the quiet criterion holds
};

// The density after every tap (taps.csv) and what the tapping cost.
struct TapSample {
  std::size_t tap = 0;
  double time = 0.0;     // s of simulated time, at the end of the rest (tap(): since the tapping began)
  double density = 0.0;  // mean over the virtual boxes; NaN when they do not fit
  double translational_per_particle_mgd = 0.0;  // at the end of the rest
};
struct TapReport {
  std::size_t taps = 0;
  double intensity = 0.0, frequency = 0.0, amplitude = 0.0;  // Gamma, Hz, m
  double rest_time = 0.0;                                    // s, at most
  bool rest_until_quiet = false;
  double density_before = 0.0;                               // NaN when the boxes do not fit
  double time_before = 0.0;                                  // s, when the first tap began
  std::vector<TapSample> samples;
  double simulated_time = 0.0;  // s
  std::size_t steps = 0;
  double time_step = 0.0;
  double wall_clock_s = 0.0;
  int lammps_ranks = 0;  // 0: aggpack's DEM ran it; else LAMMPS on that many ranks
  bool continues_dem_system = false;  // the caller's: the DEM system of the step before went on
  [[nodiscard]] std::string csv() const;  // taps.csv
};

// The tap's amplitude, m: A = Gamma g / w^2.
double tap_amplitude(const TappingSettings& settings, double g);

// A tapping's loop (with the system's state, all it takes to continue it): inside tap `tap`
// (its steps not all run yet), or in the rest after it.
struct TapLoop {
  double start = 0.0;                // s, the system's time when the tapping began
  std::size_t start_steps = 0;       // the system's steps then
  std::size_t tap = 1;
  std::size_t tap_steps_left = 0;    // of the tap in progress (0: in the rest)
  double rest_end = 0.0;             // s, the system's time when the rest ends
  std::size_t rest_steps_left = 0;   // of the rest's sample interval in progress (0: at a sample)
  std::optional<double> quiet_since;
  SettleSample last;
  TapReport report;
};

// The loop of a tapping that has not begun, on `system` as it stands (`density_before`: the
// bed's density now).
TapLoop begin_tapping(const DemSystem& system, const TappingSettings& settings, double density_before);
// Whether a loop restored from a checkpoint is one of this tapping's, on this system.
bool fits(const TapLoop& loop, const TappingSettings& settings, const DemSystem& system);

// What a tapping tells its caller: every sample of the rests (its time since the tapping
// began; `phase` names the tap), its safe points (the caller may save the loop with the system
// or stop the run by throwing), and the density probe, measured after every rest.
struct TapHooks {
  std::function<void(const SettleSample& sample, std::string_view phase)> on_sample;
  std::function<void(std::string_view phase)> at_safe_point;
  DensityProbe density;
};

// Taps the bed of `system`: `loop` is begin_tapping's or a restored one (`resumed`), and
// the tapping continues where it stood, bit for bit. Rests end by time, or by `quiet` (its
// energy condition over its window) with rest_until_quiet. Fills loop.report but for its wall
// clock; its times are since the tapping began.
void tap(DemSystem& system, const ParticleStore& particles, const TappingSettings& settings,
         const QuietCriterion& quiet, TapLoop& loop, bool resumed, const TapHooks& hooks);

}  // namespace aggpack
