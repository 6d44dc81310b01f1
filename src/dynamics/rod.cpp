#include "aggpack/dynamics/rod.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <iterator>
#include <limits>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>

#include "rest_phase.hpp"

namespace aggpack {

std::string RoddingReport::csv() const {
  std::string body = "stroke,x_m,y_m,surface_m,tip_lowest_m,depth_m,peak_force_n,stopped_by_force\n";
  for (const RodStroke& s : stroke_records)
    fmt::format_to(std::back_inserter(body), "{},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{}\n", s.stroke, s.x, s.y,
                   s.surface, s.tip_lowest, s.depth, s.peak_force, s.stopped_by_force ? 1 : 0);
  return body;
}

double highest_top(const ParticleStore& particles, std::uint32_t below_layer) {
  double top = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < particles.size(); ++i)
    if (particles.layer[i] < below_layer) top = std::max(top, particles.position[i].z + particles.radius[i]);
  return top;
}

std::vector<Vec3> rod_stroke_positions(const Container& container, std::size_t count, double margin) {
  const Box& b = container.bounds;
  const double x0 = b.lo.x + margin, y0 = b.lo.y + margin, wx = b.hi.x - b.lo.x - 2.0 * margin,
               wy = b.hi.y - b.lo.y - 2.0 * margin;
  if (!(wx > 0.0 && wy > 0.0))
    throw std::invalid_argument(fmt::format("the container is too narrow for the rod and its clearance ({} m)", margin));
  // Inside: every side plane (every plane but the floor) at least `margin` away.
  const auto inside = [&](const Vec3& p) {
    for (unsigned w = 1; w < container.plane_count(); ++w) {
      Vec3 towards;
      if (container.plane_distance(w, p, towards) < margin * (1.0 - 1e-9)) return false;
    }
    return true;
  };
  const double z = b.lo.z + 0.5 * container.height();
  const bool rectangular = inside({x0, y0, z}) && inside({x0 + wx, y0, z}) && inside({x0, y0 + wy, z}) &&
                           inside({x0 + wx, y0 + wy, z});
  const double golden = 0.5 * (std::sqrt(5.0) - 1.0);  // 1 / phi
  std::vector<Vec3> points;
  points.reserve(count);
  for (std::size_t k = 0; k < count; ++k) {
    const double u = (static_cast<double>(k) + 0.5) / static_cast<double>(count);
    const double v = std::fmod((static_cast<double>(k) + 0.5) * golden, 1.0);
    if (rectangular) {
      points.push_back({x0 + wx * v, y0 + wy * u, 0.0});
      continue;
    }
    // Vogel's spiral over the ellipse inscribed in the inset bounds (a circle in a cylinder).
    const double radius = std::sqrt(u), angle = 2.0 * std::numbers::pi * golden * static_cast<double>(k);
    points.push_back({x0 + 0.5 * wx * (1.0 + radius * std::cos(angle)),
                      y0 + 0.5 * wy * (1.0 + radius * std::sin(angle)), 0.0});
  }
  return points;
}

double rod_target_tip(const RoddingSettings& settings, const RodTargets& targets, RodDepth& mode) {
  mode = settings.depth;
  if (mode == RodDepth::Auto) mode = targets.layer_below ? RodDepth::LayerBelow : RodDepth::Floor;
  if (mode == RodDepth::LayerBelow) {
    if (!targets.layer_below)
      throw std::invalid_argument("rodding into the layer below: the bed has no layer below its top one");
    return std::max(targets.floor + settings.floor_clearance, *targets.layer_below - settings.penetration);
  }
  return targets.floor + settings.floor_clearance;
}

RodLoop begin_rodding(const DemSystem& system, const Container& container, const RoddingSettings& settings,
                      const RodTargets& targets, double density_before) {
  RodLoop loop;
  loop.start = system.time();
  loop.start_steps = system.steps();
  loop.positions = rod_stroke_positions(container, settings.strokes, 0.5 * settings.rod_diameter + settings.wall_clearance);
  RoddingReport& report = loop.report;
  report.strokes = settings.strokes;
  report.rod_diameter = settings.rod_diameter;
  report.speed = settings.speed;
  report.target_tip = rod_target_tip(settings, targets, report.depth_mode);
  report.density_before = density_before;
  report.time_step = system.time_step();
  return loop;
}

bool fits(const RodLoop& loop, const RoddingSettings& settings, const DemSystem& system) {
  const RoddingReport& report = loop.report;
  const double dt = system.time_step();
  const bool moving = loop.phase != RodPhase::StrokeStart && loop.phase != RodPhase::Rest;
  const bool rod_in = loop.phase == RodPhase::Descend || loop.phase == RodPhase::Withdraw;
  return report.strokes == settings.strokes && report.rod_diameter == settings.rod_diameter &&
         report.speed == settings.speed && report.time_step == dt && loop.start >= 0.0 &&
         loop.start <= system.time() && loop.start_steps <= system.steps() && loop.stroke >= 1 &&
         loop.stroke <= settings.strokes && loop.positions.size() == settings.strokes &&
         static_cast<unsigned>(loop.phase) <= static_cast<unsigned>(RodPhase::Rest) &&
         (report.depth_mode == RodDepth::Floor || report.depth_mode == RodDepth::LayerBelow) &&
         report.stroke_records.size() == loop.stroke - (loop.phase == RodPhase::StrokeStart ? 1 : 0) &&
         rod_in == system.tool().has_value() && (moving || loop.steps_left == 0) && std::isfinite(loop.top) &&
         (loop.phase != RodPhase::Rest || loop.rest_end - system.time() <= settings.rest_time + dt) &&
         (!loop.quiet_since || std::isfinite(*loop.quiet_since));
}

namespace {

// The rod of stroke k, descending from above the bed's top to the target from now.
RodTool stroke_tool(const DemSystem& system, const ParticleStore& particles, const RoddingSettings& settings,
                    RodLoop& loop) {
  const double r = 0.5 * settings.rod_diameter;
  const Vec3& at = loop.positions[loop.stroke - 1];
  const double surface = highest_top(particles);
  loop.top = std::max(surface, loop.report.target_tip) + settings.start_gap + r;  // the tip's centre
  const double bottom = loop.report.target_tip + r;
  const double t0 = system.time();
  RodTool tool;
  tool.radius = r;
  tool.length = std::max(1.0, 4.0 * (loop.top - bottom));  // its upper end never reaches the bed
  tool.path = {{t0, {at.x, at.y, loop.top}}, {t0 + (loop.top - bottom) / settings.speed, {at.x, at.y, bottom}}};
  loop.report.stroke_records.push_back({loop.stroke, at.x, at.y, surface, loop.report.target_tip,
                                        surface - loop.report.target_tip, 0.0, false});
  return tool;
}

// Steps of the descent between two looks at the force: half a millimetre of the rod's travel.
std::size_t force_check_steps(const RoddingSettings& settings, double dt) {
  return std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(5e-4 / (settings.speed * dt))));
}

// The descent, a look at the force every force_check_steps; at its end (the target, or the
// bed's push beyond max_force) the rod is sent back up to where the stroke began.
void descend(DemSystem& system, const RoddingSettings& settings, RodLoop& loop, const std::function<void()>& safe_point) {
  const double dt = system.time_step();
  const std::size_t check = force_check_steps(settings, dt);
  RodStroke& record = loop.report.stroke_records.back();
  while (loop.steps_left > 0) {
    std::size_t chunk = std::min(check, loop.steps_left);
    loop.steps_left -= chunk;
    run_block(system, chunk, [] {});
    if (norm(system.tool_force()) > settings.max_force && loop.steps_left > 0) {
      record.stopped_by_force = true;
      loop.steps_left = 0;
    }
    if (loop.steps_left > 0) safe_point();
  }
  const Vec3 tip = system.tool_tip();
  record.tip_lowest = tip.z - 0.5 * settings.rod_diameter;
  record.depth = record.surface - record.tip_lowest;
  const double up = std::max(0.0, loop.top - tip.z) / settings.speed;
  system.redirect_tool({{system.time(), tip}, {system.time() + std::max(up, dt), {tip.x, tip.y, loop.top}}});
  // The withdrawal runs to the step after its end: the rod stands at the top again.
  loop.steps_left = static_cast<std::size_t>(std::ceil(std::max(up, dt) / dt)) + 1;
  loop.phase = RodPhase::Withdraw;
}

}  // namespace

void rod(DemSystem& system, const ParticleStore& particles, const RoddingSettings& settings,
         const QuietCriterion& quiet, RodLoop& loop, const TapHooks& hooks) {
  RoddingReport& report = loop.report;
  const double weight = weight_energy(system, particles);
  const double dt = system.time_step();
  const auto phase_name = [&] {
    return loop.phase == RodPhase::Rest ? std::string("rest after rodding")
                                        : fmt::format("rod stroke {} of {}", loop.stroke, settings.strokes);
  };
  const std::function<void()> safe_point = [&] { hooks.at_safe_point(phase_name()); };
  while (true) {
    if (loop.phase == RodPhase::StrokeStart) {
      RodTool tool = stroke_tool(system, particles, settings, loop);
      loop.steps_left = static_cast<std::size_t>(std::ceil((tool.path.back().time - system.time()) / dt));
      system.set_tool(std::move(tool));
      loop.phase = RodPhase::Descend;
      safe_point();
    } else if (loop.phase == RodPhase::Descend) {
      descend(system, settings, loop, safe_point);
      safe_point();
    } else if (loop.phase == RodPhase::Withdraw) {
      run_block(system, loop.steps_left, safe_point);
      report.stroke_records.back().peak_force = system.tool_peak_force();
      system.set_tool(std::nullopt);
      // Across to the next point, above the bed: the rod is out of the DEM meanwhile.
      const bool last = loop.stroke == settings.strokes;
      const double across = last ? 0.0 : norm(loop.positions[loop.stroke] - loop.positions[loop.stroke - 1]);
      loop.steps_left = static_cast<std::size_t>(std::llround(across / settings.speed / dt));
      loop.phase = RodPhase::Transit;
      safe_point();
    } else if (loop.phase == RodPhase::Transit) {
      run_block(system, loop.steps_left, safe_point);
      if (loop.stroke < settings.strokes) {
        ++loop.stroke;
        loop.phase = RodPhase::StrokeStart;
      } else {
        loop.phase = RodPhase::Rest;
        loop.rest_end = system.time() + settings.rest_time;
        loop.quiet_since.reset();
      }
      safe_point();
    } else {
      const auto sample = [&] {
        loop.last = sample_system(system, particles, weight, nullptr);
        loop.last.time -= loop.start;
        hooks.on_sample(loop.last, phase_name());
      };
      dynamics_internal::rest_bed(system, quiet, settings.rest_until_quiet,
                                  {loop.rest_end, loop.rest_steps_left, loop.quiet_since, loop.last}, sample,
                                  safe_point);
      break;
    }
  }
  report.density_after = hooks.density ? hooks.density(particles) : std::numeric_limits<double>::quiet_NaN();
  report.simulated_time = system.time() - loop.start;
  report.steps = system.steps() - loop.start_steps;
}

std::optional<double> layer_top(const ParticleStore& particles, std::uint32_t below_layer, double floor) {
  double sum = 0.0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < particles.size(); ++i)
    if (particles.layer[i] < below_layer) {
      sum += particles.position[i].z - floor;
      ++count;
    }
  if (count == 0) return std::nullopt;
  return floor + 2.0 * sum / static_cast<double>(count);
}

}  // namespace aggpack
