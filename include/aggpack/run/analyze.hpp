#pragma once
#include <cstddef>
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "aggpack/analysis/coordination.hpp"
#include "aggpack/analysis/density.hpp"
#include "aggpack/analysis/measure.hpp"

namespace aggpack {

// The most boxes (explicit and cubes) one analysis measures: each is a pass over every sphere,
// at every analysis of a run and at every density check of its DEM.
inline constexpr std::size_t kMaxAnalysisBoxes = 100;

// How far, in its own diameters, the smallest sphere may look for contacts: the coordination's
// neighbour search reaches r (1 + tolerance) + r_max tolerance from each sphere and scans the
// cube of cells (about a small sphere wide) within that reach.
inline constexpr double kMaxContactReachDiameters = 4.0;
// The contact tolerance's reach beyond the smallest sphere (radius r_min), in its diameters.
[[nodiscard]] inline double contact_reach_diameters(double tolerance, double r_min, double r_max) {
  return tolerance * (r_min + r_max) / (2.0 * r_min);
}

// What to measure in a packing. Boxes are explicit; cube sides are placed as in
// method.md (centred, clear of walls, floor and free surface). With neither, one cube
// of the largest admissible side is used.
struct AnalysisRequest {
  std::vector<double> cube_sides;  // m
  std::vector<Box> boxes;
  double contact_tolerance = 1e-6;
  std::optional<double> slice_thickness;  // m, default d_max / 4
  std::optional<double> shell_thickness;  // m, default d_max / 4
  double max_profile_bins = 1e6;           // more slices or shells than this are refused
  double max_grid_cells = 67108864;        // of the coordination's neighbour grid (limits.max_grid_cells)
};

struct PackingReport {
  BedGeometry bed;
  DensityResult density;
  CoordinationResult coordination;  // in the largest box
  Profile vertical;                 // solid fraction vs height
  Profile wall;                     // solid fraction vs distance from the side walls
  double wall_profile_z_lo = 0.0, wall_profile_z_hi = 0.0;
  std::optional<MeasureContent> measure;  // a cylinder's content below its rim
};

// The boxes of a request placed in a bed. Throws InputError when a cube does not fit.
std::vector<Box> virtual_boxes(const Container& container, const BedGeometry& bed, const AnalysisRequest& request);

// Throws InputError when a cube does not fit in the bed.
PackingReport analyze_packing(const ParticleStore& particles, const Container& container,
                              const AnalysisRequest& request);

nlohmann::json to_json(const DensityResult& density);
nlohmann::json to_json(const CoordinationResult& coordination);
nlohmann::json to_json(const PackingReport& report);
// summary.json's "measure": the content of a cylindrical measure, struck off at its rim.
nlohmann::json to_json(const MeasureContent& measure);

}  // namespace aggpack
