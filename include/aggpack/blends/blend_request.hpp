#pragma once
// The blends asked of a set of material files, predicted: each material's betas by its route
// (a calibrated material by simulation, another by its lab number), CPM at the lab process's K,
// the lab route's curve beside a simulated one. `aggpack blend`, `aggpack sweep MATERIALS` and
// `aggpack predict MATERIALS` all answer through it.
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "aggpack/blends/blend_report.hpp"
#include "aggpack/blends/simulated_betas.hpp"
#include "aggpack/studies/reproduce.hpp"

namespace aggpack {

// The lab process a blend is predicted for: loose (or poured), rodded or vibrated, and its K.
// InputError naming `option` for another name.
TestProcess blend_process(const std::string& name, const std::string& option);

struct BlendRequest {
  std::vector<std::filesystem::path> materials;  // coarse first
  std::vector<double> sweep_percents;            // a sweep of the second material's volume percent; or
  std::vector<std::vector<double>> fractions;    // these blends' volume fractions (one material: {1})
  TestProcess process = {"rodded", 4.5};
  std::string route = "auto";  // auto (calibrated: simulation, else lab), lab or simulation
  SimulatedBetaOptions beds;   // the simulation route's beds (`material` is set per material)
  CpmInteraction interaction;  // de Larrard's unless asked otherwise
  // false (predict): the simulation route only from a warm cache, else the lab route, said in
  // the result's modelling; InputError when a material has neither.
  bool may_simulate = true;
};

// Every material file read, the route asked checked against it (a lab route needs a lab number),
// the blends checked: InputError before any bed runs.
void check_blend_request(const BlendRequest& request);

// The answer's curve (every material by its route), then the lab route's beside it when the
// answer simulated and every material has a lab number. The beds' progress and the caches'
// stories go to `log`.
BlendResult predict_blends(const BlendRequest& request, std::ostream& log);

// Two materials' curve by their lab numbers alone (nothing simulated), the fine from `from` to
// `to` percent in steps of 1, at `process`: the reproduce report's Table 2 section takes it.
MaterialsCurve lab_route_curve(const std::filesystem::path& coarse, const std::filesystem::path& fine,
                               const std::string& process, double from, double to);

}  // namespace aggpack
