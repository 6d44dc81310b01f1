#pragma once
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "aggpack/core/box.hpp"
#include "aggpack/core/container.hpp"
#include "aggpack/core/particle_store.hpp"
#include "aggpack/io/particle_file.hpp"
#include "aggpack/io/scenario.hpp"
#include "aggpack/run/analyze.hpp"

namespace aggpack {

// `aggpack analyze` on a bed made elsewhere (a file, or the Python module's arrays): its
// container is the spheres' bounding box, overlaps are checked as a particle file's are, and
// the analysis is the run's.
struct BedAnalysisOptions {
  std::vector<Box> boxes;          // m
  std::vector<double> cube_sides;  // m
  double tolerance = 1e-6;         // relative contact tolerance of the coordination
  double overlap_tolerance = ParticleSource{}.overlap_tolerance;
  bool soft_contacts = false;      // a soft-contact DEM's bed: any overlap short of a centre inside
  // What the caller calls the boxes and the tolerance, in messages ("--box, --cube", "--tolerance").
  std::string boxes_named = "boxes, cubes";
  std::string tolerance_named = "tolerance";
};

struct BedAnalysis {
  PackingReport report;
  Container container;  // the spheres' bounding box, walls
  PairOverlap overlap;  // the deepest pair's
};

// At most kMaxAnalysisBoxes boxes and cubes, else InputError (checkable before a bed is read).
void check_box_count(const BedAnalysisOptions& options);

// Throws InputError naming `name` (the file, or what the bed is) for bad options or a bed the
// analysis cannot measure.
BedAnalysis analyze_bed(const ParticleStore& particles, const BedAnalysisOptions& options, const std::string& name);

// What `aggpack analyze --json` prints, but the file's own keys (file, format).
nlohmann::json to_json(const BedAnalysis& analysis, std::size_t particle_count, bool soft_contacts);

}  // namespace aggpack
