#include "aggpack/studies/reproduce.hpp"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <algorithm>
#include <cmath>

#include "aggpack/core/error.hpp"
#include "aggpack/core/version.hpp"
#include "aggpack/io/atomic_file.hpp"
#include "reproduce_parts.hpp"

// aggpack reproduce's entry points, its plan and the running of its cases; the report's
// sections are composed in reproduce_*.cpp.
namespace aggpack {

namespace reproduction {
namespace {

// Table 2 from one calibration mix: the sand's rolling friction is the unknown (the stone's is
// the literature's). The bed is reduced so that the study takes about 40 minutes a seed on two
// cores (docs/validation.md, "Table 2 from one calibration mix").
CalibratedTable2Plan calibrated_plan(bool quick) {
  CalibratedTable2Plan c{"table2_mix3_stone_sand.toml", "sand", {0.0, 0.1, 0.2, 0.35}, {}, {}};
  c.bed = {"particles.fine.d_min=\"0.1 in\"", "container.side=\"4 in\"", "container.height=\"10 in\"",
           "particles.fill_height=\"4 in\"", "analysis.box_sides=[\"1.4 in\", \"1.5 in\", \"1.6 in\"]"};
  c.bed_label = "REDUCED: stone and sand cut at 0.1 in, a 4 in container filled to 4 in, cubes of 1.4-1.6 in";
  if (quick) {
    c.values = {0.0, 0.35};
    c.bed = {"particles.fine.d_min=\"0.25 in\"", "particles.coarse.d_min=\"0.25 in\"",
             "container.side=\"3 in\"",          "container.height=\"7 in\"",
             "particles.fill_height=\"3 in\"",   "analysis.box_sides=[\"1 in\", \"1.1 in\"]"};
    c.bed_label = "QUICK: stone and sand cut at 0.25 in, a 3 in container filled to 3 in, cubes of 1-1.1 in";
  }
  return c;
}

// Table 2 with shape: the stone as rigid grains of a typical crushed stone (docs/validation.md,
// "Table 2 with shape"). The grains' length sets the boxes' margins, so the bed is taller than
// the calibrated study's, and periodic (no lateral margin); the stone is cut at #4 (its smallest
// grains' members set the time step) and the sand at 0.1 in, the rest carried by CPM. The
// grains' stone has no rolling friction: the spheres' 0.2 stands in for the shape they have.
ShapedTable2Plan shaped_plan(bool quick) {
  ShapedTable2Plan s;
  s.scenario = "table2_mix3_stone_sand.toml";
  s.shape = "{ family = \"angular\", spheres = 6, templates = 32, flakiness_index = 18 }";
  s.shape_label =
      "angular grains (random convex hulls of 12 corners) of 6 spheres, 32 templates, fitted to a flakiness index of "
      "18 % (EN 933-3: a typical crushed stone, inside EN 12620's category FI20, not a measurement of the paper's "
      "stones), their rolling friction 0 (the spheres' μ_r 0.2 stands in for the shape the grains have); 6 spheres "
      "make a bumpy grain rather than an angular one, the affordable compromise (docs/validation.md)";
  s.bed = {"container.sides=\"periodic\"",         "container.side=\"4 in\"",
           "container.height=\"12 in\"",           "particles.fill_height=\"7 in\"",
           "particles.coarse.d_min=\"0.187 in\"",  "particles.fine.d_min=\"0.1 in\"",
           "analysis.box_sides=[\"1.2 in\", \"1.3 in\", \"1.4 in\"]"};
  s.bed_label = "REDUCED: stone cut at #4 (0.187 in) and sand at 0.1 in, periodic sides 4 in apart filled to 7 in, "
                "cubes of 1.2-1.4 in";
  if (quick) {
    s.shape = "{ family = \"angular\", spheres = 2, templates = 4, elongation = 0.7, flatness = 0.7 }";
    s.shape_label = "QUICK: angular grains of 2 spheres, 4 templates, I/L and S/I 0.7 ± 0.1, rolling friction 0";
    s.bed = {"container.sides=\"periodic\"",      "container.side=\"3 in\"",
             "container.height=\"8 in\"",         "particles.fill_height=\"3.5 in\"",
             "particles.coarse.d_min=\"0.3 in\"", "particles.coarse.d_max=\"0.5 in\"",
             "particles.fine.d_min=\"0.3 in\"",   "analysis.box_sides=[\"0.6 in\"]",
             "pour.batches=1",                     "dynamics.max_time=0.6"};
    s.bed_label = "QUICK: stone cut to 0.3-0.5 in and sand at 0.3 in, periodic sides 3 in apart filled to 3.5 in, "
                  "one batch, a cube of 0.6 in, the pour cut at 0.6 s";
  }
  s.grains_sets = {"particles.coarse.shape=" + s.shape, "materials.stone.rolling_friction=0"};
  return s;
}

// What each mode runs. The quick mode exercises every table and figure in a few minutes.
Plan make_plan(const ReproduceOptions& o) {
  Plan p;
  p.seeds = o.seeds > 0 ? o.seeds : (o.quick ? 1 : 3);
  const SensitivityCase shipped{"as shipped (5 in walls, sand cut at 0.04 in, mass sampling)", {}, 0.04};
  const auto cut = [](double inches) {
    return SensitivityCase{
        fmt::format("sand cut at {:g} in", inches), {fmt::format("particles.fine.d_min=\"{:g} in\"", inches)}, inches};
  };
  // Table 2's DEM protocol: a reduced stiffness, E/1000 of natural aggregate (50 GPa), which
  // moved mix 3's settled density by at most 0.0032 against E/10 and E/100 (docs/validation.md,
  // scripts/validate_stiffness.sh), and a bed called settled when the kinetic energy stays below
  // 1e-3 m g d and the box density within 5e-4 for 0.02 s: the density is then within 3e-4 of
  // its value at 1e-5 m g d, for under a third of the simulated time. The bed is the smallest
  // that holds the virtual cubes without walls: periodic sides 4 in apart (drop-and-roll needs
  // more than four of the largest diameters, 1 in), 0.64 of the shipped footprint; and the
  // Verlet skin is 0.2 of the sand's 0.04 in, which halves the list builds (docs/validation.md,
  // "Table 2 settled on a periodic cell").
  if (o.settle_table2)
    p.table2_dem = {"container.sides=\"periodic\"",
                    "container.side=\"4 in\"",
                    "dynamics.skin=\"0.008 in\"",
                    "material.youngs_modulus=5e7",
                    "material.wall_youngs_modulus=5e7",
                    "dynamics.friction_model=\"mindlin\"",
                    "dynamics.quiet_kinetic_fraction=1e-3",
                    "dynamics.quiet_window=0.02",
                    o.quick ? "dynamics.max_time=0.05" : "dynamics.max_time=1"};
  // The examples poured, then tapped: 10 taps of 2 g at 30 Hz, 0.15 s apart (a light tapping;
  // docs/validation.md has 100 taps at 2 g and 5 g).
  p.poured_sets = {"tapping.taps=10", "tapping.intensity=2", "tapping.frequency=30", "tapping.rest_time=0.15",
                   "output.formats=[]"};
  p.tapping_label = "10 taps of 2 g at 30 Hz, 0.15 s apart";
  if (o.quick) {
    p.poured_sets = {"tapping.taps=2",         "tapping.intensity=2",   "tapping.frequency=30",
                     "tapping.rest_time=0.15", "dynamics.max_time=0.6", "output.formats=[]"};
    p.tapping_label = "2 taps of 2 g at 30 Hz, 0.15 s apart (QUICK: the pour cut at 0.6 s)";
  }
  // Every mix at the sand cut-offs of docs/validation.md's whole-grading table (the 0.02 in cut
  // is what narrows the band, and costs some 30 s a run).
  if (o.whole_grading)
    p.table2_cuts_in = o.quick ? std::vector<double>{0.1, 0.06} : std::vector<double>{0.1, 0.07, 0.02};
  if (o.calibrated_table2) p.calibrated_table2 = calibrated_plan(o.quick);
  if (o.shaped_table2) p.shaped_table2 = shaped_plan(o.quick);
  p.table2_materials = o.table2_materials;
  if (o.quick) {
    p.example_sets = {"dynamics.max_time=0.25"};
    p.sensitivity = {shipped, cut(0.1), cut(0.06)};
    return p;
  }
  p.sensitivity = {shipped,
                   cut(0.1),
                   cut(0.06),
                   cut(0.03),
                   cut(0.02),
                   {"container 4.5 in", {"container.side=\"4.5 in\""}},
                   {"container 6 in", {"container.side=\"6 in\""}},
                   {"periodic sides (no walls)", {"container.sides=\"periodic\""}},
                   {"number sampling (the paper's Eq. 11)", {"particles.sampling=\"number\""}}};
  return p;
}

// The shipped variant of the sensitivity study is Table 2's own mix 3: not run twice. So is a
// sand cut-off that every mix's series already ran.
bool runs_of_its_own(const Plan& plan, const SensitivityCase& c) {
  return !c.sets.empty() && std::none_of(plan.table2_cuts_in.begin(), plan.table2_cuts_in.end(),
                                         [&](double cut) { return std::abs(cut - c.sand_cut_in) < 1e-12; });
}

std::string calibrated_label(const CalibratedTable2Plan& c, int mix, double value) {
  return fmt::format("Table 2 mix {}, stone and sand, {} rolling friction {:g}", mix, c.material, value);
}

std::string shaped_label(int mix, bool grains) {
  return fmt::format("Table 2 mix {}, stone and sand, the stone as {}", mix, grains ? "grains" : "spheres");
}

// The calibrated and shaped studies' scenario and mixes, checked before any run.
void check_study_inputs(const Plan& plan, const ReproduceInputs& in) {
  if (plan.shaped_table2 && !fs::exists(in.examples / plan.shaped_table2->scenario))
    throw InputError(fmt::format("reproduce --shaped-table2: {} is missing: the study pours every Table 2 mix from it",
                                 (in.examples / plan.shaped_table2->scenario).string()));
  if (plan.shaped_table2 && in.table2.size() < 2)
    throw InputError(fmt::format("reproduce --shaped-table2: {} has {} mix(es); a slope against Fa needs two or more",
                                 (in.examples / "fu2003_table2.csv").string(), in.table2.size()));
  if (!plan.calibrated_table2) return;
  if (!fs::exists(in.examples / plan.calibrated_table2->scenario))
    throw InputError(
        fmt::format("reproduce --calibrated-table2: {} is missing: the study pours every Table 2 mix "
                    "from it",
                    (in.examples / plan.calibrated_table2->scenario).string()));
  if (in.table2.size() < 3)
    throw InputError(
        fmt::format("reproduce --calibrated-table2: {} has {} mix(es); calibrating on one and "
                    "predicting the others needs three or more",
                    (in.examples / "fu2003_table2.csv").string(), in.table2.size()));
}

// The runs of every case, over all seeds: what the campaign announces and `--dry-run` lists.
std::vector<std::pair<std::string, std::size_t>> planned_cases(const Plan& plan, const ReproduceInputs& in) {
  const std::size_t seeds = static_cast<std::size_t>(plan.seeds);
  std::vector<std::pair<std::string, std::size_t>> cases;
  for (const PaperExample& ex : in.paper) cases.emplace_back(ex.title, seeds);
  for (const PaperExample& ex : in.paper)
    if (fs::exists(in.pour_scenario(ex))) cases.emplace_back(ex.short_name + " poured and tapped", seeds);
  for (const Table2Row& row : in.table2) {
    cases.emplace_back(fmt::format("Table 2 mix {}", row.mix), seeds);
    if (!plan.table2_dem.empty()) cases.emplace_back(fmt::format("Table 2 mix {} (with DEM)", row.mix), 1);
    for (const double cut : plan.table2_cuts_in)
      cases.emplace_back(fmt::format("Table 2 mix {}, sand cut at {:g} in", row.mix, cut), seeds);
  }
  const auto mix3 = std::find_if(in.table2.begin(), in.table2.end(), [](const Table2Row& r) { return r.mix == 3; });
  const int sensitivity_mix = mix3 != in.table2.end() ? mix3->mix : in.table2.empty() ? 0 : in.table2.front().mix;
  for (const SensitivityCase& c : plan.sensitivity)
    if (runs_of_its_own(plan, c))
      cases.emplace_back(fmt::format("mix {} sensitivity: {}", sensitivity_mix, c.label), seeds);
  if (plan.calibrated_table2)
    for (const Table2Row& row : in.table2)
      for (const double value : plan.calibrated_table2->values)
        cases.emplace_back(calibrated_label(*plan.calibrated_table2, row.mix, value), seeds);
  if (plan.shaped_table2)
    for (const Table2Row& row : in.table2)
      for (const bool grains : {false, true}) cases.emplace_back(shaped_label(row.mix, grains), seeds);
  return cases;
}

std::size_t total_runs(const std::vector<std::pair<std::string, std::size_t>>& cases) {
  std::size_t runs = 0;
  for (const auto& [what, count] : cases) runs += count;
  return runs;
}

// Where and how a reproduction's cases run: the campaign, the shipped scenarios, the plan.
struct CaseRunner {
  Campaign& campaign;
  const Plan& plan;
  const fs::path& examples;
  fs::path runs_dir;
  std::size_t seeds;
  // The overrides of every Table 2 run: its beds are not written as particle files.
  [[nodiscard]] static std::vector<std::string> no_particle_files() { return {"output.formats=[]"}; }
  [[nodiscard]] fs::path table2_scenario(int mix) const { return examples / fmt::format("table2_mix{}.toml", mix); }
};

// Beds are kept only where a picture is drawn (seed 1 of Example 2 and of the first mix):
// a Table 2 bed holds 10^5-10^6 spheres.
CaseRun keep_bed_if(bool keep, CaseRun run) {
  if (!keep) {
    run.result.report.particles = ParticleStore{};
    run.result.report.deposited.reset();
  }
  return run;
}

// Examples 1 and 2, then the examples poured, then tapped.
void run_examples(const CaseRunner& cases, const ReproduceInputs& inputs, Reproduction& rep) {
  Campaign& campaign = cases.campaign;
  for (const PaperExample& ex : inputs.paper)
    for (std::size_t s = 1; s <= cases.seeds; ++s)
      rep.examples[ex.id].add(keep_bed_if(ex.id == "example2" && s == 1,
                                          campaign.run(ex.title, cases.examples / ex.scenario, cases.plan.example_sets,
                                                       s, cases.runs_dir / ex.id / fmt::format("seed_{}", s))));
  for (const PaperExample& ex : inputs.paper)
    if (fs::exists(inputs.pour_scenario(ex)))
      for (std::size_t s = 1; s <= cases.seeds; ++s)
        rep.poured[ex.id].add(keep_bed_if(
            false,
            campaign.run(fmt::format("{} poured and tapped", ex.short_name), inputs.pour_scenario(ex),
                         cases.plan.poured_sets, s, cases.runs_dir / (ex.id + "_poured") / fmt::format("seed_{}", s))));
}

// Table 2: each mix over the seeds (seed 1 settled when the plan says so), then at the plan's sand cut-offs.
void run_table2(const CaseRunner& cases, const std::vector<Table2Row>& table2, Reproduction& rep) {
  const Plan& plan = cases.plan;
  std::vector<Table2Outcome>& mixes = rep.mixes;
  std::vector<std::string> table2_dem_sets = cases.no_particle_files();
  table2_dem_sets.insert(table2_dem_sets.end(), plan.table2_dem.begin(), plan.table2_dem.end());
  for (const Table2Row& row : table2) {
    Table2Outcome m;
    m.row = row;
    for (std::size_t s = 1; s <= cases.seeds; ++s)
      m.add(keep_bed_if(
          mixes.empty() && s == 1,
          cases.campaign.run(fmt::format("Table 2 mix {}", row.mix), cases.table2_scenario(row.mix),
                             cases.no_particle_files(), s,
                             cases.runs_dir / fmt::format("table2_mix{}", row.mix) / fmt::format("seed_{}", s))));
    // The DEM protocol deposits seed 1 again on its own bed, so the deposited column keeps the
    // shipped bed for every seed.
    if (!plan.table2_dem.empty())
      m.settled.add(keep_bed_if(
          false, cases.campaign.run(fmt::format("Table 2 mix {} (with DEM)", row.mix), cases.table2_scenario(row.mix),
                                    table2_dem_sets, 1,
                                    cases.runs_dir / fmt::format("table2_mix{}_settled", row.mix) / "seed_1")));
    for (const double cut : plan.table2_cuts_in) {
      std::vector<std::string> sets = cases.no_particle_files();
      sets.push_back(fmt::format("particles.fine.d_min=\"{:g} in\"", cut));
      SeedRuns runs;
      for (std::size_t s = 1; s <= cases.seeds; ++s)
        runs.add(keep_bed_if(
            false,
            cases.campaign.run(
                fmt::format("Table 2 mix {}, sand cut at {:g} in", row.mix, cut), cases.table2_scenario(row.mix), sets,
                s, cases.runs_dir / fmt::format("table2_mix{}_cut_{:g}in", row.mix, cut) / fmt::format("seed_{}", s))));
      m.cut_series.emplace_back(cut, std::move(runs));
    }
    mixes.push_back(std::move(m));
  }
}

// Sensitivity of Table 2 mix 3 to the choices the paper leaves open.
void run_sensitivity(const CaseRunner& cases, Reproduction& rep) {
  const Plan& plan = cases.plan;
  const Table2Outcome& sensitivity_mix = rep.sensitivity_mix();
  const Table2Row& sensitivity_row = sensitivity_mix.row;
  std::vector<Variant>& variants = rep.variants;
  for (std::size_t v = 0; v < plan.sensitivity.size(); ++v) {
    const SensitivityCase& spec = plan.sensitivity[v];
    Variant variant;
    variant.spec = spec;
    if (spec.sets.empty()) {
      for (CaseRun r : sensitivity_mix.runs) variant.add(keep_bed_if(false, std::move(r)));
    } else if (const SeedRuns* done = sensitivity_mix.at_cut(spec.sand_cut_in)) {
      for (const CaseRun& r : done->runs) variant.add(r);
    } else {
      std::vector<std::string> sets = cases.no_particle_files();
      sets.insert(sets.end(), spec.sets.begin(), spec.sets.end());
      for (std::size_t s = 1; s <= cases.seeds; ++s)
        variant.add(keep_bed_if(
            false, cases.campaign.run(fmt::format("mix {} sensitivity: {}", sensitivity_row.mix, spec.label),
                                      cases.table2_scenario(sensitivity_row.mix), sets, s,
                                      cases.runs_dir / fmt::format("sensitivity_{}", v) / fmt::format("seed_{}", s))));
    }
    variants.push_back(std::move(variant));
  }
}

// Table 2 from one calibration mix: every mix at every grid value of the material's rolling
// friction, over the seeds.
void run_calibrated_table2(const CaseRunner& cases, const std::vector<Table2Row>& table2, Reproduction& rep) {
  if (!cases.plan.calibrated_table2) return;
  const CalibratedTable2Plan& c = *cases.plan.calibrated_table2;
  for (const Table2Row& row : table2) {
    CalibratedMix mix{row, {}};
    for (const double value : c.values) {
      std::vector<std::string> sets = cases.no_particle_files();
      sets.insert(sets.end(), c.bed.begin(), c.bed.end());
      sets.push_back(fmt::format("particles.ca_fa={:.17g}", row.ca_fa));
      sets.push_back(fmt::format("materials.{}.rolling_friction={:.17g}", c.material, value));
      SeedRuns runs;
      for (std::size_t s = 1; s <= cases.seeds; ++s)
        runs.add(keep_bed_if(
            false, cases.campaign.run(calibrated_label(c, row.mix, value), cases.examples / c.scenario, sets, s,
                                      cases.runs_dir / "calibrated_table2" /
                                          fmt::format("mix{}_{}_mu_r_{:g}", row.mix, c.material, value) /
                                          fmt::format("seed_{}", s))));
      mix.at_value.push_back(std::move(runs));
    }
    rep.calibrated.push_back(std::move(mix));
  }
}

// Table 2 with shape: every mix with its stone as spheres and as grains, on one bed, over the seeds.
void run_shaped_table2(const CaseRunner& cases, const std::vector<Table2Row>& table2, Reproduction& rep) {
  if (!cases.plan.shaped_table2) return;
  const ShapedTable2Plan& plan = *cases.plan.shaped_table2;
  for (const Table2Row& row : table2) {
    ShapedMix mix{row, {}, {}};
    for (const bool grains : {false, true}) {
      std::vector<std::string> sets = cases.no_particle_files();
      sets.insert(sets.end(), plan.bed.begin(), plan.bed.end());
      sets.push_back(fmt::format("particles.ca_fa={:.17g}", row.ca_fa));
      if (grains) sets.insert(sets.end(), plan.grains_sets.begin(), plan.grains_sets.end());
      SeedRuns& runs = grains ? mix.grains : mix.spheres;
      for (std::size_t s = 1; s <= cases.seeds; ++s)
        runs.add(keep_bed_if(false,
                             cases.campaign.run(shaped_label(row.mix, grains), cases.examples / plan.scenario, sets, s,
                                                cases.runs_dir / "shaped_table2" /
                                                    fmt::format("mix{}_{}", row.mix, grains ? "grains" : "spheres") /
                                                    fmt::format("seed_{}", s))));
    }
    rep.shaped.push_back(std::move(mix));
  }
}

// Every case of the plan through one campaign: Examples 1 and 2, the Table 2 mixes, the
// sensitivity variants and the studies.
void run_all(const CaseRunner& cases, const ReproduceInputs& inputs, Reproduction& rep) {
  run_examples(cases, inputs, rep);
  run_table2(cases, inputs.table2, rep);
  run_sensitivity(cases, rep);
  run_calibrated_table2(cases, inputs.table2, rep);
  run_shaped_table2(cases, inputs.table2, rep);
}

// Runs every case of the plan, each checked first (a study's later runs take hours to reach).
Reproduction run_cases(const ReproduceOptions& options, std::ostream& log) {
  const Plan plan = make_plan(options);
  const ReproduceInputs inputs = read_inputs(options.examples);
  check_study_inputs(plan, inputs);
  const std::size_t planned = total_runs(planned_cases(plan, inputs));
  const fs::path runs_dir = options.out / "runs";
  const auto seeds = static_cast<std::size_t>(plan.seeds);
  {
    Campaign checks(options.threads, options.quiet, log, planned, Campaign::Checkpoints::removed, Campaign::Mode::check);
    Reproduction unused;
    run_all(CaseRunner{checks, plan, inputs.examples, runs_dir, seeds}, inputs, unused);
    checks.clear_progress();
    if (!options.quiet)
      fmt::print(log, "aggpack reproduce: checked the {} runs' scenarios (their sizes and grains made) in {:.1f} s\n",
                 planned, checks.seconds());
  }
  Campaign campaign(options.threads, options.quiet, log, planned,
                    options.resume ? Campaign::Checkpoints::kept_and_resumed : Campaign::Checkpoints::kept);
  Reproduction rep;
  rep.plan = plan;
  rep.paper = inputs.paper;
  run_all(CaseRunner{campaign, plan, inputs.examples, runs_dir, seeds}, inputs, rep);
  rep.runs = campaign.runs_done();
  rep.resumed_runs = campaign.runs_resumed();
  rep.kept_checkpoints = campaign.kept_checkpoints();
  rep.threads = options.threads;
  rep.wall_clock_s = campaign.seconds();
  return rep;
}

}  // namespace
}  // namespace reproduction

using namespace reproduction;  // the parts of the report, private to this file and reproduce_*.cpp

ReproducePlan plan_reproduce(const ReproduceOptions& options) {
  const Plan plan = make_plan(options);
  const ReproduceInputs inputs = read_inputs(options.examples);
  check_study_inputs(plan, inputs);
  ReproducePlan p;
  p.examples = fs::absolute(options.examples).lexically_normal();
  p.seeds = plan.seeds;
  p.cases = planned_cases(plan, inputs);
  p.runs = total_runs(p.cases);
  return p;
}

std::string describe(const ReproducePlan& plan) {
  std::string text = fmt::format("examples: {}\n", plan.examples.string());
  for (const auto& [what, runs] : plan.cases) text += fmt::format("  {:3} x {}\n", runs, what);
  text += fmt::format("runs: {} ({} per case); nothing run or written (--dry-run)\n", plan.runs,
                      plan.seeds == 1 ? std::string("1 seed") : fmt::format("{} seeds", plan.seeds));
  return text;
}

nlohmann::json reproduce(const ReproduceOptions& options, std::ostream& log) {
  if (!options.quiet) fmt::print(log, "aggpack reproduce: scenarios from {}\n", options.examples.string());
  const Reproduction rep = run_cases(options, log);
  FigureSet figures(options.out);
  Document doc;
  doc.title = "Does aggpack reproduce Fu and Dekelbab (2003)?";
  nlohmann::json result;
  compose_header(doc, rep, options);
  compose_summary(doc, result, rep);
  compose_examples(doc, figures, rep);
  compose_protocols(doc, figures, result, rep);
  compose_table2(doc, figures, result, rep);
  compose_table2_materials(doc, figures, result, rep);
  compose_sensitivity(doc, result, rep);
  compose_calibrated_table2(doc, figures, result, rep);
  compose_shaped_table2(doc, figures, result, rep);
  compose_notes(doc, rep);
  result["aggpack_version"] = kVersion;
  result["mode"] = options.quick ? "quick" : "full";
  result["seeds"] = rep.plan.seeds;
  result["runs"] = rep.runs;
  result["resumed_runs"] = rep.resumed_runs;
  result["wall_clock_s"] = rep.wall_clock_s;
  result["command_line"] = options.command_line;
  result["examples_dir"] = fs::absolute(options.examples).lexically_normal().string();
  nlohmann::json figure_list = nlohmann::json::array();
  for (const auto& [file, content] : figures.files()) figure_list.push_back(file);
  result["figures"] = figure_list;
  nlohmann::json data_list = nlohmann::json::array();  // each plot's data, beside its SVG
  for (const auto& [file, content] : figures.data()) data_list.push_back(file);
  result["figure_data"] = data_list;

  figures.write();
  write_file_atomically(options.out / "report.md", to_markdown(doc));
  write_file_atomically(options.out / "report.html", to_html(doc, figures.files()));
  write_file_atomically(options.out / "reproduce.json", result.dump(2) + "\n");
  remove_checkpoints(rep.kept_checkpoints);
  if (!options.quiet)
    fmt::print(log, "report: {} and {} ({:.1f} min)\n", (options.out / "report.html").string(),
               (options.out / "report.md").string(), rep.wall_clock_s / 60.0);
  return result;
}

}  // namespace aggpack
