#include "aggpack/dynamics/jig.hpp"

#include <cmath>
#include <iterator>
#include <string>

#include <fmt/format.h>

#include "rest_phase.hpp"

namespace aggpack {

std::string JigReport::csv() const {
  return dynamics_internal::compaction_curve_csv("drop", time_before, density_before, samples);
}

ContainerMotion jig_motion(const JiggingSettings& settings, double start, double g) {
  return ContainerMotion::lift_and_drop(start, settings.height, settings.lift_acceleration, g);
}

JigLoop begin_jigging(const DemSystem& system, const JiggingSettings& settings, double density_before) {
  JigLoop loop;
  loop.start = system.time();
  loop.start_steps = system.steps();
  JigReport& report = loop.report;
  report.drops = settings.drops;
  report.height = settings.height;
  report.lift_acceleration = settings.lift_acceleration;
  report.impact_speed = std::sqrt(2.0 * norm(system.gravity()) * settings.height);
  report.rest_time = settings.rest_time;
  report.rest_until_quiet = settings.rest_until_quiet;
  report.time_step = system.time_step();
  report.density_before = density_before;
  return loop;
}

bool fits(const JigLoop& loop, const JiggingSettings& settings, const DemSystem& system) {
  const JigReport& report = loop.report;
  const double dt = system.time_step(), until_rest_end = loop.rest_end - system.time();
  const ContainerMotion motion = jig_motion(settings, 0.0, norm(system.gravity()));
  return report.drops == settings.drops && report.height == settings.height &&
         report.lift_acceleration == settings.lift_acceleration && report.rest_time == settings.rest_time &&
         report.rest_until_quiet == settings.rest_until_quiet && report.time_step == dt && loop.start >= 0.0 &&
         loop.start <= system.time() && loop.start_steps <= system.steps() && loop.drop >= 1 &&
         loop.drop <= settings.drops && report.samples.size() == loop.drop - 1 &&
         (loop.drop_steps_left > 0 ? static_cast<double>(loop.drop_steps_left) <= motion.end() / dt + 2.0
                                   : until_rest_end >= -dt && until_rest_end <= settings.rest_time + dt) &&
         static_cast<double>(loop.rest_steps_left) <= settings.rest_time / dt + 2.0 &&
         (!loop.quiet_since || std::isfinite(*loop.quiet_since));
}

void jig(DemSystem& system, const ParticleStore& particles, const JiggingSettings& settings,
         const QuietCriterion& quiet, JigLoop& loop, bool resumed, const TapHooks& hooks) {
  JigReport& report = loop.report;
  const double weight = weight_energy(system, particles);
  const double dt = system.time_step(), g = norm(system.gravity());
  bool resuming = resumed;
  for (; loop.drop <= settings.drops; ++loop.drop) {
    const std::string phase = fmt::format("jig drop {} of {}", loop.drop, settings.drops);
    const auto safe_point = [&] { hooks.at_safe_point(phase); };
    const auto sample = [&] {
      loop.last = sample_system(system, particles, weight, nullptr);
      loop.last.time -= loop.start;
      hooks.on_sample(loop.last, phase);
    };
    if (!resuming) {
      const ContainerMotion motion = jig_motion(settings, system.time(), g);
      system.set_container_motion(motion);
      // The drop runs to the step after its end: the container stands on its base again.
      loop.drop_steps_left = static_cast<std::size_t>(std::ceil((motion.end() - system.time()) / dt)) + 1;
    }
    if (!resuming || loop.drop_steps_left > 0) {
      run_block(system, loop.drop_steps_left, safe_point);
      loop.rest_end = system.time() + settings.rest_time;
      loop.quiet_since.reset();
      sample();
      safe_point();
    }
    resuming = false;
    dynamics_internal::rest_bed(system, quiet, settings.rest_until_quiet,
                                {loop.rest_end, loop.rest_steps_left, loop.quiet_since, loop.last}, sample, safe_point);
    report.samples.push_back(
        {loop.drop, system.time() - loop.start, hooks.density(particles), loop.last.translational_per_particle_mgd});
  }
  report.simulated_time = system.time() - loop.start;
  report.steps = system.steps() - loop.start_steps;
}

}  // namespace aggpack
