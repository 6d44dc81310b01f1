#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <cstddef>
#include <functional>
#include <optional>
#include <string_view>
#include <vector>

#include "aggpack/core/enum_names.hpp"
#include "aggpack/dynamics/dem_system.hpp"

namespace aggpack {

// When a settling run stops: the bed is quiet, or the simulated time ran out.
struct QuietCriterion {
  double max_time = 2.0;            // s of simulated time
  double sample_interval = 1e-3;    // s between samples (time series and criterion)
  double window = 0.05;             // s over which the bed must stay quiet
  // Translational kinetic energy per particle / mean (m g d) below this. Spin is left out:
  // without twisting resistance a sphere may keep spinning about a contact normal forever.
  double kinetic_fraction = 1e-5;
  double density_tolerance = 5e-4;  // change of the virtual-box density over the window
  // DEM steps of `time_step` between two samples (at least one).
  [[nodiscard]] std::size_t steps_per_sample(double time_step) const {
    return std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(sample_interval / time_step)));
  }
};

enum class SettleEnd { Quiet, MaxTime };
inline constexpr std::array kSettleEndNames{EnumName<SettleEnd>{SettleEnd::Quiet, "quiet"},
                                            EnumName<SettleEnd>{SettleEnd::MaxTime, "max_time"}};
std::string_view settle_end_name(SettleEnd end);

struct SettleSample {
  double time = 0.0;            // s since the dynamics started
  double density = 0.0;         // from the probe; NaN without one or when it cannot measure
  DemSystem::KineticEnergy kinetic_energy;  // J, free particles
  double translational_per_particle_mgd = 0.0;  // the quiet criterion's measure: per free particle / mean m g d
  ContactStatistics contacts;
};

struct SettleResult {
  SettleEnd end = SettleEnd::MaxTime;
  double simulated_time = 0.0;  // s
  std::size_t steps = 0;
  SettleSample last;
};

// When a settling run will end, forecast from its samples so far. Once the bed has stopped
// collapsing, its kinetic energy decays about as a power of time, ever more slowly as the bed
// locks up: log energy fitted against log time over the later half of the time since its peak
// (at least five samples) gives when it falls below the threshold; the run then needs the
// quiet window on top. No forecast while the energy is not falling.
// The density condition is not forecast: it is usually met long before the energy one.
class QuietForecast {
 public:
  explicit QuietForecast(const QuietCriterion& criterion) : criterion_(criterion) {}
  void add(const SettleSample& sample);
  // Simulated time (s since the start) at which the run should end, at most max_time.
  [[nodiscard]] std::optional<double> expected_end() const;

 private:
  QuietCriterion criterion_;
  std::vector<double> time_, log_energy_;
  double last_loud_ = 0.0;  // last sample time above the energy threshold
};

using DensityProbe = std::function<double(const ParticleStore&)>;
using SampleSink = std::function<void(const SettleSample&)>;

// Sum of m g d over the system's free particles, J: the scale of the quiet criterion's energy.
double weight_energy(const DemSystem& system, const ParticleStore& particles);

// The system's state now (time since it was made, energies, contacts, the probe's density, or
// NaN without a probe), the energy per particle relative to `weight` (weight_energy above).
// InputError when the system has diverged (its kinetic energy is not finite).
SettleSample sample_system(const DemSystem& system, const ParticleStore& particles, double weight,
                           const DensityProbe& density);

// Runs the `steps_left` steps of a block (a sample interval, a tap) in slices of about a
// quarter of a second of wall clock, counting `steps_left` down and calling `between` after
// every slice but the last: a safe point inside the block, however long the block (a tap at
// 0.01 Hz is 50 s of simulated time), so a signal is honoured and a checkpoint is on time.
// A loop keeps `steps_left` in its saved state: resumed inside a block, it finishes it.
// Slicing does not change the result (DemSystem::run(a) then run(b) is run(a + b), bit for bit).
void run_block(DemSystem& system, std::size_t& steps_left, const std::function<void()>& between);

// What gravity, the insertion and the container can give a bed: spheres that started at most
// `height` above the floor, at most `speed` fast (the insertion, the container's peak speed),
// on a floor that moves at most `floor_travel` (a tap's amplitude).
struct EnergyBudget {
  double height = 0.0;        // m
  double speed = 0.0;         // m/s
  double floor_travel = 0.0;  // m
};
// Whether the bed has blown up (a time step beyond what the contacts resolve, an impact too
// fast for the stiffness): a number that is not finite, a kinetic energy ten times beyond
// what `budget` allows, or a free sphere whose centre went through the floor or a side wall.
// Returns what happened, in words; none for a sane bed. O(n): called once per sample.
std::optional<std::string> find_blow_up(const DemSystem& system, const ParticleStore& particles,
                                        const Container& container, const SettleSample& sample,
                                        const EnergyBudget& budget);

// A settling run's loop between two samples: with the system's state (DemSystem::save_state),
// all it takes to continue the run.
struct SettleLoop {
  double start = 0.0;               // s, the system's time when the run began
  std::size_t start_steps = 0;      // the system's steps then
  std::deque<SettleSample> window;  // the samples of the quiet window so far
  std::size_t block_steps_left = 0; // steps still to run before the next sample (0: at a sample)
};
// Called after every sample that does not end the run, and inside long blocks between samples:
// a safe point, where the caller may save the loop (with the system) for a checkpoint, or stop
// the run by throwing.
using SettleSafePoint = std::function<void(const SettleLoop&)>;

// Steps `system` until the criterion is met, sampling every sample_interval (the first
// sample is at the start). `density` measures the bed (the virtual boxes, in a run);
// `on_sample` sees every sample, for time series and progress. With `resume` (a loop saved
// at a safe point, the system restored to the same moment) the run continues from there, and
// ends as the uninterrupted run would have, bit for bit.
SettleResult settle(DemSystem& system, const ParticleStore& particles, const QuietCriterion& criterion,
                    const DensityProbe& density, const SampleSink& on_sample,
                    const SettleSafePoint& safe_point = {}, const SettleLoop* resume = nullptr);

}  // namespace aggpack
