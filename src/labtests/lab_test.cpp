// aggpack test: a standard's test of one aggregate, planned (checked against the standard before
// any run), run over seeds through the campaign runner, and reported in the lab's units.
#include "aggpack/labtests/lab_test.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <functional>

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

// A representative measure at least this many largest particles across: narrower, its wall
// layers would leave it no core to read.
constexpr double kLeastRepresentativeSizes = 4.0;

// Writes a part's scenario for a simulated measure, adding its modelling notes.
using ScenarioWriter = std::function<std::string(const SimulatedMeasure&, std::vector<std::string>&)>;

void add_notes(std::vector<std::string>& to, const std::vector<std::string>& notes) {
  for (const std::string& note : notes)
    if (std::find(to.begin(), to.end(), note) == to.end()) to.push_back(note);
}

// The part's measure and scenario: the standard's measure, or where `may_scale` and it would
// hold more than --max-particles, a representative one of the same proportions scaled by
// cbrt(max / expected), refused when it would be narrower than kLeastRepresentativeSizes.
void size_part(LabTestPlan& plan, LabTestPart& part, SimulatedMeasure full, const ScenarioWriter& write,
               const LabTestOptions& options, bool may_scale) {
  std::vector<std::string> notes;
  part.scenario_text = write(full, notes);
  part.simulated_diameter_m = full.diameter_m;
  part.simulated_height_m = full.rim_m;
  part.largest_size_m = full.largest_size_m;
  part.full_size_particles = expected_particle_count(load_part(part, options).particles);
  if (may_scale && part.full_size_particles > options.max_particles) {
    part.scale = std::cbrt(options.max_particles / part.full_size_particles);
    SimulatedMeasure scaled = full;
    scaled.diameter_m *= part.scale;
    scaled.rim_m *= part.scale;
    const double least = kLeastRepresentativeSizes * full.largest_size_m;
    if (scaled.diameter_m < least)
      throw InputError(fmt::format(
          "--max-particles {:.0f}: {} would hold about {:.0f} particles; a representative measure of {:.0f} would be "
          "{:.1f} mm across, narrower than {:g} of its largest particles ({:.2f} mm); expected --max-particles of at "
          "least {:.0f}",
          options.max_particles, part.label, part.full_size_particles, options.max_particles, scaled.diameter_m / kMm,
          kLeastRepresentativeSizes, full.largest_size_m / kMm,
          std::ceil(part.full_size_particles * std::pow(least / full.diameter_m, 3))));
    // Said first, so that the scenario's own comments say it too.
    notes.assign(
        1,
        fmt::format(
            "{}: a representative measure, the standard's scaled by {:.3f} ({:.1f} mm across, {:.1f} mm high, about "
            "{:.0f} "
            "particles instead of {:.0f}); the standard measure's content read from it as core - (core - its content) "
            "x "
            "{:.3f}, the walls' loss of density being a layer of the same loss per unit area at any size (the core: "
            "farther than one largest particle from its wall); checked against a full-size run in docs/validation.md",
            part.label, part.scale, scaled.diameter_m / kMm, scaled.rim_m / kMm, options.max_particles,
            part.full_size_particles, part.scale));
    part.scenario_text = write(scaled, notes);
    part.simulated_diameter_m = scaled.diameter_m;
    part.simulated_height_m = scaled.rim_m;
  }
  add_notes(plan.modelling, notes);
}

void plan_c29(LabTestPlan& plan, const LabTestOptions& options) {
  const AggregateMaterial& m = plan.material;
  const C29Method method = method_named(kC29MethodNames, options.method, "ASTM C29");
  plan.method = std::string(name_of(kC29MethodNames, method));
  plan.standard = "ASTM C29/C29M-17a (AASHTO T 19)";
  const std::string source = fmt::format("{}: grading", m.file.string());
  plan.nominal_maximum_size_m = nominal_maximum_size(m.grading.grading);
  check_c29_method(method, plan.nominal_maximum_size_m, source);
  plan.grain_volume_ratio = grain_volume_ratio(m);  // after the checks: it draws the grains' templates
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
  part.measure_height_m = setup.measure.height_m;
  part.cut_off_m = setup.cut_off_m;
  if (part.cut_off_m > 0.0) {
    part.cut_off_percent = percent_passing_at(m.grading.grading, setup.cut_off_m);
    plan.modelling.push_back(fmt::format("fines below {:.3g} mm ({:.1f} % of the mass) left out, the rest renormalised",
                                         part.cut_off_m / kMm, part.cut_off_percent));
  }
  // Always the standard's measure: a smaller one would change what 25 strokes of the rod do.
  const SimulatedMeasure full{setup.measure.diameter_m, setup.measure.height_m, maximum_size(m.grading.grading),
                              plan.grain_volume_ratio};
  size_part(
      plan, part, full,
      [&](const SimulatedMeasure& simulated, std::vector<std::string>& notes) {
        setup.simulated = simulated;
        return c29_scenario(setup, notes);
      },
      options, false);
  plan.parts.push_back(std::move(part));
}

LabTestPart c1252_part(LabTestPlan& plan, const LabTestOptions& options, std::string label,
                       std::optional<Grading> grading) {
  C1252Setup setup;
  setup.material = &plan.material;
  setup.label = std::move(label);
  setup.standard_grading = std::move(grading);
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
  part.cut_off_m = setup.cut_off_m;
  const Grading& g = setup.standard_grading ? *setup.standard_grading : plan.material.grading.grading;
  part.cut_off_percent = setup.cut_off_m > 0.0 ? percent_passing_at(g, setup.cut_off_m) : 0.0;
  if (setup.cut_off_m > 0.0)
    plan.modelling.push_back(fmt::format("{}: fines below {:.3g} mm ({:.1f} % of the mass) left out, the rest "
                                         "renormalised",
                                         part.label, setup.cut_off_m / kMm, part.cut_off_percent));
  // Method C: the sand passing 4.75 mm (c1252_scenario cuts it there).
  const double largest = std::min(maximum_size(g), kC1252MethodCLargest);
  size_part(
      plan, part, {kC1252Diameter, kC1252Height, largest, plan.grain_volume_ratio},
      [&](const SimulatedMeasure& simulated, std::vector<std::string>& notes) {
        setup.simulated = simulated;
        return c1252_scenario(setup, notes);
      },
      options, true);
  return part;
}

void plan_c1252(LabTestPlan& plan, const LabTestOptions& options) {
  const C1252Method method = method_named(kC1252MethodNames, options.method, "ASTM C1252");
  plan.method = std::string(name_of(kC1252MethodNames, method));
  plan.standard = "ASTM C1252-17 (AASHTO T 304)";
  plan.measure_name = "C1252 cylinder, 100 mL (39 mm x 86 mm)";
  const Grading& grading = plan.material.grading.grading;
  check_c1252_grading(method, grading, fmt::format("{}: grading", plan.material.file.string()));
  plan.grain_volume_ratio = grain_volume_ratio(plan.material);  // after the checks: it draws the grains' templates
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

// The packing of a cylinder's core: its rings of the wall profile (over the bed's height less
// one largest particle at the floor and at the surface) farther than `clearance` from the wall,
// weighted by their areas.
double core_packing(const PackingReport& report, double clearance) {
  const double radius = 0.5 * report.measure->diameter;
  const Profile& rings = report.wall;
  const double half = rings.position.size() > 1 ? 0.5 * (rings.position[1] - rings.position[0]) : 0.0;
  double solid = 0.0, area = 0.0;
  for (std::size_t k = 0; k < rings.position.size(); ++k) {
    const double inner = radius - std::min(radius, rings.position[k] + half);
    const double outer = radius - (rings.position[k] - half);
    if (rings.position[k] - half < clearance || outer <= 0.0) continue;
    const double a = outer * outer - inner * inner;
    solid += rings.solid_fraction[k] * a;
    area += a;
  }
  if (!(area > 0.0)) throw std::logic_error("a lab test's measure has no core (narrower than two largest particles)");
  return solid / area;
}

// A part's run: the packing of the struck-off content and the particles it holds, read as the
// standard measure's from a representative one (LabTestPartResult::packing).
struct PartOutcome {
  double packing = 0.0, packing_whole = 0.0, simulated = 0.0, core = 0.0;
  std::size_t particles = 0;
};
PartOutcome outcome_of(const CaseRun& run, const LabTestPart& part) {
  const PackingReport& report = run.result.report.final;
  if (!report.measure) throw std::logic_error("a lab test's run has no measure (its container is a cylinder)");
  const MeasureContent& measure = *report.measure;
  // Filled to overflowing, or the content is not the test's (the amount is planned for it).
  if (!(report.bed.surface > measure.rim + part.largest_size_m))
    throw std::runtime_error(fmt::format(
        "{}: the bed's surface ({:.1f} mm) is not a largest particle above the rim ({:.1f} mm): the measure was not "
        "filled, and its content is not the test's; expected a fill above the rim (report it: the test plans its "
        "amount from the packing expected)",
        part.label, report.bed.surface * 1e3, measure.rim * 1e3));
  PartOutcome o{measure.packing_density, measure.packing_density_whole_particles, measure.packing_density, 0.0,
                measure.particles};
  o.core = core_packing(report, part.largest_size_m);
  if (part.scale < 1.0) {
    o.packing = o.core - (o.core - measure.packing_density) * part.scale;
    o.packing_whole = o.core - (o.core - measure.packing_density_whole_particles) * part.scale;
  }
  return o;
}

// Adds a run's time, stage by stage, to a part's.
void add_timing(LabTestTiming& t, const RunReport& r) {
  const auto seconds = [&](const char* key) {
    const auto it = r.wall_clock_s.find(key);
    return it == r.wall_clock_s.end() ? 0.0 : it->second;
  };
  t.sizes_s += seconds("sizes");
  t.grains_s += seconds("grains");
  t.analysis_s += seconds("analysis");
  if (r.dynamics) {
    t.pour_s += r.dynamics->wall_clock_s();
    t.dem_steps += r.dynamics->steps();
  }
  for (const RoddingReport& rod : r.roddings) t.rodding_s += rod.wall_clock_s, t.dem_steps += rod.steps;
  for (const JigReport& jig : r.jiggings) t.jigging_s += jig.wall_clock_s, t.dem_steps += jig.steps;
  t.spheres = r.particles.size();
  t.simulated_s += r.simulated_time;
}

}  // namespace

LabTestPlan plan_lab_test(const LabTestOptions& options) {
  if (options.seeds < 1 || options.seeds > 100)
    throw InputError(fmt::format("--seeds {}: expected 1 to 100", options.seeds));
  if (!(options.max_particles >= 100.0 && options.max_particles <= 1e8))  // NaN too
    throw InputError(fmt::format("--max-particles {}: expected 100 to 1e8", options.max_particles));
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
      const PartOutcome o = outcome_of(run, part);
      pr.packing.push_back(o.packing);
      pr.packing_whole.push_back(o.packing_whole);
      pr.packing_simulated.push_back(o.simulated);
      pr.packing_core.push_back(o.core);
      pr.particles.push_back(o.particles);
      pr.wall_clock_s += run.result.wall_clock_s;
      add_timing(pr.timing, run.result.report);
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
