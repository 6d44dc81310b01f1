#include "aggpack/dynamics/tap.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <numbers>

#include <fmt/format.h>

#include "rest_phase.hpp"

namespace aggpack {

std::string TapReport::csv() const {
  return dynamics_internal::compaction_curve_csv("tap", time_before, density_before, samples);
}

namespace {
double angular_frequency(const TappingSettings& settings) { return 2.0 * std::numbers::pi * settings.frequency; }
}  // namespace

double tap_amplitude(const TappingSettings& settings, double g) {
  const double omega = angular_frequency(settings);
  return settings.intensity * g / (omega * omega);
}

TapLoop begin_tapping(const DemSystem& system, const TappingSettings& settings, double density_before) {
  TapLoop loop;
  loop.start = system.time();
  loop.start_steps = system.steps();
  TapReport& report = loop.report;
  report.taps = settings.taps;
  report.intensity = settings.intensity;
  report.frequency = settings.frequency;
  report.amplitude = tap_amplitude(settings, norm(system.gravity()));
  report.rest_time = settings.rest_time;
  report.rest_until_quiet = settings.rest_until_quiet;
  report.time_step = system.time_step();
  report.density_before = density_before;
  return loop;
}

bool fits(const TapLoop& loop, const TappingSettings& settings, const DemSystem& system) {
  const TapReport& report = loop.report;
  const double dt = system.time_step(), until_rest_end = loop.rest_end - system.time();
  return report.taps == settings.taps && report.intensity == settings.intensity &&
         report.frequency == settings.frequency && report.rest_time == settings.rest_time &&
         report.rest_until_quiet == settings.rest_until_quiet && report.time_step == dt && loop.start >= 0.0 &&
         loop.start <= system.time() && loop.start_steps <= system.steps() && loop.tap >= 1 &&
         loop.tap <= settings.taps && report.samples.size() == loop.tap - 1 &&
         // Inside a tap (its steps still to run, at most one tap's), or in the rest after it.
         (loop.tap_steps_left > 0 ? static_cast<double>(loop.tap_steps_left) <= 0.5 / settings.frequency / dt + 2.0
                                  : until_rest_end >= -dt && until_rest_end <= settings.rest_time + dt) &&
         static_cast<double>(loop.rest_steps_left) <= settings.rest_time / dt + 2.0 &&
         (!loop.quiet_since || std::isfinite(*loop.quiet_since));
}

void tap(DemSystem& system, const ParticleStore& particles, const TappingSettings& settings,
         const QuietCriterion& quiet, TapLoop& loop, bool resumed, const TapHooks& hooks) {
  TapReport& report = loop.report;
  const double omega = angular_frequency(settings);
  const double weight = weight_energy(system, particles);
  const double dt = system.time_step();
  const std::size_t steps_per_sample = quiet.steps_per_sample(dt);
  // A sample of the rest (no density: it is measured once per tap).
  const auto sample = [&](std::string_view phase) {
    loop.last = sample_system(system, particles, weight, nullptr);
    loop.last.time -= loop.start;
    hooks.on_sample(loop.last, phase);
  };
  // A resumed tapping continues inside the tap, or in the rest, where it stopped.
  bool resuming = resumed;
  for (; loop.tap <= settings.taps; ++loop.tap) {
    const std::string phase = fmt::format("tap {} of {}", loop.tap, settings.taps);
    if (!resuming) {
      const ContainerMotion motion{system.time(), report.amplitude, omega, 0.5};
      system.set_container_motion(motion);
      // The tap runs to the step after its end, so the container is at rest again.
      loop.tap_steps_left = static_cast<std::size_t>(std::ceil((motion.end() - system.time()) / dt)) + 1;
    }
    if (!resuming || loop.tap_steps_left > 0) {
      run_block(system, loop.tap_steps_left, [&] { hooks.at_safe_point(phase); });
      loop.rest_end = system.time() + settings.rest_time;
      loop.quiet_since.reset();  // the first sample of the current quiet spell
      sample(phase);
      hooks.at_safe_point(phase);
    }
    resuming = false;
    while (loop.rest_steps_left > 0 || system.time() < loop.rest_end - 0.5 * dt) {
      if (loop.rest_steps_left == 0)
        loop.rest_steps_left =
            std::min(steps_per_sample, static_cast<std::size_t>(std::llround((loop.rest_end - system.time()) / dt)));
      run_block(system, loop.rest_steps_left, [&] { hooks.at_safe_point(phase); });
      sample(phase);
      if (settings.rest_until_quiet) {
        if (loop.last.translational_per_particle_mgd > quiet.kinetic_fraction) loop.quiet_since.reset();
        else if (!loop.quiet_since) loop.quiet_since = loop.last.time;
        if (loop.quiet_since && loop.last.time - *loop.quiet_since >= quiet.window) break;
      }
      hooks.at_safe_point(phase);
    }
    report.samples.push_back(
        {loop.tap, system.time() - loop.start, hooks.density(particles), loop.last.translational_per_particle_mgd});
  }
  report.simulated_time = system.time() - loop.start;
  report.steps = system.steps() - loop.start_steps;
}

}  // namespace aggpack
