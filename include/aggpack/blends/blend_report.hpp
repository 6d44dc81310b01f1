#pragma once
// `aggpack blend`'s answer: the curve (or the points asked), the densest blend with its band, in
// the lab's units, as a table, JSON and a plot; every curve's route and modelling said.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "aggpack/blends/blend.hpp"
#include "aggpack/blends/blend_check.hpp"

namespace aggpack {

// One prediction of the blends asked: every material's betas by one route, and the points.
struct BlendCurve {
  std::string route;  // "simulation", "lab_test", or "mixed" (some materials each way)
  std::vector<MaterialBetas> materials;
  std::vector<BlendPoint> points;
  std::optional<DensestBlend> densest;  // a sweep's
};

struct BlendResult {
  TestProcess process;  // the lab process the blends are predicted for, and its K
  bool sweep = false;   // the points are a sweep of the second material's volume percent
  // The answer first; where the answer's route is the simulation and every material also has a
  // lab number, the lab route's curve second, beside it.
  std::vector<BlendCurve> curves;
  std::vector<std::string> modelling;  // the blend's own modelling choices
  double wall_clock_s = 0.0;
};

nlohmann::json to_json(const BlendResult& result);
// The console's table: one line a point (volume and mass percents, packing with its band,
// voids, bulk density), the densest blend and its bands, the routes.
std::string describe(const BlendResult& result);
// The packing against the second material's volume percent (a sweep), every curve, the
// densest marked; the lab route dashed; a check's simulated blends (seed mean and sd) as points.
std::string blend_svg(const BlendResult& result, const BlendCheck* check = nullptr);

}  // namespace aggpack
