#pragma once
#include <cstdint>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "aggpack/io/scenario.hpp"
#include "aggpack/studies/calibration.hpp"

namespace aggpack {

// `aggpack calibrate SCENARIO --dem --measured PHI`: the value of one contact parameter (a
// material's rolling friction, or its friction) for which the scenario's own protocol, run by
// the DEM over seeds 1..N, packs at the measured density (README, "Calibrating the grains").
// The density falls as either parameter rises, so the search is a bracketing one: both ends of
// the range, then regula falsi (Illinois) on the seed mean, each value run on the same seeds.
struct DemCalibrationOptions {
  CalibrationOptions runs;  // the scenario, its overrides, seeds, threads and quiet, as for calibrate
  double measured = 0.0;                             // the measured packing density of the scenario's bed
  std::vector<std::string> fit{"rolling_friction"};  // the parameters asked for: one measurement fixes one
  std::vector<std::string> materials;        // whose value is fitted; empty: the one material the bed is made of
  bool shared = false;                       // one value for every material of `materials`
  std::optional<std::vector<double>> range;  // [low, high] searched; default by parameter
  int max_evaluations = 6;  // values simulated, the range's two ends included
};

// A calibrated parameter's name in a scenario's material table.
[[nodiscard]] std::string material_key(const std::string& parameter);

// One value tried: the densities of its seeds.
struct DemEvaluation {
  double value = 0.0;
  SimulatedDensities density;
};

// A value where a monotone, noisy function of it crosses a target: the search of calibrate --dem.
struct CrossingSearch {
  std::vector<DemEvaluation> evaluations;  // in the order they ran
  double value = 0.0;                      // where the line between the last bracket's ends meets the target
  double band_low = 0.0, band_high = 0.0;  // the same at the target -+ one standard error of the bracket's means
  bool band_clipped = false;               // the band was cut at an end of the range
  bool converged = false;                  // a value's seed mean came within its standard error of the target
};
// Finds where `density(value)` (decreasing) equals `target` in [low, high] in at most
// `max_evaluations` calls. InputError when the target lies beyond what the range's ends give
// (beyond one standard error): no value in the range reaches it.
CrossingSearch find_crossing(const std::function<SimulatedDensities(double)>& density, double low, double high,
                             double target, int max_evaluations, const std::string& parameter);

struct DemCalibration {
  std::string scenario, protocol, parameter;
  std::vector<std::string> materials;  // fitted, one shared value
  double measured = 0.0;
  std::uint64_t seeds = 0;
  double range_low = 0.0, range_high = 0.0;
  CrossingSearch search;
  std::vector<std::string> assignments;  // the scenario keys the value sets, "key=value"
};

DemCalibration calibrate_dem(const DemCalibrationOptions& options, std::ostream& log);
// The calibration file's JSON (kind "aggpack DEM calibration", read by read_dem_calibration).
nlohmann::json to_json(const DemCalibration& calibration);
}  // namespace aggpack
