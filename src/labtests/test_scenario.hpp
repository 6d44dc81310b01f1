#pragma once
// Private to labtests: a test's scenario text, from the material and the standard's numbers.
#include <toml++/toml.h>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "aggpack/io/material_file.hpp"
#include "aggpack/labtests/lab_test.hpp"
#include "aggpack/labtests/standards.hpp"

namespace aggpack {

// The pieces every test's scenario is written with.
std::string metres(double m);  // "0.0125 m": every digit a double needs
// The material file's table `key` (none: an empty table), its `file` made absolute.
toml::table material_table(const std::filesystem::path& material_file, const std::string& key);
// [material]: the aggregate's oven-dry particle density and the material file's contact keys (a
// reduced Young's modulus when it gives none, said in `modelling`).
toml::table material_keys(const AggregateMaterial& m, std::vector<std::string>& modelling);
toml::table step(std::string kind);
toml::table layer_step(std::string kind, int layer, int layers);
// The header: what the file is and every modelling choice, as TOML comments.
std::string header(const std::string& title, const std::vector<std::string>& modelling);
[[nodiscard]] double impact_speed(double height);  // of a free fall from `height`
std::string text_of(const toml::table& root);

// The packing the lab measured for this test (the amount to generate), or a typical one.
[[nodiscard]] double expected_packing(const AggregateMaterial& m, LabTestKind test);

// The material's grains' own solid over the generator's count of it, each particle the sphere
// of its size (pi/6 I^3, I the sieve size): the mean over its library of templates; 1 for
// spheres. The amount generated is divided by it, so that the measure fills.
[[nodiscard]] double grain_volume_ratio(const AggregateMaterial& m);

// The cylinder a test simulates: the standard's measure, or a smaller one of the same
// proportions (a representative measure) where the standard's would hold too many particles.
struct SimulatedMeasure {
  double diameter_m = 0.0, rim_m = 0.0;
  double largest_size_m = 0.0;      // of the particles it holds: the overfill and the collar hold a few of them
  double grain_volume_ratio = 1.0;  // of the material's grains (grain_volume_ratio)
};

struct C29Setup {
  const AggregateMaterial* material = nullptr;
  C29Method method = C29Method::Rodding;
  Measure measure;             // the standard's
  SimulatedMeasure simulated;  // the cylinder run
  double cut_off_m = 0.0;  // finer material not generated
  double expected_packing = 0.6;
  double max_time_s = 2.0;  // each DEM step's budget of simulated time
};
// The scenario's text; `modelling` gets the choices it makes (also written as its comments).
std::string c29_scenario(const C29Setup& setup, std::vector<std::string>& modelling);

struct C1252Setup {
  const AggregateMaterial* material = nullptr;
  std::string label;                      // "A", "B, 1.18-2.36 mm", "C"
  std::optional<Grading> standard_grading;  // A and B: the standard's sample; C: none (the material's, < 4.75 mm)
  SimulatedMeasure simulated;               // the cylinder run
  double cut_off_m = 0.0;
  double expected_packing = 0.57;
  double max_time_s = 2.0;
};
std::string c1252_scenario(const C1252Setup& setup, std::vector<std::string>& modelling);

}  // namespace aggpack
