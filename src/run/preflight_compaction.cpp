// The checks of rodding and jigging that can be made before any work.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <variant>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/dynamics/rod.hpp"
#include "aggpack/run/preflight.hpp"

namespace aggpack {

namespace {
// The most a driven body may move in one time step, relative to the smallest radius.
constexpr double kMostTravelPerStep = 0.1;
}  // namespace

void check_compaction(const Scenario& sc, double time_step, double smallest_radius) {
  const std::string file = sc.file.string();
  const double most_speed = kMostTravelPerStep * smallest_radius / time_step;
  if (sc.rodding) {
    const RoddingSettings& r = *sc.rodding;
    try {
      (void)rod_stroke_positions(sc.container, r.strokes, 0.5 * r.rod_diameter + r.wall_clearance);
    } catch (const std::invalid_argument&) {
      throw InputError(fmt::format("{}: rodding.rod_diameter, rodding.wall_clearance: a rod of {:g} m with {:g} m "
                                   "from the walls does not fit the container's section; expected a narrower rod "
                                   "or a wider container",
                                   file, r.rod_diameter, r.wall_clearance));
    }
    if (!(r.speed <= most_speed))
      throw InputError(fmt::format("{}: rodding.speed: {:g} m/s moves the rod more than {:g} of the smallest radius "
                                   "({:.3g} m) in a time step of {:.3g} s; expected at most {:.3g} m/s",
                                   file, r.speed, kMostTravelPerStep, smallest_radius, time_step, most_speed));
  }
  if (sc.jigging) {
    const JiggingSettings& j = *sc.jigging;
    const double g = norm(sc.dynamics->dem.gravity);
    if (!(j.lift_acceleration < g))
      throw InputError(fmt::format("{}: jigging.lift_acceleration: {:g} m/s^2 is not below g ({:g} m/s^2): the bed "
                                   "would leave the floor as the lift slows; expected less",
                                   file, j.lift_acceleration, g));
    const double impact = std::sqrt(2.0 * g * j.height);
    if (!(impact <= most_speed))
      throw InputError(fmt::format("{}: jigging.height: a drop of {:g} m meets the base at {:.3g} m/s, more than {:g} "
                                   "of the smallest radius ({:.3g} m) per time step of {:.3g} s; expected a height of "
                                   "at most {:.3g} m or a shorter time step",
                                   file, j.height, impact, kMostTravelPerStep, smallest_radius, time_step,
                                   most_speed * most_speed / (2.0 * g)));
  }
}

double compaction_samples(const Scenario& sc, const Step& step, double every) {
  if (std::holds_alternative<RodStep>(step.kind)) return sc.rodding->rest_time / every + 2.0;
  if (std::holds_alternative<JigStep>(step.kind))
    return static_cast<double>(sc.jigging->drops) * (sc.jigging->rest_time / every + 2.0);
  return 0.0;
}

double compaction_time(const Scenario& sc, const Step& step) {
  if (std::holds_alternative<RodStep>(step.kind)) {
    // Each stroke down and up at most the container's height, and across it.
    const RoddingSettings& r = *sc.rodding;
    const double travel = 2.0 * sc.container.height() + std::hypot(sc.container.length_x(), sc.container.length_y());
    return static_cast<double>(r.strokes) * travel / r.speed + r.rest_time;
  }
  if (std::holds_alternative<JigStep>(step.kind)) {
    const JiggingSettings& j = *sc.jigging;
    const ContainerMotion drop = ContainerMotion::lift_and_drop(0.0, j.height, j.lift_acceleration,
                                                                norm(sc.dynamics->dem.gravity));
    return static_cast<double>(j.drops) * (drop.end() + j.rest_time);
  }
  return 0.0;
}

}  // namespace aggpack
