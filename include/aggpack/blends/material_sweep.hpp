#pragma once
// `aggpack sweep STONE.toml SAND.toml --fa 20:60:1 --check 30,40`: the blends of two materials
// predicted first (seconds, blend_request.hpp), the DEM of the blend run only at the points asked
// (blend_check.hpp); sweep.json, sweep.csv and sweep.svg say of every density whether it was
// simulated or predicted, and from which materials' calibration.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "aggpack/blends/blend_check.hpp"
#include "aggpack/blends/blend_request.hpp"

namespace aggpack {

struct MaterialSweepOptions {
  BlendRequest blend;                  // two materials and the sweep's percents (the second's)
  std::vector<double> check_percents;  // the DEM of the blend at these fine percents only (none: no DEM)
  double check_particles = 400;        // coarse particles in each check bed
  double check_cut = 0.0;              // m: the fine cut there in the check (0: none)
};

struct MaterialSweep {
  BlendResult predicted;
  std::optional<BlendCheck> check;
  std::vector<nlohmann::json> calibrations;  // each material's [calibration] as read (null: none)
};

// InputError before any bed for a check percent outside (0, 100) or anything check_blend_request
// refuses.
MaterialSweep sweep_materials(const MaterialSweepOptions& options, std::ostream& log);

// sweep.json: every point with its "source" ("predicted" or "simulated"), the route of its
// betas and the materials' calibrations; the densest predicted blend; the whole prediction and
// check beside them.
nlohmann::json to_json(const MaterialSweep& sweep);
// sweep.csv: one row a density, predicted or simulated.
std::string sweep_csv(const MaterialSweep& sweep);

}  // namespace aggpack
