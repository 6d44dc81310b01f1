// A bed made elsewhere, measured as a run's final bed is (aggpack analyze, the Python module).
#include "aggpack/run/analyze_bed.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "aggpack/analysis/density.hpp"
#include "aggpack/core/error.hpp"
#include "aggpack/core/version.hpp"
#include "aggpack/io/scenario.hpp"

namespace aggpack {

void check_box_count(const BedAnalysisOptions& options) {
  if (options.boxes.size() + options.cube_sides.size() > kMaxAnalysisBoxes)
    throw InputError(fmt::format("{}: {} boxes; expected at most {} (each is a pass over every sphere)",
                                 options.boxes_named, options.boxes.size() + options.cube_sides.size(),
                                 kMaxAnalysisBoxes));
}

BedAnalysis analyze_bed(const ParticleStore& particles, const BedAnalysisOptions& options, const std::string& name) {
  check_box_count(options);
  if (!(options.tolerance >= 0.0 && options.tolerance <= 1.0))
    throw InputError(fmt::format("{} {}: expected a relative tolerance from 0 to 1", options.tolerance_named,
                                 options.tolerance));
  if (!(options.overlap_tolerance >= 0.0 && options.overlap_tolerance <= 1.0))
    throw InputError(fmt::format("overlap tolerance {}: expected a fraction of the smaller radius from 0 to 1",
                                 options.overlap_tolerance));
  BedAnalysis analysis;
  analysis.container = bounding_container(particles);
  const RunLimits limits;  // the defaults: a bed without a scenario has none to raise them
  analysis.overlap = check_particle_overlaps(particles, analysis.container, options.overlap_tolerance,
                                             options.soft_contacts, name, limits.max_grid_cells);
  const auto [r_min, r_max] = std::minmax_element(particles.radius.begin(), particles.radius.end());
  if (!particles.empty() &&
      !(contact_reach_diameters(options.tolerance, *r_min, *r_max) <= kMaxContactReachDiameters))
    throw InputError(fmt::format(
        "{} {}: the smallest sphere of {} (radius {:.4g} m) would look for contacts {:.4g} of its diameters "
        "away; expected at most {:g}, a tolerance of at most {:.4g}",
        options.tolerance_named, options.tolerance, name, *r_min, contact_reach_diameters(options.tolerance, *r_min, *r_max),
        kMaxContactReachDiameters,
        options.tolerance * kMaxContactReachDiameters / contact_reach_diameters(options.tolerance, *r_min, *r_max)));
  AnalysisRequest request;
  request.contact_tolerance = options.tolerance;
  request.max_profile_bins = limits.max_profile_bins;
  request.max_grid_cells = limits.max_grid_cells;
  request.boxes = options.boxes;
  request.cube_sides = options.cube_sides;
  try {
    analysis.report = analyze_packing(particles, analysis.container, request);
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", name, e.what()));
  }
  return analysis;
}

nlohmann::json to_json(const BedAnalysis& analysis, std::size_t particle_count, bool soft_contacts) {
  nlohmann::json j = to_json(analysis.report);
  j["aggpack_version"] = kVersion;
  j["particle_count"] = particle_count;
  if (analysis.overlap.depth_over_radius > 1e-6) {
    j["largest_pair_overlap_rel"] = analysis.overlap.depth_over_radius;
    j["soft_contacts"] = soft_contacts;
  }
  const auto& cb = analysis.container.bounds;
  j["container"] = {{"lo", {cb.lo.x, cb.lo.y, cb.lo.z}}, {"hi", {cb.hi.x, cb.hi.y, cb.hi.z}}, {"periodic", false},
                    {"note", "bounding box of the spheres"}};
  return j;
}

}  // namespace aggpack
