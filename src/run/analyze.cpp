#include "aggpack/run/analyze.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/spatial/multilevel_grid.hpp"

namespace aggpack {

namespace {
// An explicit box must lie in the container (for a packing file: the spheres' bounding box),
// or its density would count empty space beyond the packing as void.
void check_inside(const Box& box, const Container& container) {
  const Box& c = container.bounds;
  const double slack = 1e-9 * std::max({c.hi.x - c.lo.x, c.hi.y - c.lo.y, c.hi.z - c.lo.z});
  bool horizontal_ok = container.periodic || (box.lo.x >= c.lo.x - slack && box.hi.x <= c.hi.x + slack &&
                                              box.lo.y >= c.lo.y - slack && box.hi.y <= c.hi.y + slack);
  if (container.is_cylinder())  // each of its four vertical edges within the circle
    for (const double x : {box.lo.x, box.hi.x})
      for (const double y : {box.lo.y, box.hi.y}) {
        Vec3 outward;
        horizontal_ok = horizontal_ok &&
                        container.plane_distance(Container::kCylinderWall, {x, y, c.lo.z}, outward) >= -slack;
      }
  if (!horizontal_ok || box.lo.z < c.lo.z - slack || box.hi.z > c.hi.z + slack)
    throw InputError(fmt::format("the box {} does not lie inside the packing, which spans {}; give the box in the "
                                 "file's length unit (--length-unit) or with a unit on each number",
                                 box_text(box), box_text(c)));
}
}  // namespace

std::vector<Box> virtual_boxes(const Container& container, const BedGeometry& bed, const AnalysisRequest& request) {
  std::vector<Box> boxes = request.boxes;
  for (const Box& b : boxes) check_inside(b, container);
  for (double side : request.cube_sides) boxes.push_back(place_virtual_cube(side, container, bed));
  if (boxes.empty()) {
    const double horizontal = container.widest_centred_square(bed.d_max);
    const double largest = std::min(horizontal, bed.surface - bed.floor - 2.0 * bed.d_max);
    if (largest <= 0.0)
      throw InputError("the bed is too small for a virtual box that keeps one d_max from the walls, the floor "
                       "and the free surface; give a box explicitly");
    boxes.push_back(place_virtual_cube(largest, container, bed));
  }
  for (const Box& b : boxes)
    if (!(b.hi.x > b.lo.x && b.hi.y > b.lo.y && b.hi.z > b.lo.z))
      throw InputError("a box must have hi > lo on every axis");
  return boxes;
}

PackingReport analyze_packing(const ParticleStore& particles, const Container& container,
                              const AnalysisRequest& request) {
  if (particles.empty()) throw InputError("the packing has no particles to analyse");
  // Every array below is sized by the spheres' extent over their sizes: bounded first, so a
  // sphere far from the others is refused before any memory is taken (measure_bed's slices
  // are d_max thick, the profiles' d_max / 4 by default, the coordination's grid cells about
  // a sphere wide).
  double top = container.bounds.lo.z, d_max = 0.0;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    top = std::max(top, particles.position[i].z + particles.radius[i]);
    d_max = std::max(d_max, 2.0 * particles.radius[i]);
  }
  const double height = top - container.bounds.lo.z;
  const double slices_needed = height / std::min(d_max, request.slice_thickness.value_or(0.25 * d_max));
  if (!(slices_needed <= request.max_profile_bins))
    throw InputError(fmt::format("the spheres reach {:.4g} m above the floor, {:.3g} slices of the vertical profile "
                                 "({:.3g} m thick), more than the limit of {:.3g} (limits.max_profile_bins); expected "
                                 "a packing without a sphere far above the others, or a thicker slice",
                                 height, slices_needed, std::min(d_max, request.slice_thickness.value_or(0.25 * d_max)),
                                 request.max_profile_bins));
  const double cells = MultilevelGrid::cells_needed(container, particles.radius, container.bounds.volume(),
                                                    container.height());
  if (!(cells <= request.max_grid_cells))
    throw InputError(fmt::format("the spheres span {} but are at most {:.4g} m across: a neighbour grid over them "
                                 "would need {:.3g} cells, more than the limit of {:.3g} (limits.max_grid_cells); is a "
                                 "sphere far from the others, or the length unit wrong?",
                                 box_text(container.bounds), d_max, cells, request.max_grid_cells));
  PackingReport report;
  report.bed = measure_bed(particles, container);
  const BedGeometry& bed = report.bed;
  const std::vector<Box> boxes = virtual_boxes(container, bed, request);
  report.density = measure_density(particles, container, boxes);
  for (const BoxDensity& b : report.density.boxes)
    if (!(b.density > 0.0))
      throw InputError(fmt::format("the box {} holds no sphere (the packing spans {}): a density of 0 would mean "
                                   "nothing",
                                   box_text(b.box), box_text(container.bounds)));

  const auto largest = std::max_element(boxes.begin(), boxes.end(),
                                        [](const Box& a, const Box& b) { return a.volume() < b.volume(); });
  report.coordination = measure_coordination(particles, container, *largest, request.contact_tolerance);

  const double slice = request.slice_thickness.value_or(0.25 * bed.d_max);
  const double shell = request.shell_thickness.value_or(0.25 * bed.d_max);
  const double slices = (bed.top - bed.floor) / slice;
  const double shells = 0.5 * std::min(container.length_x(), container.length_y()) / shell;
  if (!(std::max(slices, shells) <= request.max_profile_bins))
    throw InputError(fmt::format("the profiles would need {:.3g} {} ({} {:.3g} m across {:.4g} m), more than the "
                                 "limit of {:.3g} (limits.max_profile_bins); expected a thicker slice or shell, or a "
                                 "packing without a sphere far from the others",
                                 std::max(slices, shells), slices >= shells ? "slices" : "shells",
                                 slices >= shells ? "slice thickness" : "shell thickness",
                                 slices >= shells ? slice : shell,
                                 slices >= shells ? bed.top - bed.floor : std::min(container.length_x(), container.length_y()),
                                 request.max_profile_bins));
  report.vertical = vertical_profile(particles, container, slice);
  report.wall_profile_z_lo = bed.floor + bed.d_max;
  report.wall_profile_z_hi = bed.surface - bed.d_max;
  report.wall = wall_distance_profile(particles, container, shell, report.wall_profile_z_lo, report.wall_profile_z_hi);
  if (container.is_cylinder()) report.measure = measure_content(particles, container);
  return report;
}

namespace {
nlohmann::json vec(const Vec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); }
}  // namespace

nlohmann::json to_json(const DensityResult& density) {
  nlohmann::json boxes = nlohmann::json::array();
  for (const auto& b : density.boxes)
    boxes.push_back({{"side_m", b.side}, {"lo", vec(b.box.lo)}, {"hi", vec(b.box.hi)}, {"density", b.density}});
  return {{"boxes", boxes}, {"mean", density.mean}, {"sd", density.sd}};
}

nlohmann::json to_json(const CoordinationResult& c) {
  return {{"mean", c.mean},
          {"particles_counted", c.particles_counted},
          {"histogram", c.histogram},
          {"relative_tolerance", c.relative_tolerance}};
}

nlohmann::json to_json(const PackingReport& r) {
  nlohmann::json j;
  j["density"] = to_json(r.density);
  j["bed"] = {{"floor_m", r.bed.floor}, {"surface_m", r.bed.surface}, {"top_m", r.bed.top},
              {"d_min_m", r.bed.d_min}, {"d_max_m", r.bed.d_max}};
  j["coordination"] = to_json(r.coordination);
  j["profiles"]["vertical"] = {{"z_m", r.vertical.position}, {"solid_fraction", r.vertical.solid_fraction}};
  j["profiles"]["wall_distance"] = {{"distance_m", r.wall.position},
                                    {"solid_fraction", r.wall.solid_fraction},
                                    {"z_range_m", {r.wall_profile_z_lo, r.wall_profile_z_hi}}};
  if (r.measure) j["measure"] = to_json(*r.measure);
  return j;
}

nlohmann::json to_json(const MeasureContent& m) {
  return {{"diameter_m", m.diameter},
          {"rim_m", m.rim},
          {"volume_m3", m.volume},
          {"particles", m.particles},
          {"particles_cut_by_rim", m.particles_cut},
          {"packing_density", m.packing_density},
          {"packing_density_whole_particles", m.packing_density_whole_particles},
          {"strike_off", "exact cut at the rim"}};
}

}  // namespace aggpack
