#pragma once
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "aggpack/core/option_names.hpp"
#include "aggpack/io/scenario.hpp"
#include "aggpack/models/packing_models.hpp"

namespace aggpack {

// The analytic models' parameters, each with where it came from.
struct ModelParameters {
  double compaction_index = 4.1;  // CPM's K
  std::string compaction_source;
  double beta = 0.72;             // CPM's residual packing density of every class (spheres)
  std::string beta_source;
  // The fine aggregate's classes of a blend, when they pack otherwise (a natural sand); none: beta.
  std::optional<double> beta_fine;
  std::string beta_fine_source;
};

// The parameters for a protocol until they are calibrated: K is de Larrard's value for the
// lab process nearest the protocol (poured, 4.1, for a deposition, a pour or a settling;
// vibrated, 4.75, once it taps), beta the value quoted for spheres, 0.72.
ModelParameters default_model_parameters(bool tapped);
// Whether a protocol has a tap step (what chooses the default K).
[[nodiscard]] bool protocol_taps(const Protocol& protocol);

// What the models say of one size distribution.
struct DistributionPrediction {
  std::string name;         // "simulated" or "whole_grading"
  std::string description;  // what the distribution is
  ModelDistribution classes;
  CpmResult cpm;
  RadiusMoments moments;
  double random_close_packing = 0.0;  // Desmond and Weeks
  // Furnas's limit for two classes: each size alone at CPM's monosized density.
  std::optional<double> furnas_at_mix, furnas_densest, furnas_densest_fine_fraction;
};

struct Predictions {
  ModelParameters parameters;
  std::vector<DistributionPrediction> distributions;
  // The grains' density, for the bulk density and voids beside each density (ASTM C29): the
  // scenario's material.density, or natural aggregate's 2650 kg/m3 for a grading alone.
  double particle_density = 2650.0;
  std::string particle_density_source = "natural aggregate, assumed (no scenario)";
};

// The models on a scenario's size distribution: the one it simulates (after its cut-offs; for a
// particle file the file's spheres, `file_diameters`) and, when a grading is cut, the whole
// grading. No simulation.
Predictions predict_scenario(const Scenario& scenario, const ModelParameters& parameters,
                             std::span<const double> file_diameters = {});
// The models on one distribution.
DistributionPrediction predict_distribution(std::string name, std::string description, ModelDistribution classes,
                                            const ModelParameters& parameters);

// `aggpack predict`: a scenario (its protocol chooses K, or its models.calibration gives K and
// beta), or a grading (a CSV file or a shipped
// grading's name) alone or blended with a fine one at a coarse/fine volume ratio (K for
// pouring); K, the process or beta given override those.
struct PredictRequest {
  std::string input;
  std::optional<std::string> fine;
  std::optional<double> ca_fa;
  std::optional<double> compaction_index;
  std::optional<std::string> process;
  std::optional<double> beta;
  std::optional<double> beta_fine;
  std::optional<std::filesystem::path> calibration;  // an aggpack calibrate file: K and beta
  ScenarioOverrides overrides;
  OptionStyle named = OptionStyle::Cli;  // the options in messages: the CLI's flags or Python's keywords
};
Predictions predict(const PredictRequest& request);

nlohmann::json to_json(const Predictions& predictions);
// The terminal's lines: one per distribution and model.
std::string describe(const Predictions& predictions);

// The grains' density of the scenario's particles, kg/m^3: [material]'s, or of several materials
// each component's weighted by its volume (a mix's by its coarse/fine ratio, size classes by
// their volume fractions or counts x d^3).
[[nodiscard]] double grains_density(const Scenario& scenario);

}  // namespace aggpack
