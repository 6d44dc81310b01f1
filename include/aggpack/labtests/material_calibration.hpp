#pragma once
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "aggpack/labtests/lab_test.hpp"
#include "aggpack/studies/dem_calibration.hpp"

namespace aggpack {

// `aggpack calibrate MATERIAL --test c29 --method rodding` (README, "Calibrating a material on
// its lab test"): the material's free contact parameter fitted so that the simulated test gives
// the lab's number the material file records ([lab.c29] or [lab.c1252], the same method), by
// the search of calibrate --dem (both ends of the range, then regula falsi on the seeds' mean).
struct MaterialCalibrationOptions {
  LabTestOptions test;                       // the material file, the test and method, seeds, threads
  std::string parameter;                     // "friction" or "rolling_friction"; empty: rolling_friction for
                                             // spheres (standing in for shape), friction for grains
  std::optional<std::vector<double>> range;  // [low, high]; default by parameter, as calibrate --dem
  int max_evaluations = 6;
};

struct MaterialCalibration {
  LabTestPlan plan;
  std::string parameter;           // fitted
  std::string key;                 // the material file's key it sets: "contact.<key>"
  double lab_value = 0.0;          // kg/m3 (C29) or % (C1252)
  double target_packing = 0.0;     // what the lab value is as a packing fraction
  std::uint64_t seeds = 0;
  double range_low = 0.0, range_high = 0.0;
  CrossingSearch search;
};

MaterialCalibration calibrate_material(const MaterialCalibrationOptions& options, std::ostream& log);
nlohmann::json to_json(const MaterialCalibration& calibration);

// The calibrated material file: the original text (its comments kept) without an earlier
// [calibration] table, and a [calibration] table after it whose `contact` values replace the
// [contact] table's (load_material_file applies them) and which records the fit.
std::string calibrated_material_text(const MaterialCalibration& calibration, std::string_view original_text);

}  // namespace aggpack
