// The subcommands that run series of runs: calibrate, whole-grading, reproduce and sweep.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "aggpack/blends/material_sweep.hpp"
#include "aggpack/core/error.hpp"
#include "aggpack/io/atomic_file.hpp"
#include "aggpack/io/material_file.hpp"
#include "aggpack/io/output_directory.hpp"
#include "aggpack/labtests/material_calibration.hpp"
#include "aggpack/run/preflight.hpp"
#include "aggpack/studies/calibration.hpp"
#include "aggpack/studies/dem_calibration.hpp"
#include "aggpack/studies/reproduce.hpp"
#include "aggpack/studies/sweep.hpp"
#include "aggpack/studies/whole_grading.hpp"
#include "arguments.hpp"
#include "commands.hpp"
#include "examples_dir.hpp"

namespace {

// The folder of a file to write is checked (and made) before the simulations, not after them.
void check_output_file(const std::string& option, const std::string& target, std::string_view expected) {
  const std::filesystem::path out = target;
  if (std::filesystem::is_directory(out))
    throw aggpack::InputError(fmt::format("{} {}: a folder; expected {}", option, target, expected));
  aggpack::check_output_directory(out.has_parent_path() ? out.parent_path() : ".", true);
}

struct CalibrateArguments {
  aggpack::CalibrationOptions calibration;
  aggpack::DemCalibrationOptions dem;
  bool by_dem = false;
  std::optional<double> measured;
  std::string range, out;
  std::string test, method;  // --test: the positional is a material file, fitted to its lab test
};

// calibrate MATERIAL --test c29|c1252 --method M: the material's contact parameter fitted to its
// own lab test; writes the calibrated material file (and the search beside it, FILE.json).
int calibrate_on_test(CalibrateArguments& a) {
  aggpack::MaterialCalibrationOptions o;
  o.test.material = a.calibration.scenario;
  const auto test = aggpack::value_of(aggpack::kLabTestNames, a.test);
  if (!test) throw aggpack::InputError(fmt::format("--test {}: expected c29 or c1252", a.test));
  o.test.test = *test;
  o.test.method = a.method;
  o.test.seeds = a.calibration.seeds;
  o.test.threads = a.calibration.threads;
  o.test.quiet = a.calibration.quiet;
  o.test.set = a.calibration.overrides.set;
  if (a.dem.fit.size() > 1) throw aggpack::InputError("--fit: one parameter: one lab value fixes one");
  if (!a.dem.fit.empty()) o.parameter = a.dem.fit.front();
  if (!a.range.empty()) o.range = numbers_argument(a.range, "--range");
  o.max_evaluations = a.dem.max_evaluations;
  const std::filesystem::path material = o.test.material;
  const std::filesystem::path out =
      a.out.empty() ? material.parent_path() / (material.stem().string() + "_calibrated.toml")
                    : std::filesystem::path(a.out);
  check_output_file("--out", out.string(), "the calibrated material file's name");
  const std::string original = aggpack::read_scenario_text(material);  // the same limits as a scenario's
  const aggpack::MaterialCalibration c = aggpack::calibrate_material(o, std::cout);
  const std::string text = aggpack::calibrated_material_text(c, original);
  aggpack::parse_material_file(text, out);  // what is written reads back
  aggpack::write_file_atomically(out, text);
  aggpack::write_file_atomically(out.string() + ".json", aggpack::to_json(c).dump(1) + "\n");
  if (!o.test.quiet)
    fmt::print("aggpack: calibrated {} of {} = {:.4g} (band {:.4g} to {:.4g}{}) to its {} {} {:.6g} {}, from {} values x "
               "{} seeds; wrote {} and {}.json\n",
               c.parameter, c.plan.material.name, c.search.value, c.search.band_low, c.search.band_high,
               c.search.band_clipped ? ", cut at the range's end" : "", c.plan.standard, c.plan.method, c.lab_value,
               c.plan.test == aggpack::LabTestKind::C29 ? "kg/m3" : "% voids", c.search.evaluations.size(), c.seeds,
               out.string(), out.string());
  if (!c.search.converged)
    fmt::print(stderr, "aggpack: warning: NOT CONVERGED: no value's seed mean came within its standard error of the "
                       "lab's value in {} values; the value is interpolated between the last two (raise --max-runs)\n",
               c.search.evaluations.size());
  return 0;
}

int calibrate_by_dem(CalibrateArguments& a) {
  if (!a.measured)
    throw aggpack::InputError("--dem: --measured is missing: the measured packing density of the scenario's "
                              "bed, which the fit reproduces");
  aggpack::DemCalibrationOptions& d = a.dem;
  d.runs = a.calibration;
  d.measured = *a.measured;
  if (!a.range.empty()) d.range = numbers_argument(a.range, "--range");
  const aggpack::DemCalibration c = aggpack::calibrate_dem(d, std::cout);
  aggpack::write_file_atomically(a.out, aggpack::to_json(c).dump(1) + "\n");
  if (!d.runs.quiet)
    fmt::print("aggpack: calibrated {} of {} = {:.4g} (band {:.4g} to {:.4g}{}) to the measured {:.4f}, from {} values "
               "x {} seeds of {} ({}); wrote {}\n",
               c.parameter, fmt::join(c.materials, " and "), c.search.value, c.search.band_low, c.search.band_high,
               c.search.band_clipped ? ", cut at the range's end" : "", c.measured, c.search.evaluations.size(),
               c.seeds, c.scenario, c.protocol, a.out);
  if (!c.search.converged)  // even when quiet: the value is an interpolation the runs did not confirm
    fmt::print(stderr, "aggpack: warning: NOT CONVERGED: no value's seed mean came within its standard error of the "
                       "measurement in {} values; the value is interpolated between the last two (raise --max-runs)\n",
               c.search.evaluations.size());
  return 0;
}

Subcommand add_calibrate(CLI::App& app) {
  using Arguments = CalibrateArguments;
  const auto a = std::make_shared<Arguments>();
  aggpack::CalibrationOptions& calibration = a->calibration;
  auto* cmd = app.add_subcommand(
      "calibrate",
      "CPM's K and beta from simulations of a scenario's protocol: a monosized bed and the scenario's mix; with --dem, "
      "a material's rolling friction or friction fitted by DEM runs to a measured density");
  cmd->add_option("scenario", calibration.scenario,
                  "Scenario of two sizes or more (TOML); with --test, the material file")
      ->required();
  cmd->add_option("--out", a->out,
                  "The calibration file to write (JSON); with --test, the calibrated material file (default "
                  "<material>_calibrated.toml beside it)");
  cmd->add_option("--seeds", calibration.seeds, "Seeds per packing (default 3)")->check(CLI::Range(1, 100));
  add_threads_option(cmd, calibration.threads);
  cmd->add_option("--set", calibration.overrides.set, "Override a scenario key: key.path=value");
  cmd->add_flag("--quiet", calibration.quiet, "Print nothing on success");
  auto* dem = cmd->add_flag("--dem", a->by_dem,
                            "Fit a contact parameter by DEM runs of the scenario's own protocol to --measured");
  cmd->add_option("--measured", a->measured, "With --dem: the measured packing density of the scenario's bed")
      ->needs(dem);
  auto* test = cmd->add_option("--test", a->test,
                               "Fit the material file's contact parameter to its lab test: c29 or c1252")
                   ->excludes(dem);
  cmd->add_option("--method", a->method, "With --test: the test's method (rodding, ..., A, B, C)")->needs(test);
  cmd->add_option("--fit", a->dem.fit,
                  "With --dem or --test: rolling_friction (--dem's default) or friction; --test's default: "
                  "rolling_friction for spheres, friction for grains")
      ->delimiter(',');
  cmd->add_option("--materials", a->dem.materials,
                  "With --dem: the material(s) whose value is fitted (default: the bed's one material)")
      ->delimiter(',')
      ->needs(dem);
  cmd->add_flag("--shared", a->dem.shared, "With --dem: one value for every material of --materials")->needs(dem);
  cmd->add_option("--range", a->range,
                  "With --dem or --test: LOW,HIGH searched (default 0,0.5 for rolling_friction, 0.1,1 for friction)");
  cmd->add_option("--max-runs", a->dem.max_evaluations,
                  "With --dem or --test: values simulated at most, the range's ends included (default 6; each over "
                  "--seeds)");
  return {cmd, [a, cmd] {
            if (!a->test.empty()) {
              if (cmd->count("--fit") == 0) a->dem.fit.clear();  // --test's default depends on the material
              return calibrate_on_test(*a);
            }
            for (const char* option : {"--fit", "--range", "--max-runs"})
              if (!a->by_dem && cmd->count(option) > 0)
                throw aggpack::InputError(fmt::format("{}: only with --dem or --test", option));
            if (a->out.empty()) throw aggpack::InputError("--out is missing: the calibration file to write (JSON)");
            check_output_file("--out", a->out, "the calibration file's name");
            if (a->by_dem) return calibrate_by_dem(*a);
            const aggpack::Calibration c = aggpack::calibrate(a->calibration, std::cout);
            aggpack::write_file_atomically(a->out, aggpack::to_json(c).dump(1) + "\n");
            if (!a->calibration.quiet)
              fmt::print("aggpack: calibrated CPM from {} ({}; {} seeds): K = {:.3g} ({:.3g} to {:.3g}), beta = {:.4f} "
                         "({:.4f} to {:.4f}); monosized {:.4f} ± {:.4f}, mix {:.4f} ± {:.4f}; wrote {}\n",
                         c.scenario, c.protocol, c.seeds, c.compaction_index, c.compaction_low, c.compaction_high,
                         c.beta, c.beta_low, c.beta_high, c.monosized.mean, c.monosized.standard_error, c.mix.mean,
                         c.mix.standard_error, a->out);
            return 0;
          }};
}

struct WholeGradingArguments {
  aggpack::WholeGradingOptions whole;
  std::string cuts, out, plot;
  std::vector<std::string> calibrations;
};

int whole_grading_command(WholeGradingArguments& a) {
  const CalibrationArguments calibrations = calibration_arguments(a.calibrations);
  a.whole.calibration = calibrations.cpm;
  if (calibrations.calibrated_by) {
    a.whole.overrides.set.push_back(*calibrations.calibrated_by);
    a.whole.overrides.typed_as[*calibrations.calibrated_by] = calibrations.typed;
  }
  a.whole.cut_offs = lengths_argument(a.cuts, "--cut-offs");
  a.whole.cut_off_texts = list_parts(a.cuts);
  for (const auto& [option, target] : {std::pair{"--out", a.out}, std::pair{"--plot", a.plot}})
    if (!target.empty()) check_output_file(option, target, "a file's name");
  const aggpack::WholeGradingEstimate e = aggpack::estimate_whole_grading(a.whole, std::cout);
  if (!a.out.empty()) aggpack::write_file_atomically(a.out, aggpack::to_json(e).dump(1) + "\n");
  if (!a.plot.empty()) {
    const aggpack::Plot plot = aggpack::whole_grading_plot(e);
    aggpack::write_file_atomically(a.plot, aggpack::svg_plot(plot));
    // The figure's data beside it, under the same name (not over a file named .csv itself).
    std::filesystem::path data = a.plot;
    if (data.extension() != ".csv") aggpack::write_file_atomically(data.replace_extension(".csv"), aggpack::plot_csv(plot));
  }
  fmt::print("{}", aggpack::describe(e));
  return 0;
}

Subcommand add_whole_grading(CLI::App& app) {
  const auto a = std::make_shared<WholeGradingArguments>();
  aggpack::WholeGradingOptions& whole = a->whole;
  auto* cmd = app.add_subcommand(
      "whole-grading", "The whole grading's density: a series of cut-offs simulated, CPM carrying it below them");
  cmd->add_option("scenario", whole.scenario, "Scenario sampling a grading or a coarse/fine mix (TOML)")->required();
  cmd->add_option("--cut-offs", a->cuts, "Three or more d_min of the finest grading, e.g. \"0.1in,0.07in,0.04in\"")
      ->required();
  cmd->add_option("--seeds", whole.seeds, "Seeds per cut-off (default 3)")->check(CLI::Range(1, 100));
  cmd->add_option("--calibration", a->calibrations,
                  "A file aggpack calibrate wrote: CPM's K and beta, or (with --dem) fitted keys for every run");
  cmd->add_option("--out", a->out, "Also write the estimate as JSON to this file");
  cmd->add_option("--plot", a->plot, "Also draw the density against the volume left out to this SVG file");
  add_threads_option(cmd, whole.threads);
  cmd->add_option("--set", whole.overrides.set, "Override a scenario key: key.path=value");
  cmd->add_flag("--quiet", whole.quiet, "Print only the estimate");
  return {cmd, [a] { return whole_grading_command(*a); }};
}

struct ReproduceArguments {
  aggpack::ReproduceOptions reproduce;
  std::string out, examples_dir, seeds;
  bool dry_run = false;
  CLI::Option* examples_opt = nullptr;
  CLI::Option* seeds_opt = nullptr;
};

int reproduce_command(ReproduceArguments& a, int argc, char** argv) {
  aggpack::ReproduceOptions& reproduce = a.reproduce;
  reproduce.out = a.out;
  if (a.examples_dir.empty())
    throw aggpack::InputError("reproduce: cannot tell where this aggpack is installed (no /proc/self/exe), so "
                              "not where its shipped scenarios are: give --examples DIR");
  if (!*a.examples_opt && !std::filesystem::is_directory(a.examples_dir))
    throw aggpack::InputError(fmt::format(
        "reproduce: no shipped scenarios in {}, where an installed aggpack keeps them (share/aggpack/examples "
        "beside its bin/; cmake --install puts them there): give --examples DIR",
        a.examples_dir));
  reproduce.examples = a.examples_dir;
  // Beside Table 2: the shipped stone and sand's curve, predicted from their lab numbers.
  const std::filesystem::path materials = reproduce.examples / "materials";
  if (std::filesystem::exists(materials / "crushed_stone_19mm.toml") &&
      std::filesystem::exists(materials / "natural_sand.toml"))
    reproduce.table2_materials = aggpack::lab_route_curve(materials / "crushed_stone_19mm.toml",
                                                          materials / "natural_sand.toml", "rodded", 20.0, 60.0);
  if (*a.seeds_opt) reproduce.seeds = count_argument(a.seeds, "--seeds");
  if (a.dry_run) {
    fmt::print("{}", aggpack::describe(aggpack::plan_reproduce(reproduce)));
    return 0;
  }
  for (int k = 0; k < argc; ++k) reproduce.command_line += (k ? " " : "") + std::string(k ? argv[k] : "aggpack");
  aggpack::reproduce(reproduce, std::cout);
  return 0;
}

Subcommand add_reproduce(CLI::App& app, int argc, char** argv) {
  const auto a = std::make_shared<ReproduceArguments>();
  aggpack::ReproduceOptions& reproduce = a->reproduce;
  reproduce.examples = default_examples_dir(argc > 0 ? argv[0] : nullptr);
  a->out = reproduce.out.string();
  a->examples_dir = reproduce.examples.string();
  auto* cmd = app.add_subcommand(
      "reproduce", "Run the paper's Examples 1, 2 and Table 2 over seeds and write report.html and report.md");
  cmd->add_flag("--quick", reproduce.quick, "One seed, DEM cut at 0.25 s, short pours, three sensitivity rows (about two minutes)");
  a->seeds_opt = cmd->add_option("--seeds", a->seeds, "Seeds per case (default 3; 1 with --quick)");
  cmd->add_flag("--settle-table2", reproduce.settle_table2,
                "Also settle seed 1 of every Table 2 mix by DEM at E/1000 (hours: see BENCHMARKS.md)");
  cmd->add_flag("--whole-grading", reproduce.whole_grading,
                "Also run every Table 2 mix with the sand cut at 0.1, 0.07 and 0.02 in, for its whole grading "
                "(minutes more: BENCHMARKS.md)");
  cmd->add_flag("--calibrated-table2", reproduce.calibrated_table2,
                "Also predict Table 2 from one calibration mix: every mix poured with stone and sand at 4 values of "
                "the sand's rolling friction on a reduced bed (about 40 minutes a seed on two cores)");
  cmd->add_flag("--shaped-table2", reproduce.shaped_table2,
                "Also run Table 2 with shape: every mix poured on one reduced bed with its stone as spheres and as "
                "rigid grains of crushed stone (flakiness 18 %) (hours a seed on two cores: docs/validation.md)");
  cmd->add_flag("--resume", reproduce.resume,
                "Continue an interrupted reproduce into the same --out: runs it finished or began are taken "
                "up from their checkpoints, not run again");
  cmd->add_option("--out", a->out, "Output directory (default out/reproduce)");
  a->examples_opt =
      cmd->add_option("--examples", a->examples_dir, "Folder of the shipped scenarios and fu2003_table2.csv")
          ->capture_default_str();
  cmd->add_flag("--dry-run", a->dry_run,
                "Print the scenarios' folder and the runs this reproduce would make; run nothing");
  add_threads_option(cmd, reproduce.threads);
  cmd->add_flag("--quiet", reproduce.quiet, "Print nothing on success, no progress line");
  return {cmd, [a, argc, argv] { return reproduce_command(*a, argc, argv); }};
}

struct SweepArguments {
  aggpack::SweepOptions sweep;
  std::vector<std::filesystem::path> inputs;  // a scenario; or two material files
  std::string out, fa, seeds, cuts, stop_after;
  std::vector<std::string> calibrations;
  std::string check, process = "rodded", route = "auto";  // materials only
};

// sweep STONE.toml SAND.toml: the curve predicted, the DEM only at --check's points.
int sweep_materials_command(const SweepArguments& a, const CLI::App& cmd) {
  for (const char* option : {"--set", "--cut-offs", "--calibration", "--stop-after", "--resume"})
    if (cmd.count(option) > 0)
      throw aggpack::InputError(fmt::format(
          "sweep of two materials: {} is a scenario's option; expected --fa, --check, --process, --route, --seeds",
          option));
  aggpack::MaterialSweepOptions o;
  o.blend.materials = a.inputs;
  o.blend.sweep_percents = aggpack::parse_fa_points(a.fa);
  o.blend.process = aggpack::blend_process(a.process, "--process");
  if (a.route != "auto" && a.route != "lab" && a.route != "simulation")
    throw aggpack::InputError(fmt::format("--route {}: expected auto, lab or simulation", a.route));
  o.blend.route = a.route;
  if (!a.seeds.empty()) o.blend.beds.seeds = count_argument(a.seeds, "--seeds");
  o.blend.beds.threads = a.sweep.threads;
  o.blend.beds.quiet = a.sweep.quiet;
  if (!a.check.empty()) o.check_percents = numbers_argument(a.check, "--check");
  aggpack::check_output_directory(a.out, true, "--out");
  const aggpack::MaterialSweep s = aggpack::sweep_materials(o, std::cerr);
  const std::filesystem::path out = a.out;
  aggpack::write_file_atomically(out / "sweep.json", aggpack::to_json(s).dump(1) + "\n");
  aggpack::write_file_atomically(out / "sweep.csv", aggpack::sweep_csv(s));
  aggpack::write_file_atomically(out / "sweep.svg", aggpack::blend_svg(s.predicted, s.check ? &*s.check : nullptr));
  if (!a.sweep.quiet)
    fmt::print("{}{}wrote {}, sweep.csv and sweep.svg\n", aggpack::describe(s.predicted),
               s.check ? aggpack::describe(*s.check) : "", (out / "sweep.json").string());
  return 0;
}

int sweep_scenario_command(SweepArguments& a, const CLI::App& cmd) {
  for (const char* option : {"--check", "--process", "--route"})
    if (cmd.count(option) > 0)
      throw aggpack::InputError(fmt::format(
          "sweep of a scenario: {} is a sweep of two materials' option (sweep STONE.toml SAND.toml); a scenario's "
          "sweep simulates every point",
          option));
  aggpack::SweepOptions& options = a.sweep;
  options.scenario = a.inputs.front();
  options.out = a.out;
  if (!a.seeds.empty()) options.seeds = count_argument(a.seeds, "--seeds");
  options.fa_percent = aggpack::parse_fa_points(a.fa);
  if (!a.cuts.empty()) {
    options.cut_offs = lengths_argument(a.cuts, "--cut-offs");
    options.cut_off_texts = list_parts(a.cuts);
  }
  if (!a.stop_after.empty()) options.stop_after = a.stop_after;
  const CalibrationArguments calibrations = calibration_arguments(a.calibrations);
  options.calibration = calibrations.cpm;
  if (calibrations.calibrated_by) {
    options.sets.push_back(*calibrations.calibrated_by);
    options.typed_as[*calibrations.calibrated_by] = calibrations.typed;
  }
  aggpack::sweep(options, std::cout);
  return 0;
}

Subcommand add_sweep(CLI::App& app) {
  const auto a = std::make_shared<SweepArguments>();
  aggpack::SweepOptions& sweep = a->sweep;
  a->out = sweep.out.string();
  auto* cmd =
      app.add_subcommand("sweep",
                         "Density against sand fraction: a scenario's coarse/fine mix simulated at every point, or two "
                         "materials' blends predicted (the DEM only at --check's points)");
  cmd->add_option("inputs", a->inputs,
                  "Scenario with a coarse/fine mix (TOML); or two material files, coarse then fine")
      ->required()
      ->expected(1, 2);
  cmd->add_option("--fa", a->fa, "Fine aggregate %: FROM:TO:STEP or a list, e.g. 25:45:5 or 29,35,43")->required();
  cmd->add_option("--seeds", a->seeds, "Seeds per point (default 3); of materials: of each bed");
  cmd->add_option("--out", a->out, "Output directory (default out/sweep)");
  cmd->add_option("--check", a->check,
                  "Two materials: P1,P2,...: the DEM of the blend (periodic bed) at these fine percents only");
  cmd->add_option("--process", a->process, "Two materials: loose, rodded or vibrated, the K of CPM (default rodded)");
  cmd->add_option("--route", a->route,
                  "Two materials: their betas by auto (calibrated: simulation, else lab), lab or simulation");
  cmd->add_option("--set", sweep.sets, "Override a scenario key in every run: key.path=value");
  cmd->add_option("--cut-offs", a->cuts,
                  "Three or more d_min of the fine grading: each blend's whole grading estimated from them");
  cmd->add_option("--calibration", a->calibrations,
                  "A file aggpack calibrate wrote: CPM's K and beta (with --cut-offs), or (with --dem) fitted keys for "
                  "every run");
  cmd->add_option("--stop-after", a->stop_after, "Stop each run after this stage (deposition, dynamics)");
  add_threads_option(cmd, sweep.threads);
  cmd->add_flag("--resume", sweep.resume,
                "Continue an interrupted sweep into the same --out: runs it finished or began are taken up "
                "from their checkpoints, not run again");
  cmd->add_flag("--quiet", sweep.quiet, "Print nothing on success, no progress line");
  return {cmd, [a, cmd] {
            return a->inputs.size() == 2 ? sweep_materials_command(*a, *cmd) : sweep_scenario_command(*a, *cmd);
          }};
}

}  // namespace

// A braced list is evaluated in order: the subcommands are added, and listed, in this order.
std::vector<Subcommand> add_study_commands(CLI::App& app, int argc, char** argv) {
  return {add_calibrate(app), add_whole_grading(app), add_reproduce(app, argc, argv), add_sweep(app)};
}
