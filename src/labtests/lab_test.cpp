// aggpack test: a standard's test of one aggregate, planned (checked against the standard before
// any run), run over seeds through the campaign runner, and reported in the lab's units.
#include "aggpack/labtests/lab_test.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>

#include "aggpack/core/error.hpp"
#include "aggpack/core/version.hpp"
#include "aggpack/run/generate_sizes.hpp"
#include "test_scenario.hpp"

namespace aggpack {

namespace {

constexpr double kMm = 1e-3;

template <class E, std::size_t N>
E method_named(const std::array<EnumName<E>, N>& table, const std::string& name, const char* standard) {
  if (const auto m = value_of(table, name)) return *m;
  throw InputError(fmt::format("--method {}: {} defines {}", name.empty() ? "(none)" : name, standard,
                               fmt::join(names_of(table), ", ")));
}

// The scenario of a part, read as `aggpack run` would (every key checked) before any run. Its
// paths are absolute; its name in messages says whose test it is.
Scenario load_part(const LabTestPart& part, const LabTestOptions& options) {
  ScenarioOverrides overrides;
  overrides.set = options.set;
  const std::filesystem::path name =
      options.material.parent_path() / fmt::format("{} ({} scenario)", options.material.filename().string(), part.label);
  return parse_scenario(part.scenario_text, name, overrides);
}

// C29's default cut-off of fines: an eighth of the nominal maximum size (2.4 mm for a 19 mm
// stone); none (0) when the grading has nothing finer.
double c29_cut_off(const AggregateMaterial& m, double nms, const LabTestOptions& options) {
  if (options.finest_size_m > 0.0) return options.finest_size_m;
  return nms / 8.0 > m.grading.grading.smallest() ? nms / 8.0 : 0.0;
}

void plan_c29(LabTestPlan& plan, const LabTestOptions& options) {
  const AggregateMaterial& m = plan.material;
  const C29Method method = method_named(kC29MethodNames, options.method, "ASTM C29");
  plan.method = std::string(name_of(kC29MethodNames, method));
  plan.standard = "ASTM C29/C29M-17a (AASHTO T 19)";
  const std::string source = fmt::format("{}: grading", m.file.string());
  plan.nominal_maximum_size_m = nominal_maximum_size(m.grading.grading);
  check_c29_method(method, plan.nominal_maximum_size_m, source);
  C29Setup setup;
  setup.material = &plan.material;
  setup.method = method;
  setup.measure = c29_measure(plan.nominal_maximum_size_m, source);
  setup.cut_off_m = c29_cut_off(m, plan.nominal_maximum_size_m, options);
  setup.expected_packing = expected_packing(m, LabTestKind::C29);
  plan.measure_name = setup.measure.name;
  LabTestPart part;
  part.label = fmt::format("ASTM C29 {}", plan.method);
  part.measure_diameter_m = setup.measure.diameter_m;
  part.measure_height_m = part.simulated_height_m = setup.measure.height_m;
  part.cut_off_m = setup.cut_off_m;
  if (part.cut_off_m > 0.0) {
    part.cut_off_percent = percent_passing_at(m.grading.grading, setup.cut_off_m);
    plan.modelling.push_back(fmt::format("fines below {:.3g} mm ({:.1f} % of the mass) left out, the rest renormalised",
                                         part.cut_off_m / kMm, part.cut_off_percent));
  }
  part.scenario_text = c29_scenario(setup, plan.modelling);
  plan.parts.push_back(std::move(part));
}

LabTestPart c1252_part(LabTestPlan& plan, const LabTestOptions& options, std::string label,
                       std::optional<Grading> grading) {
  C1252Setup setup;
  setup.material = &plan.material;
  setup.label = std::move(label);
  setup.standard_grading = std::move(grading);
  setup.simulated_height_m = kC1252Height;
  // Method C's sand as received: the fines below C1252 A's finest sieve, 0.150 mm, left out
  // unless --finest says otherwise (a sand's passing 0.075 mm would be tens of millions of grains).
  const bool as_received = !setup.standard_grading;
  setup.cut_off_m = options.finest_size_m > 0.0 ? options.finest_size_m
                    : as_received && plan.material.grading.grading.smallest() < kC1252FinestDefault
                        ? kC1252FinestDefault
                        : 0.0;
  setup.expected_packing = expected_packing(plan.material, LabTestKind::C1252);
  LabTestPart part;
  part.label = fmt::format("ASTM C1252 {}", setup.label);
  part.measure_diameter_m = kC1252Diameter;
  part.measure_height_m = kC1252Height;
  part.simulated_height_m = setup.simulated_height_m;
  part.cut_off_m = setup.cut_off_m;
  const Grading& g = setup.standard_grading ? *setup.standard_grading : plan.material.grading.grading;
  part.cut_off_percent = setup.cut_off_m > 0.0 ? percent_passing_at(g, setup.cut_off_m) : 0.0;
  if (setup.cut_off_m > 0.0)
    plan.modelling.push_back(fmt::format("{}: fines below {:.3g} mm ({:.1f} % of the mass) left out, the rest "
                                         "renormalised",
                                         part.label, setup.cut_off_m / kMm, part.cut_off_percent));
  std::vector<std::string> modelling;
  part.scenario_text = c1252_scenario(setup, modelling);
  for (const std::string& note : modelling)
    if (std::find(plan.modelling.begin(), plan.modelling.end(), note) == plan.modelling.end())
      plan.modelling.push_back(note);
  return part;
}

void plan_c1252(LabTestPlan& plan, const LabTestOptions& options) {
  const C1252Method method = method_named(kC1252MethodNames, options.method, "ASTM C1252");
  plan.method = std::string(name_of(kC1252MethodNames, method));
  plan.standard = "ASTM C1252-17 (AASHTO T 304)";
  plan.measure_name = "C1252 cylinder, 100 mL (39 mm x 86 mm)";
  const Grading& grading = plan.material.grading.grading;
  check_c1252_grading(method, grading, fmt::format("{}: grading", plan.material.file.string()));
  plan.nominal_maximum_size_m = nominal_maximum_size(grading);
  if (method == C1252Method::A) {
    plan.parts.push_back(c1252_part(plan, options, "A", grading_of_fractions(c1252_method_a_fractions(), "C1252 A")));
  } else if (method == C1252Method::B) {
    for (const SieveFraction& f : c1252_method_b_fractions()) {
      const std::string label = fmt::format("B, {:.3g}-{:.3g} mm", f.lower_m / kMm, f.upper_m / kMm);
      plan.parts.push_back(c1252_part(plan, options, label, grading_of_fractions({f}, "C1252 " + label)));
    }
  } else {
    plan.parts.push_back(c1252_part(plan, options, "C", std::nullopt));
  }
}

// A part's run: the packing of the struck-off content and the particles it holds.
struct PartOutcome {
  double packing = 0.0, packing_whole = 0.0;
  std::size_t particles = 0;
};
PartOutcome outcome_of(const CaseRun& run) {
  const auto& measure = run.result.report.final.measure;
  if (!measure) throw std::logic_error("a lab test's run has no measure (its container is a cylinder)");
  return {measure->packing_density, measure->packing_density_whole_particles, measure->particles};
}

}  // namespace

LabTestPlan plan_lab_test(const LabTestOptions& options) {
  if (options.seeds < 1 || options.seeds > 100)
    throw InputError(fmt::format("--seeds {}: expected 1 to 100", options.seeds));
  LabTestPlan plan;
  plan.material = load_material_file(options.material);
  plan.test = options.test;
  if (options.test == LabTestKind::C29) plan_c29(plan, options);
  else plan_c1252(plan, options);
  for (const LabTestPart& part : plan.parts) load_part(part, options);  // checked now, not later
  return plan;
}

LabTestResult run_lab_test(const LabTestPlan& plan, const LabTestOptions& options, Campaign& campaign) {
  LabTestResult result;
  result.plan = plan;
  const auto start = std::chrono::steady_clock::now();
  for (int s = 1; s <= options.seeds; ++s) result.seeds.push_back(static_cast<std::uint64_t>(s));
  std::vector<double> per_seed_mean(result.seeds.size(), 0.0);
  for (const LabTestPart& part : plan.parts) {
    LabTestPartResult pr;
    pr.label = part.label;
    for (std::size_t k = 0; k < result.seeds.size(); ++k) {
      const CaseRun run = campaign.run(part.label, load_part(part, options), result.seeds[k]);
      const PartOutcome o = outcome_of(run);
      pr.packing.push_back(o.packing);
      pr.packing_whole.push_back(o.packing_whole);
      pr.particles.push_back(o.particles);
      pr.wall_clock_s += run.result.wall_clock_s;
      per_seed_mean[k] += o.packing / static_cast<double>(plan.parts.size());
    }
    pr.packing_stats = seed_statistics(pr.packing);
    pr.packing_whole_stats = seed_statistics(pr.packing_whole);
    result.parts.push_back(std::move(pr));
  }
  result.packing = seed_statistics(per_seed_mean);
  const AggregateMaterial& m = plan.material;
  const double sd = std::isnan(result.packing.sd) ? 0.0 : result.packing.sd;
  if (plan.test == LabTestKind::C29) {
    const double solid = oven_dry_specific_gravity(m) * kWaterDensity;  // C29's S W
    result.bulk_density_kg_m3 = result.packing.mean * solid;
    result.bulk_density_sd_kg_m3 = sd * solid;
    if (m.c29 && name_of(kC29MethodNames, m.c29->method) == plan.method) result.lab_value = m.c29->kg_per_m3;
  } else if (m.c1252 && name_of(kC1252MethodNames, m.c1252->method) == plan.method) {
    result.lab_value = m.c1252->percent;
  }
  result.voids_percent = 100.0 * (1.0 - result.packing.mean);
  result.voids_sd_percent = 100.0 * sd;
  result.wall_clock_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

LabTestResult run_lab_test(const LabTestOptions& options, std::ostream& log) {
  const LabTestPlan plan = plan_lab_test(options);
  Campaign campaign(options.threads, options.quiet, log, plan.parts.size() * static_cast<std::size_t>(options.seeds));
  return run_lab_test(plan, options, campaign);
}

}  // namespace aggpack
