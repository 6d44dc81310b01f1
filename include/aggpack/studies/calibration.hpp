#pragma once
#include <filesystem>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "aggpack/io/scenario.hpp"
#include "aggpack/run/calibration_file.hpp"
#include "aggpack/run/predictions.hpp"

namespace aggpack {

// `aggpack calibrate SCENARIO`: CPM's two parameters from aggpack's own simulations of the
// scenario's protocol (README, "Analytic packing models"). Two packings, each over seeds
// 1..N: the monosized bed of the scenario's coarsest class (the same protocol, container and
// solid volume) and the scenario's own mix. With K unknown, the monosized density gives
// beta(K) = phi_mono (1 + 1/K) (CPM's own relation for one class); the K for which CPM with
// that beta gives the mix's simulated density is the calibrated one. The band: the same
// solved at the densities' mean +- one standard error, both ways.
struct CalibrationOptions {
  std::filesystem::path scenario;
  ScenarioOverrides overrides;
  int seeds = 3;
  int threads = 0;
  bool quiet = false;
};

struct SimulatedDensities {
  std::string what;             // "monosized, d = ... m", "the scenario's mix"
  std::vector<double> density;  // per seed, the mean over the virtual boxes
  double mean = 0.0, standard_error = 0.0;
};

// The densities of seeds 1..N, their mean and the standard error of that mean (0 for one seed).
SimulatedDensities simulated_densities(std::string what, std::vector<double> densities);

struct Calibration {
  std::string scenario, protocol;  // the scenario file, its stages in order
  std::uint64_t seeds = 0;
  SimulatedDensities monosized, mix;
  double compaction_index = 0.0, compaction_low = 0.0, compaction_high = 0.0;
  double beta = 0.0, beta_low = 0.0, beta_high = 0.0;
};

// Solves for K and beta from the two densities (InputError when no K in [beta < 1, 1e4]
// gives the mix's density: the model cannot fit these simulations).
struct CalibratedParameters {
  double compaction_index = 0.0, beta = 0.0;
};
CalibratedParameters solve_calibration(const ModelDistribution& mix, double monosized_density, double mix_density);

Calibration calibrate(const CalibrationOptions& options, std::ostream& log);
nlohmann::json to_json(const Calibration& calibration);
}  // namespace aggpack
