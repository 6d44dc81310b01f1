#include "aggpack/run/predictions.hpp"

#include <cmath>
#include <algorithm>
#include <filesystem>
#include <variant>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "aggpack/analysis/bulk_density.hpp"
#include "aggpack/core/error.hpp"
#include "aggpack/io/particle_file.hpp"
#include "aggpack/run/calibration_file.hpp"
#include "aggpack/run/grading_report.hpp"
#include "aggpack/run/protocol.hpp"

namespace aggpack {

ModelParameters default_model_parameters(bool taps) {
  ModelParameters p;
  p.compaction_index = *compaction_index_of(taps ? "vibrated" : "poured");
  p.compaction_source =
      taps ? "de Larrard's K for vibration (4.75), the lab process nearest a tapped protocol; not calibrated"
           : "de Larrard's K for pouring (4.1), the lab process nearest a deposited, poured or settled bed; not "
             "calibrated";
  p.beta = 0.72;
  p.beta_source = "the residual packing density of spheres quoted for the CPM (about 0.72); not calibrated";
  return p;
}

bool protocol_taps(const Protocol& protocol) {
  return std::any_of(protocol.steps.begin(), protocol.steps.end(),
                     [](const Step& s) { return std::holds_alternative<TapStep>(s.kind); });
}

DistributionPrediction predict_distribution(std::string name, std::string description, ModelDistribution classes,
                                            const ModelParameters& parameters) {
  DistributionPrediction d;
  d.name = std::move(name);
  d.description = std::move(description);
  d.classes = std::move(classes);
  std::vector<double> beta;
  for (const ModelClass& c : d.classes.classes)
    beta.push_back(c.fine && parameters.beta_fine ? *parameters.beta_fine : parameters.beta);
  d.cpm = cpm(d.classes, beta, parameters.compaction_index);
  d.moments = radius_moments(d.classes);
  d.random_close_packing = desmond_weeks_rcp(d.moments);
  if (d.classes.classes.size() == 2) {
    const double coarse = beta[0] / (1.0 + 1.0 / parameters.compaction_index);
    const double fine = beta[1] / (1.0 + 1.0 / parameters.compaction_index);
    d.furnas_at_mix = furnas_binary(coarse, fine, d.classes.classes[1].volume_fraction);
    d.furnas_densest = furnas_densest(coarse, fine);
    d.furnas_densest_fine_fraction = furnas_densest_fine_fraction(coarse, fine);
  }
  return d;
}

namespace {
// A grading's classes between its cut-offs (none: the whole curve).
ModelDistribution source_classes(const GradingSource& g, bool whole) {
  return whole ? grading_classes(g.grading) : grading_classes(g.grading, g.d_min, g.d_max);
}

}  // namespace

double grains_density(const Scenario& sc) {
  if (material_count(sc) == 1) return sc.material.density;
  const ParticleSource& p = sc.particles;
  const auto density = [&](std::size_t component) { return material_of(sc, p.material_of_component(component)).density; };
  if (p.graded && p.graded->fine) return (p.graded->ca_fa * density(0) + density(1)) / (p.graded->ca_fa + 1.0);
  if (!p.sizes) return density(0);
  double weighted = 0.0, total = 0.0;
  for (std::size_t k = 0; k < p.sizes->classes.size(); ++k) {
    const SizeClass& c = p.sizes->classes[k];
    const double volume =
        c.volume_fraction ? *c.volume_fraction : static_cast<double>(c.count.value_or(0)) * std::pow(c.diameter, 3);
    weighted += volume * density(k);
    total += volume;
  }
  return total > 0.0 ? weighted / total : density(0);
}

Predictions predict_scenario(const Scenario& sc, const ModelParameters& parameters,
                             std::span<const double> file_diameters) {
  Predictions out;
  out.parameters = parameters;
  out.particle_density = grains_density(sc);
  out.particle_density_source = material_count(sc) == 1 ? "the scenario's material.density"
                                                        : "the components' materials, weighted by volume";
  const ParticleSource& p = sc.particles;
  if (p.sizes) {
    const std::vector<std::size_t> counts = class_counts(*p.sizes);
    std::vector<double> diameters;
    for (std::size_t k = 0; k < counts.size(); ++k) diameters.insert(diameters.end(), counts[k], p.sizes->classes[k].diameter);
    out.distributions.push_back(predict_distribution("simulated", "the scenario's size classes",
                                                     diameter_classes(diameters), parameters));
  } else if (p.graded) {
    const GradedParticles& g = *p.graded;
    const auto classes = [&](bool whole) {
      return g.fine ? blend(source_classes(g.main, whole), source_classes(*g.fine, whole), g.ca_fa)
                    : source_classes(g.main, whole);
    };
    const bool cut = g.main.d_min || g.main.d_max || (g.fine && (g.fine->d_min || g.fine->d_max));
    out.distributions.push_back(predict_distribution(
        "simulated", cut ? "the scenario's grading between its cut-offs, as simulated" : "the scenario's grading",
        classes(false), parameters));
    // Without a d_min the simulation leaves out what passes the smallest sieve: the whole curve keeps it.
    out.distributions.push_back(predict_distribution(
        "whole_grading", "the whole grading: no cut-off, what passes the smallest sieve included", classes(true),
        parameters));
  } else if (!file_diameters.empty()) {
    out.distributions.push_back(predict_distribution("simulated", "the particle file's spheres",
                                                     diameter_classes(file_diameters), parameters));
  }
  return out;
}

namespace {

// The request's own values, before any file is read: each named as the caller gave it.
void check_request(const PredictRequest& r) {
  const auto named = [&](std::string_view flag) { return option_name(flag, r.named); };
  const auto given = [&](std::string_view flag, double value) {
    return option_given(flag, fmt::format("{:g}", value), r.named);
  };
  if (r.fine.has_value() != r.ca_fa.has_value())
    throw InputError(fmt::format("{} and {} go together: the fine grading and the coarse/fine volume ratio of the "
                                 "blend (for example {}), which has no default",
                                 named("--mix"), named("--ca-fa"), option_given("--ca-fa", "1.52", r.named)));
  if (r.ca_fa && !(*r.ca_fa > 0.0 && std::isfinite(*r.ca_fa)))
    throw InputError(fmt::format("{}: expected a number above 0", given("--ca-fa", *r.ca_fa)));
  if (r.compaction_index && r.process)
    throw InputError(fmt::format("{} and {} both give the compaction index; give one", named("--k"), named("--process")));
  if (r.calibration && (r.compaction_index || r.process || r.beta || r.beta_fine))
    throw InputError(fmt::format("{} gives K and beta; give it alone, or {} (or {}) and {} (and {})",
                                 named("--calibration"), named("--k"), named("--process"), named("--beta"),
                                 named("--beta-fine")));
  if (r.compaction_index && !(*r.compaction_index > 0.0))
    throw InputError(fmt::format("{}: expected a positive compaction index (4.1 poured ... 9 vibrated and "
                                 "compressed)",
                                 given("--k", *r.compaction_index)));
  if (r.beta && !(*r.beta > 0.0 && *r.beta < 1.0))
    throw InputError(fmt::format("{}: expected a residual packing density between 0 and 1", given("--beta", *r.beta)));
  if (r.beta_fine && !(*r.beta_fine > 0.0 && *r.beta_fine < 1.0))
    throw InputError(fmt::format("{}: expected a residual packing density between 0 and 1",
                                 given("--beta-fine", *r.beta_fine)));
}

}  // namespace

Predictions predict(const PredictRequest& r) {
  check_request(r);
  const auto named = [&](std::string_view flag) { return option_name(flag, r.named); };
  std::optional<double> process_k;
  if (r.process) {
    process_k = compaction_index_of(*r.process);
    if (!process_k)
      throw InputError(fmt::format("{}: expected poured, rodded, vibrated or vibrated_compressed",
                                   option_given("--process", *r.process, r.named)));
  }
  const bool scenario = r.input.ends_with(".toml");
  std::optional<Scenario> sc;
  bool tapped = false;
  if (scenario) {
    if (r.fine)
      throw InputError(fmt::format("{} applies to a grading; a scenario gives its own blend", named("--mix")));
    sc = load_scenario(r.input, r.overrides);
    tapped = protocol_taps(scenario_protocol(*sc));
  }
  ModelParameters parameters = default_model_parameters(tapped);
  if (sc && sc->models_calibration) parameters = read_calibration(*sc->models_calibration);
  if (r.calibration) parameters = read_calibration(*r.calibration);
  if (r.compaction_index) parameters.compaction_index = *r.compaction_index, parameters.compaction_source = "--k";
  if (process_k)
    parameters.compaction_index = *process_k,
    parameters.compaction_source = fmt::format("de Larrard's K for the process \"{}\" (--process)", *r.process);
  if (r.beta) parameters.beta = *r.beta, parameters.beta_source = "--beta";
  if (r.beta_fine) parameters.beta_fine = *r.beta_fine, parameters.beta_fine_source = "--beta-fine";
  const bool blended = r.fine || (sc && sc->particles.graded && sc->particles.graded->fine);
  if (r.beta_fine && !blended)
    throw InputError(fmt::format("{} applies to a blend's fine aggregate: give {} and {}, or a scenario with a "
                                 "coarse/fine mix",
                                 named("--beta-fine"), named("--mix"), named("--ca-fa")));
  if (sc) {
    if (!sc->particles.file) return predict_scenario(*sc, parameters);
    if (sc->particles.bed_from_caller())
      throw InputError(fmt::format("{}: particles.from = \"-\": the bed is given by the library's caller at run "
                                   "time, so there is no distribution to predict from here; predict from the run's "
                                   "report (its predictions), or name a particle file",
                                   sc->file.string()));
    // The file's spheres are the distribution, as in the run's summary.
    const auto max_bytes = sc->limits.max_input_bytes();
    const PackingFile file = read_packing_file(*sc->particles.file, sc->particles.file_length_unit,
                                               sc->material.density, max_bytes, sc->particles.file_timestep);
    std::vector<double> diameters;
    for (const double radius : file.particles.radius) diameters.push_back(2.0 * radius);
    return predict_scenario(*sc, parameters, diameters);
  }
  const Grading coarse = load_grading(r.input);
  Predictions out;
  out.parameters = parameters;
  if (r.fine) {
    const Grading fine = load_grading(*r.fine);
    out.distributions.push_back(predict_distribution(
        "whole_grading", fmt::format("{} and {} at coarse/fine {:g}", coarse.name, fine.name, *r.ca_fa),
        blend(grading_classes(coarse), grading_classes(fine), *r.ca_fa), parameters));
  } else {
    out.distributions.push_back(predict_distribution("whole_grading", fmt::format("the grading {}", coarse.name),
                                                     grading_classes(coarse), parameters));
  }
  return out;
}

nlohmann::json to_json(const Predictions& p) {
  nlohmann::json j;
  j["parameters"] = {{"cpm_compaction_index", p.parameters.compaction_index},
                     {"cpm_compaction_index_source", p.parameters.compaction_source},
                     {"cpm_residual_packing_density", p.parameters.beta},
                     {"cpm_residual_packing_density_source", p.parameters.beta_source}};
  j["parameters"]["particle_density_kg_m3"] = p.particle_density;
  j["parameters"]["particle_density_source"] = p.particle_density_source;
  if (p.parameters.beta_fine) {
    j["parameters"]["cpm_residual_packing_density_fine"] = *p.parameters.beta_fine;
    j["parameters"]["cpm_residual_packing_density_fine_source"] = p.parameters.beta_fine_source;
  }
  for (const DistributionPrediction& d : p.distributions) {
    nlohmann::json e;
    e["description"] = d.description;
    e["classes"] = d.classes.classes.size();
    e["classes_rule"] = d.classes.rule;
    const BulkDensity bulk = bulk_density(d.cpm.density, p.particle_density);
    e["cpm"] = {{"density", d.cpm.density},
                {"virtual_density", d.cpm.virtual_density},
                {"dominant_class_diameter_m", d.classes.classes[d.cpm.dominant].diameter},
                {"voids_content_percent", bulk.voids_percent},
                {"bulk_density_kg_m3", bulk.kg_per_m3},
                {"bulk_density_lb_ft3", bulk.lb_per_ft3}};
    // Beyond the polydispersity it was fitted to, the formula runs away (above 1): no value.
    const bool fitted = d.moments.polydispersity <= kDesmondWeeksValidPolydispersity;
    e["desmond_weeks"] = {{"random_close_packing", fitted ? nlohmann::json(d.random_close_packing) : nlohmann::json()},
                          {"polydispersity", d.moments.polydispersity},
                          {"skewness", d.moments.skewness},
                          {"within_fitted_range", fitted}};
    if (d.furnas_at_mix)
      e["furnas"] = {{"at_this_mix", *d.furnas_at_mix},
                     {"densest", *d.furnas_densest},
                     {"densest_fine_fraction", *d.furnas_densest_fine_fraction}};
    j[d.name] = e;
  }
  return j;
}

std::string describe(const Predictions& p) {
  fmt::memory_buffer out;
  auto o = std::back_inserter(out);
  for (const DistributionPrediction& d : p.distributions) {
    const std::size_t n = d.classes.classes.size();
    fmt::format_to(o, "  models, {} ({}, {} class{}):\n", d.name == "simulated" ? "as simulated" : "whole grading",
                   d.description, n, n == 1 ? "" : "es");
    fmt::format_to(o, "    CPM (K {:g}, beta {:g}{}): density {:.4f}, virtual {:.4f}\n", p.parameters.compaction_index,
                   p.parameters.beta,
                   p.parameters.beta_fine ? fmt::format(", the fine aggregate's {:g}", *p.parameters.beta_fine) : "",
                   d.cpm.density, d.cpm.virtual_density);
    fmt::format_to(o, "      {} (particle density {:g} kg/m3, {})\n", describe(bulk_density(d.cpm.density, p.particle_density)),
                   p.particle_density, p.particle_density_source);
    if (d.moments.polydispersity <= kDesmondWeeksValidPolydispersity)
      fmt::format_to(o, "    Desmond-Weeks random close packing: {:.4f} (polydispersity {:.3f}, skewness {:.3f})\n",
                     d.random_close_packing, d.moments.polydispersity, d.moments.skewness);
    else
      fmt::format_to(o, "    Desmond-Weeks random close packing: not applicable (polydispersity {:.3f}, beyond the "
                        "{:g} it was fitted to)\n",
                     d.moments.polydispersity, kDesmondWeeksValidPolydispersity);
    if (d.furnas_at_mix)
      fmt::format_to(o, "    Furnas infinite size ratio: {:.4f} at this mix, densest {:.4f} at {:.1f} % fine\n",
                     *d.furnas_at_mix, *d.furnas_densest, 100.0 * *d.furnas_densest_fine_fraction);
  }
  return fmt::to_string(out);
}

}  // namespace aggpack
