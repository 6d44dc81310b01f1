#include "aggpack/dynamics/settle.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <limits>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"

namespace aggpack {

std::string_view settle_end_name(SettleEnd end) {
  return name_of(kSettleEndNames, end);
}

void QuietForecast::add(const SettleSample& sample) {
  const double e = sample.translational_per_particle_mgd;
  time_.push_back(sample.time);
  log_energy_.push_back(std::log(std::max(e, 1e-300)));
  if (e > criterion_.kinetic_fraction) last_loud_ = sample.time;
}

std::optional<double> QuietForecast::expected_end() const {
  if (time_.empty()) return std::nullopt;
  const double now = time_.back();
  const double threshold = std::log(criterion_.kinetic_fraction);
  // Already below: quiet once the window has passed since the last loud sample.
  if (log_energy_.back() <= threshold) return std::min(criterion_.max_time, std::max(now, last_loud_ + criterion_.window));
  // A power of time fitted over the later half of the time since the energy's peak: long
  // enough that a burst (an avalanche, a rattler) does not dominate, recent enough to follow
  // a decay that slows down as the bed locks up. (Examples 1 and 2: the time left shown is a
  // median 1.14 and 1.03 times the true one; an exponential fit gave about 0.5.)
  const std::size_t peak = static_cast<std::size_t>(
      std::max_element(log_energy_.begin(), log_energy_.end()) - log_energy_.begin());
  const double from = 0.5 * (time_[peak] + now);
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = peak; i < time_.size(); ++i) {
    if (time_[i] < from || !(time_[i] > 0.0)) continue;
    const double x = std::log(time_[i]), y = log_energy_[i];
    n += 1;
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  if (n < 5) return std::nullopt;
  const double denominator = n * sxx - sx * sx;
  if (!(denominator > 0)) return std::nullopt;
  const double slope = (n * sxy - sx * sy) / denominator;
  if (!(slope < 0)) return std::nullopt;
  const double intercept = (sy - slope * sx) / n;
  // exp of at most 700: a slope near zero would overflow to a forecast of infinity.
  const double crossing = std::max(now, std::exp(std::min(700.0, (threshold - intercept) / slope)));
  return std::min(criterion_.max_time, crossing + criterion_.window);
}

double weight_energy(const DemSystem& system, const ParticleStore& particles) {
  double weight = 0.0;
  const double g = norm(system.gravity());
  for (std::size_t i = 0; i < particles.size(); ++i)
    if (!system.is_frozen(i)) weight += particles.mass[i] * g * 2.0 * particles.radius[i];
  return weight;
}

SettleSample sample_system(const DemSystem& system, const ParticleStore& particles, double weight,
                           const DensityProbe& density) {
  SettleSample s;
  s.time = system.time();
  s.kinetic_energy = system.kinetic_energy();
  // A system that diverged has positions no analysis can take (they would be cast to cells).
  if (!std::isfinite(s.kinetic_energy.total()))
    throw InputError(fmt::format("the DEM diverged at {:.6g} s simulated (a kinetic energy of {} J): its time step is "
                                 "too large for its contacts, or it started from a state no run reaches",
                                 s.time, s.kinetic_energy.total()));
  s.density = density ? density(particles) : std::numeric_limits<double>::quiet_NaN();
  // Per particle over mean m g d: the free-particle count cancels.
  s.translational_per_particle_mgd = weight > 0.0 ? s.kinetic_energy.translational / weight : 0.0;
  s.contacts = system.contact_statistics();
  return s;
}

std::optional<std::string> find_blow_up(const DemSystem& system, const ParticleStore& particles,
                                        const Container& container, const SettleSample& sample,
                                        const EnergyBudget& budget) {
  const Box& b = container.bounds;
  double d_min = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (system.is_frozen(i)) continue;
    const Vec3& p = particles.position[i];
    d_min = std::min(d_min, 2.0 * particles.radius[i]);
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      return fmt::format("sphere {} has a position that is not a number", i);
    if (p.z < b.lo.z - budget.floor_travel)
      return fmt::format("sphere {} went through the floor (its centre at z = {:.4g} m, the floor at {:.4g} m)", i,
                         p.z, b.lo.z);
    if (!container.holds_horizontally(p))
      return fmt::format("sphere {} went through a side wall (its centre at x = {:.4g}, y = {:.4g} m)", i, p.x, p.y);
  }
  if (!std::isfinite(d_min)) return std::nullopt;  // nothing free to move
  // Per particle over m g d, as the sample's measure: falling `height` and starting at `speed`
  // gives at most (v^2 / 2 + g h) / (g d_min); ten times that (and ten diameters' fall) is no
  // longer a bed moved by gravity.
  const double g = norm(system.gravity());
  const double allowed =
      10.0 * (0.5 * budget.speed * budget.speed + g * budget.height) / (g * d_min) + 10.0;
  const double energy = sample.translational_per_particle_mgd;
  if (!(energy <= allowed))
    return fmt::format("its kinetic energy reached {:.3g} m g d per sphere, more than ten times what gravity, the "
                       "insertion and the container can give it ({:.3g})",
                       energy, allowed / 10.0);
  return std::nullopt;
}

void run_block(DemSystem& system, std::size_t& steps_left, const std::function<void()>& between) {
  using Clock = std::chrono::steady_clock;
  constexpr double kSliceSeconds = 0.25;
  std::size_t slice = 8;  // a first slice short enough for any bed, then sized by its wall clock
  while (steps_left > 0) {
    const std::size_t steps = std::min(slice, steps_left);
    const auto t0 = Clock::now();
    system.run(steps);
    steps_left -= steps;
    const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    const double per_step = std::max(seconds, 1e-9) / static_cast<double>(steps);
    slice = std::clamp<std::size_t>(static_cast<std::size_t>(kSliceSeconds / per_step), 1, 1u << 20);
    if (steps_left > 0 && between) between();
  }
}

SettleResult settle(DemSystem& system, const ParticleStore& particles, const QuietCriterion& criterion,
                    const DensityProbe& density, const SampleSink& on_sample, const SettleSafePoint& safe_point,
                    const SettleLoop* resume) {
  if (!(criterion.sample_interval > 0.0) || !(criterion.window >= criterion.sample_interval))
    throw InputError(fmt::format("quiet window {} s must be at least the sample interval {} s (> 0)",
                                 criterion.window, criterion.sample_interval));
  SettleResult result;
  const double weight = weight_energy(system, particles);
  const std::size_t free_particles = system.free_count();

  const std::size_t steps_per_sample = criterion.steps_per_sample(system.time_step());
  SettleLoop loop;
  if (resume) loop = *resume;
  else loop = {system.time(), system.steps(), {}};
  const double start = loop.start;
  std::deque<SettleSample>& window = loop.window;
  const auto take_sample = [&] {
    SettleSample s = sample_system(system, particles, weight, density);
    s.time = system.time() - start;
    if (on_sample) on_sample(s);
    return s;
  };
  const auto quiet = [&] {
    if (window.back().time - window.front().time < criterion.window * (1.0 - 1e-9)) return false;
    // A NaN density (no probe, or the boxes do not fit the bed yet) leaves the energy alone.
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const SettleSample& s : window) {
      if (s.translational_per_particle_mgd > criterion.kinetic_fraction) return false;
      if (std::isnan(s.density)) continue;
      lo = std::min(lo, s.density);
      hi = std::max(hi, s.density);
    }
    return !(hi - lo > criterion.density_tolerance);
  };

  if (!resume) {
    window.push_back(take_sample());
    if (safe_point) safe_point(loop);
  }
  while (true) {
    if (free_particles == 0) {
      result.end = SettleEnd::Quiet;
      break;
    }
    if (loop.block_steps_left == 0) {  // at a sample: end here, or start the next interval
      if (system.time() - start >= criterion.max_time * (1.0 - 1e-12)) {
        result.end = SettleEnd::MaxTime;
        break;
      }
      loop.block_steps_left = steps_per_sample;
    }
    run_block(system, loop.block_steps_left, [&] {
      if (safe_point) safe_point(loop);
    });
    window.push_back(take_sample());
    while (window.size() > 2 && window[1].time <= window.back().time - criterion.window * (1.0 - 1e-9))
      window.pop_front();
    if (quiet()) {
      result.end = SettleEnd::Quiet;
      break;
    }
    if (safe_point) safe_point(loop);
  }
  result.simulated_time = system.time() - start;
  result.steps = system.steps() - loop.start_steps;
  result.last = window.back();
  return result;
}

}  // namespace aggpack
