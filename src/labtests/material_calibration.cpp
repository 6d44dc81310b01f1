// calibrate MATERIAL --test: the material's contact parameter fitted to its own lab test.
#include "aggpack/labtests/material_calibration.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "aggpack/core/error.hpp"
#include "aggpack/core/version.hpp"

namespace aggpack {

namespace {

// The lab's number for the plan's test and method, and what it is as a packing fraction.
std::pair<double, double> lab_target(const LabTestPlan& plan) {
  const AggregateMaterial& m = plan.material;
  if (plan.test == LabTestKind::C29) {
    if (!m.c29 || name_of(kC29MethodNames, m.c29->method) != plan.method)
      throw InputError(fmt::format("{}: no ASTM C29 {} bulk density to calibrate to: give it as [lab.c29] "
                                   "bulk_density with method = \"{}\"",
                                   m.file.string(), plan.method, plan.method));
    return {m.c29->kg_per_m3, 1.0 - voids_percent(m, m.c29->kg_per_m3) / 100.0};
  }
  if (!m.c1252 || name_of(kC1252MethodNames, m.c1252->method) != plan.method)
    throw InputError(fmt::format("{}: no ASTM C1252 method {} uncompacted voids to calibrate to: give them as "
                                 "[lab.c1252] voids_percent with method = \"{}\"",
                                 m.file.string(), plan.method, plan.method));
  return {m.c1252->percent, 1.0 - m.c1252->percent / 100.0};
}

std::string lever(const MaterialCalibrationOptions& options, const AggregateMaterial& m) {
  if (options.parameter.empty()) return m.shape ? "friction" : "rolling_friction";
  if (options.parameter != "friction" && options.parameter != "rolling_friction")
    throw InputError(fmt::format("--fit {}: expected friction or rolling_friction", options.parameter));
  return options.parameter;
}

}  // namespace

MaterialCalibration calibrate_material(const MaterialCalibrationOptions& options, std::ostream& log) {
  if (options.test.seeds < 2)
    throw InputError(fmt::format("--seeds {}: expected 2 to 100 with --test: the seeds' scatter is the noise the "
                                 "fit's band is made of",
                                 options.test.seeds));
  if (options.max_evaluations < 2 || options.max_evaluations > 50)
    throw InputError(fmt::format("--max-runs {}: expected 2 to 50 values", options.max_evaluations));
  MaterialCalibration c;
  c.plan = plan_lab_test(options.test);
  c.parameter = lever(options, c.plan.material);
  c.key = "contact." + material_key(c.parameter);
  std::tie(c.lab_value, c.target_packing) = lab_target(c.plan);
  c.seeds = static_cast<std::uint64_t>(options.test.seeds);
  const std::vector<double> range = options.range.value_or(
      c.parameter == "friction" ? std::vector<double>{0.1, 1.0} : std::vector<double>{0.0, 0.5});
  if (range.size() != 2 || !(range[0] >= 0.0 && range[0] < range[1]))
    throw InputError("--range: expected LOW,HIGH with 0 <= LOW < HIGH");
  c.range_low = range[0], c.range_high = range[1];
  // Every value's runs are checked as the first would be: the range's ends are planned now.
  for (const double end : range) {
    LabTestOptions o = options.test;
    o.set.push_back(fmt::format("material.{}={}", material_key(c.parameter), end));
    plan_lab_test(o);
  }
  Campaign campaign(options.test.threads, options.test.quiet, log,
                    c.plan.parts.size() * c.seeds * static_cast<std::size_t>(options.max_evaluations));
  const auto density = [&](double value) {
    LabTestOptions o = options.test;
    o.set.push_back(fmt::format("material.{}={}", material_key(c.parameter), value));
    const LabTestResult r = run_lab_test(plan_lab_test(o), o, campaign);
    std::vector<double> per_seed(r.seeds.size(), 0.0);
    for (const LabTestPartResult& part : r.parts)
      for (std::size_t k = 0; k < per_seed.size(); ++k) per_seed[k] += part.packing[k] / double(r.parts.size());
    return simulated_densities(fmt::format("{} = {:.4g}", c.parameter, value), per_seed);
  };
  c.search = find_crossing(density, c.range_low, c.range_high, c.target_packing, options.max_evaluations, c.parameter);
  return c;
}

nlohmann::json to_json(const MaterialCalibration& c) {
  nlohmann::json evaluations = nlohmann::json::array();
  for (const DemEvaluation& e : c.search.evaluations)
    evaluations.push_back({{"value", e.value},
                           {"packing_density", e.density.density},
                           {"mean", e.density.mean},
                           {"standard_error", e.density.standard_error}});
  return {{"kind", "aggpack material calibration"},
          {"aggpack_version", kVersion},
          {"material", c.plan.material.file.string()},
          {"test", std::string(name_of(kLabTestNames, c.plan.test))},
          {"standard", c.plan.standard},
          {"method", c.plan.method},
          {"lab_value", c.lab_value},
          {"lab_unit", c.plan.test == LabTestKind::C29 ? "kg/m3" : "% voids"},
          {"target_packing_density", c.target_packing},
          {"parameter", c.parameter},
          {"key", c.key},
          {"value", c.search.value},
          {"band", {c.search.band_low, c.search.band_high}},
          {"band_clipped", c.search.band_clipped},
          {"converged", c.search.converged},
          {"range", {c.range_low, c.range_high}},
          {"seeds", c.seeds},
          {"evaluations", evaluations},
          {"modelling", c.plan.modelling}};
}

std::string calibrated_material_text(const MaterialCalibration& c, std::string_view original) {
  // An earlier calibration is the file's last table, after the marker this function writes.
  constexpr std::string_view kMarker = "# --- written by aggpack calibrate";
  std::string text(original.substr(0, std::min(original.size(), original.find(kMarker))));
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  const std::string contact_key = material_key(c.parameter);
  text += fmt::format(
      "\n\n{} {} (aggpack {}): {} fitted to {} {} = {:.6g} {}, {} seeds\n"
      "[calibration]\n"
      "test = \"{}\"\nmethod = \"{}\"\nlab_value = {:.6g}\ntarget_packing_density = {:.6g}\n"
      "parameter = \"{}\"\nband = [{:.6g}, {:.6g}]\nconverged = {}\nseeds = {}\naggpack_version = \"{}\"\n"
      "[calibration.contact]  # replaces [contact]'s value\n{} = {:.6g}\n",
      kMarker, "on its lab test", kVersion, c.parameter, c.plan.standard, c.plan.method, c.lab_value,
      c.plan.test == LabTestKind::C29 ? "kg/m3" : "% voids", c.seeds, name_of(kLabTestNames, c.plan.test),
      c.plan.method, c.lab_value, c.target_packing, c.parameter, c.search.band_low, c.search.band_high,
      c.search.converged ? "true" : "false", c.seeds, kVersion, contact_key, c.search.value);
  return text;
}

}  // namespace aggpack
