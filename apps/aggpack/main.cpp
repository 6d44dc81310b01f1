// The aggpack command line: parses arguments and calls the library. Exit codes:
// 0 success, 2 bad input (scenario, particle file, arguments), 1 internal failure.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <functional>
#include <iostream>
#include <limits>

#include "aggpack/core/error.hpp"
#include "aggpack/core/text.hpp"
#include "aggpack/core/units.hpp"
#include "aggpack/core/version.hpp"
#include "aggpack/io/particle_file.hpp"
#include "aggpack/run/analyze.hpp"
#include "aggpack/run/grading_report.hpp"
#include "aggpack/studies/calibration.hpp"
#include "aggpack/run/predictions.hpp"
#include "aggpack/io/atomic_file.hpp"
#include "aggpack/run/preflight.hpp"
#include "aggpack/studies/reproduce.hpp"
#include "aggpack/run/lammps_bridge.hpp"
#include "aggpack/run/run.hpp"
#include "aggpack/studies/sweep.hpp"
#include "aggpack/studies/whole_grading.hpp"
#include "examples_dir.hpp"

namespace {

// The one piece of global state: a signal handler can reach nothing else. SIGINT and SIGTERM
// ask the run to stop at its next safe point; a second signal ends the process at once.
aggpack::StopRequest g_stop;
extern "C" void request_stop(int signal_number) {
  if (g_stop.requested()) {
    std::signal(signal_number, SIG_DFL);
    std::raise(signal_number);
  }
  g_stop.request(signal_number);
}

// `aggpack run` and `aggpack resume`: a progress line unless quiet, SIGINT and SIGTERM
// stopping the run at its next safe point; exit 0, or 128 + the signal (130, 143).
int run_until_done_or_stopped(aggpack::RunOptions& options, const std::function<aggpack::RunResult()>& go) {
  aggpack::Progress progress =
      aggpack::Progress::wanted(options.quiet) ? aggpack::Progress(std::cerr) : aggpack::Progress();
  options.progress = &progress;
  options.stop = &g_stop;
  std::signal(SIGINT, request_stop);
  std::signal(SIGTERM, request_stop);
  const aggpack::RunResult result = go();
  options.progress = nullptr;
  return result.report.interrupted ? 128 + result.report.interrupted->signal_number : 0;
}

// A length given on the command line; a bare number is in `bare_unit` (metres per unit).
double length_argument(const std::string& text, const std::string& option, long double bare_unit = 1.0L) {
  std::string why;
  const auto v = aggpack::parse_length(text, &why, bare_unit);
  if (!v || *v <= 0.0) throw aggpack::InputError(fmt::format("{} {}: expected a positive length ({})", option, text, why));
  return *v;
}

// A seed in the range a scenario's `seed` takes, 0 to 2^63 - 1: never wrapped or saturated.
std::uint64_t seed_argument(const std::string& text) {
  std::int64_t value = -1;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || value < 0)
    throw aggpack::InputError(fmt::format("--seed {}: expected an integer from 0 to {} (as the scenario's seed)", text,
                                          std::numeric_limits<std::int64_t>::max()));
  return static_cast<std::uint64_t>(value);
}

// A number above 0. (CLI11's PositiveNumber would say "not in range 0.000000 to 1797...",
// its bound DBL_MAX in 309 digits.)
double positive_argument(const std::string& text, const std::string& option) {
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || !(value > 0.0) || !std::isfinite(value))
    throw aggpack::InputError(fmt::format("{} {}: expected a number above 0", option, text));
  return value;
}

// A count of 1 or more, such as a number of seeds.
int count_argument(const std::string& text, const std::string& option) {
  int value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || value < 1)
    throw aggpack::InputError(fmt::format("{} {}: expected a whole number, 1 or more", option, text));
  return value;
}

// A wall-clock interval in seconds, >= 0, as the TOML value of output.checkpoint_every.
std::string seconds_argument(const std::string& text) {
  double value = -1.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || !(value >= 0.0) || !(value <= 1e9))
    throw aggpack::InputError(
        fmt::format("--checkpoint-every {}: expected seconds of wall clock from 0 (every safe point) to 1e9", text));
  return fmt::format("{}", value);  // the shortest text that reads back as the same double
}

// The parts of "a,b,c", each as typed (without blanks around it).
std::vector<std::string> list_parts(const std::string& text) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (true) {
    const auto comma = text.find(',', start);
    const std::size_t length = comma == std::string::npos ? std::string::npos : comma - start;
    parts.emplace_back(aggpack::trim(std::string_view(text).substr(start, length)));
    if (comma == std::string::npos) return parts;
    start = comma + 1;
  }
}

// "a,b,c" as lengths (bare numbers in `bare_unit` metres), naming `option` in errors.
std::vector<double> lengths_argument(const std::string& text, const std::string& option, long double bare_unit = 1.0L) {
  std::vector<double> v;
  for (const std::string& part : list_parts(text)) {
    std::string why;
    const auto value = aggpack::parse_length(part, &why, bare_unit);
    if (!value) throw aggpack::InputError(fmt::format("{} {}: \"{}\": {}", option, text, part, why));
    v.push_back(*value);
  }
  return v;
}

aggpack::Box box_argument(const std::string& text, long double bare_unit) {
  const std::vector<double> v = lengths_argument(text, "--box", bare_unit);
  if (v.size() != 6 || !(v[3] > v[0] && v[4] > v[1] && v[5] > v[2]))
    throw aggpack::InputError(fmt::format("--box {}: expected xmin,ymin,zmin,xmax,ymax,zmax with max > min", text));
  return {{v[0], v[1], v[2]}, {v[3], v[4], v[5]}};
}

struct AnalyzeArguments {
  std::string file, unit = "m";
  std::vector<std::string> boxes, cubes;
  double tolerance = 1e-6;
  double overlap_tolerance = aggpack::ParticleSource{}.overlap_tolerance;
  bool soft_contacts = false;
  bool json = false;
  std::optional<std::int64_t> timestep;  // of a LAMMPS dump; none: the last
};

int analyze_command(const AnalyzeArguments& a) {
  const auto& [file, unit, boxes, cubes, tolerance, overlap_tolerance, soft_contacts, json, timestep] = a;
  const auto factor = aggpack::metres_per_unit(unit);
  if (!factor) throw aggpack::InputError(fmt::format("--length-unit {}: unknown unit; expected m, cm, mm, um, in, ft or yd", unit));
  if (boxes.size() + cubes.size() > aggpack::kMaxAnalysisBoxes)
    throw aggpack::InputError(fmt::format("--box, --cube: {} boxes; expected at most {} (each is a pass over every "
                                          "sphere)",
                                          boxes.size() + cubes.size(), aggpack::kMaxAnalysisBoxes));
  const aggpack::PackingFile packing =
      aggpack::read_packing_file(file, static_cast<double>(*factor), 1.0, aggpack::kDefaultMaxInputFileBytes, timestep);
  const aggpack::ParticleStore& particles = packing.particles;
  const auto container = aggpack::bounding_container(particles);
  const aggpack::RunLimits limits;  // the defaults: analyze has no scenario to raise them
  const auto overlap = aggpack::check_particle_overlaps(particles, container, overlap_tolerance, soft_contacts, file,
                                                        limits.max_grid_cells);
  const auto [r_min, r_max] = std::minmax_element(particles.radius.begin(), particles.radius.end());
  if (!particles.empty() &&
      !(aggpack::contact_reach_diameters(tolerance, *r_min, *r_max) <= aggpack::kMaxContactReachDiameters))
    throw aggpack::InputError(fmt::format(
        "--tolerance {}: the smallest sphere of {} (radius {:.4g} m) would look for contacts {:.4g} of its diameters "
        "away; expected at most {:g}, a tolerance of at most {:.4g}",
        tolerance, file, *r_min, aggpack::contact_reach_diameters(tolerance, *r_min, *r_max),
        aggpack::kMaxContactReachDiameters,
        tolerance * aggpack::kMaxContactReachDiameters / aggpack::contact_reach_diameters(tolerance, *r_min, *r_max)));
  aggpack::AnalysisRequest request;
  request.contact_tolerance = tolerance;
  request.max_profile_bins = limits.max_profile_bins;
  request.max_grid_cells = limits.max_grid_cells;
  // Bare numbers in --box and --cube are in the file's unit, like the file's own numbers.
  for (const auto& b : boxes) request.boxes.push_back(box_argument(b, *factor));
  for (const auto& c : cubes) request.cube_sides.push_back(length_argument(c, "--cube", *factor));
  const auto report = [&] {
    try {
      return aggpack::analyze_packing(particles, container, request);
    } catch (const aggpack::InputError& e) {
      throw aggpack::InputError(fmt::format("{}: {}", file, e.what()));
    }
  }();
  if (json) {
    auto j = aggpack::to_json(report);
    j["aggpack_version"] = aggpack::kVersion;
    j["file"] = file;
    j["format"] = packing.format;
    j["particle_count"] = particles.size();
    if (overlap.depth_over_radius > 1e-6) {
      j["largest_pair_overlap_rel"] = overlap.depth_over_radius;
      j["soft_contacts"] = soft_contacts;
    }
    const auto& cb = container.bounds;
    j["container"] = {{"lo", {cb.lo.x, cb.lo.y, cb.lo.z}}, {"hi", {cb.hi.x, cb.hi.y, cb.hi.z}}, {"periodic", false},
                      {"note", "bounding box of the spheres"}};
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  fmt::print("{} ({}): {} particles, d = {:.6g} .. {:.6g} m, free surface at {:.6g} m\n", file, packing.format, particles.size(),
             report.bed.d_min, report.bed.d_max, report.bed.surface);
  for (const auto& b : report.density.boxes)
    fmt::print("  box [{:.6g}, {:.6g}, {:.6g}] .. [{:.6g}, {:.6g}, {:.6g}] m: density {:.6f}\n", b.box.lo.x,
               b.box.lo.y, b.box.lo.z, b.box.hi.x, b.box.hi.y, b.box.hi.z, b.density);
  fmt::print("  mean density {:.6f}, sd {:.6f}\n", report.density.mean, report.density.sd);
  if (overlap.depth_over_radius > 1e-3)
    fmt::print("  spheres overlap by up to {:.3g} of the smaller radius (particles {} and {}): the shared volume "
               "counts twice\n", overlap.depth_over_radius, overlap.i, overlap.j);
  fmt::print("  mean coordination {:.4f} over {} spheres in the largest box\n", report.coordination.mean,
             report.coordination.particles_counted);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"aggpack: 3-D random packings of polydisperse spheres and concrete aggregate gradings"};
  app.set_version_flag("--version", aggpack::kVersion);
  app.require_subcommand(1);

  aggpack::RunOptions run;
  std::string scenario;
  std::string out_dir;
  std::string seed;
  std::string stop_after;
  auto* run_cmd = app.add_subcommand("run", "Run a scenario and write particles.csv, particles.vtp, summary.json");
  run_cmd->add_option("scenario", scenario, "Scenario file (TOML)")->required();
  auto* out_opt = run_cmd->add_option("--out", out_dir, "Output directory (overrides output.directory)");
  const auto thread_range = CLI::Range(0, aggpack::kMaxThreads, "0 (all cores) or 1 to 256");
  auto* seed_opt = run_cmd->add_option("--seed", seed, "Random seed, 0 to 2^63-1 (overrides seed)");
  run_cmd->add_option("--threads", run.threads, "OpenMP threads (default 0: all cores)")->check(thread_range);
  run_cmd->add_option("--set", run.overrides.set, "Override a scenario key: key.path=value (TOML value)");
  auto* stop_opt = run_cmd->add_option("--stop-after", stop_after, "Stop after this stage (deposition, dynamics)");
  run_cmd->add_flag("--quiet", run.quiet, "Print nothing on success");
  run_cmd->add_flag("--overwrite", run.overwrite,
                    "Write into an output folder that holds files no aggpack run wrote (they are left alone)");
  // Checkpoints: the CLI's options are overrides of the scenario's output keys, so that the
  // checkpoint records them with the rest.
  std::string checkpoint_every;
  auto* every_opt = run_cmd->add_option("--checkpoint-every", checkpoint_every,
                                        "Write checkpoint.bin at most every SECONDS of wall clock (0: at every safe "
                                        "point; overrides output.checkpoint_every, default 60)");
  bool no_checkpoint = false;
  run_cmd->add_flag("--no-checkpoint", no_checkpoint, "Write no checkpoint (output.checkpoint = false)")
      ->excludes(every_opt);

  std::string resume_dir;
  aggpack::RunOptions resume;
  std::string resume_every;
  auto* resume_cmd = app.add_subcommand(
      "resume", "Continue an interrupted or killed run from the checkpoint in its folder; same results, bit for bit");
  resume_cmd->add_option("run_dir", resume_dir, "The run's output folder (holding checkpoint.bin)")->required();
  resume_cmd->add_option("--threads", resume.threads, "OpenMP threads (default 0: all cores)")
      ->check(thread_range);
  auto* resume_every_opt =
      resume_cmd->add_option("--checkpoint-every", resume_every, "Checkpoint at most every SECONDS from now on");
  resume_cmd->add_flag("--quiet", resume.quiet, "Print nothing on success");

  std::vector<std::string> check_sets;
  auto* check_cmd = app.add_subcommand("check", "Validate a scenario without running it");
  check_cmd->add_option("scenario", scenario, "Scenario file (TOML)")->required();
  check_cmd->add_option("--set", check_sets, "Override a scenario key: key.path=value (TOML value)");

  AnalyzeArguments analyze;
  auto& [file, unit, boxes, cubes, tolerance, overlap_tolerance, soft_contacts, json, timestep] = analyze;
  auto* analyze_cmd = app.add_subcommand("analyze", "Measure density, coordination and profiles of a packing file");
  analyze_cmd->add_option("file", file, "Packing: CSV with header x,y,z,r (or diameter), whitespace x y z r, a LAMMPS dump or data file")
      ->required();
  analyze_cmd->add_option("--box", boxes, "Box xmin,ymin,zmin,xmax,ymax,zmax (lengths; bare numbers in --length-unit); repeatable");
  analyze_cmd->add_option("--cube", cubes, "Virtual cube side (bare number in --length-unit), placed as in docs/method.md section 2; repeatable");
  analyze_cmd->add_option("--length-unit", unit, "Unit of the file's numbers (m, mm, in, ...)");
  analyze_cmd->add_option("--tolerance", tolerance, "Relative contact tolerance for coordination")
      ->check(CLI::Range(0.0, 1.0));
  analyze_cmd->add_option("--overlap-tolerance", overlap_tolerance,
                          "Deepest overlap of two spheres accepted, / smaller radius (default 0.25)")
      ->check(CLI::Range(0.0, 1.0));
  analyze_cmd->add_flag("--soft-contacts", soft_contacts,
                        "The file comes from a soft-contact DEM: accept any overlap short of a centre inside another sphere");
  analyze_cmd->add_flag("--json", json, "Print machine-readable JSON");
  analyze_cmd->add_option("--timestep", timestep, "A LAMMPS dump's snapshot to read (default: the last)");

  aggpack::GradingQuery grading_query;
  std::string grading_unit, d_min_text, d_max_text;
  bool grading_json = false, grading_list = false;
  auto* grading_cmd = app.add_subcommand("grading", "Print and check a grading (or a coarse/fine mix) without a run");
  grading_cmd->add_option("grading", grading_query.grading, "A shipped grading name or a CSV sieve analysis");
  grading_cmd->add_option("--mix", grading_query.fine, "A fine grading (name or file) to blend with it");
  grading_cmd->add_option("--ca-fa", grading_query.ca_fa, "Coarse/fine volume ratio of the mix (default 1)");
  grading_cmd->add_option("--band", grading_query.band, "Check against astm_c33_fine, astm_c33_57 or astm_c33_67");
  auto* d_min_opt = grading_cmd->add_option("--d-min", d_min_text, "Cut-off below this size (length)");
  auto* d_max_opt = grading_cmd->add_option("--d-max", d_max_text, "Cut-off above this size (length)");
  grading_cmd->add_option("--length-unit", grading_unit,
                          "Unit of a bare 'opening' column in files (none by default: such a column is refused)");
  grading_cmd->add_flag("--json", grading_json, "Print machine-readable JSON");
  grading_cmd->add_flag("--list", grading_list, "List the shipped gradings and bands");

  aggpack::PredictRequest predict;
  bool predict_json = false;
  auto* predict_cmd = app.add_subcommand(
      "predict", "Analytic packing densities (CPM, Furnas, Desmond-Weeks) of a scenario's or a grading's sizes");
  predict_cmd->add_option("input", predict.input, "Scenario (.toml), a shipped grading's name or a CSV sieve analysis")
      ->required();
  predict_cmd->add_option("--mix", predict.fine, "A fine grading (name or file) to blend with the grading");
  std::string predict_ca_fa;
  auto* predict_ca_fa_opt = predict_cmd->add_option("--ca-fa", predict_ca_fa, "Coarse/fine volume ratio of the blend");
  predict_cmd->add_option("--k", predict.compaction_index, "CPM compaction index K (4.1 poured ... 9 vibrated and compressed)");
  predict_cmd->add_option("--process", predict.process, "K of a lab process: poured, rodded, vibrated, vibrated_compressed");
  predict_cmd->add_option("--beta", predict.beta, "CPM residual packing density of every class (default 0.72, spheres)");
  predict_cmd->add_option("--beta-fine", predict.beta_fine,
                          "CPM residual packing density of a blend's fine aggregate (default: --beta)");
  predict_cmd->add_option("--calibration", predict.calibration, "K and beta from a file aggpack calibrate wrote");
  predict_cmd->add_option("--set", predict.overrides.set, "Override a scenario key: key.path=value");

  aggpack::CalibrationOptions calibration;
  std::string calibration_out;
  auto* calibrate_cmd = app.add_subcommand(
      "calibrate", "CPM's K and beta from simulations of a scenario's protocol: a monosized bed and the scenario's mix");
  calibrate_cmd->add_option("scenario", calibration.scenario, "Scenario of two sizes or more (TOML)")->required();
  calibrate_cmd->add_option("--out", calibration_out, "The calibration file to write (JSON)")->required();
  calibrate_cmd->add_option("--seeds", calibration.seeds, "Seeds per packing (default 3)")->check(CLI::Range(1, 100));
  calibrate_cmd->add_option("--threads", calibration.threads, "OpenMP threads (default 0: all cores)")
      ->check(thread_range);
  calibrate_cmd->add_option("--set", calibration.overrides.set, "Override a scenario key: key.path=value");
  calibrate_cmd->add_flag("--quiet", calibration.quiet, "Print nothing on success");
  predict_cmd->add_flag("--json", predict_json, "Print machine-readable JSON");

  aggpack::WholeGradingOptions whole;
  std::string whole_cuts, whole_out, whole_plot;
  auto* whole_cmd = app.add_subcommand(
      "whole-grading", "The whole grading's density: a series of cut-offs simulated, CPM carrying it below them");
  whole_cmd->add_option("scenario", whole.scenario, "Scenario sampling a grading or a coarse/fine mix (TOML)")->required();
  whole_cmd->add_option("--cut-offs", whole_cuts, "Three or more d_min of the finest grading, e.g. \"0.1in,0.07in,0.04in\"")
      ->required();
  whole_cmd->add_option("--seeds", whole.seeds, "Seeds per cut-off (default 3)")->check(CLI::Range(1, 100));
  whole_cmd->add_option("--calibration", whole.calibration, "CPM's K and beta from a file aggpack calibrate wrote");
  whole_cmd->add_option("--out", whole_out, "Also write the estimate as JSON to this file");
  whole_cmd->add_option("--plot", whole_plot, "Also draw the density against the volume left out to this SVG file");
  whole_cmd->add_option("--threads", whole.threads, "OpenMP threads (default 0: all cores)")->check(thread_range);
  whole_cmd->add_option("--set", whole.overrides.set, "Override a scenario key: key.path=value");
  whole_cmd->add_flag("--quiet", whole.quiet, "Print only the estimate");

  aggpack::ReproduceOptions reproduce;
  reproduce.examples = default_examples_dir(argc > 0 ? argv[0] : nullptr);
  std::string reproduce_out = reproduce.out.string(), examples_dir = reproduce.examples.string();
  bool reproduce_dry_run = false;
  auto* reproduce_cmd = app.add_subcommand(
      "reproduce", "Run the paper's Examples 1, 2 and Table 2 over seeds and write report.html and report.md");
  reproduce_cmd->add_flag("--quick", reproduce.quick, "One seed, DEM cut at 0.25 s, short pours, three sensitivity rows (about two minutes)");
  std::string reproduce_seeds;
  auto* reproduce_seeds_opt =
      reproduce_cmd->add_option("--seeds", reproduce_seeds, "Seeds per case (default 3; 1 with --quick)");
  reproduce_cmd->add_flag("--settle-table2", reproduce.settle_table2,
                          "Also settle seed 1 of every Table 2 mix by DEM at E/1000 (hours: see BENCHMARKS.md)");
  reproduce_cmd->add_flag("--whole-grading", reproduce.whole_grading,
                          "Also run every Table 2 mix with the sand cut at 0.1, 0.07 and 0.02 in, for its whole grading "
                          "(minutes more: BENCHMARKS.md)");
  reproduce_cmd->add_flag("--resume", reproduce.resume,
                          "Continue an interrupted reproduce into the same --out: runs it finished or began are taken "
                          "up from their checkpoints, not run again");
  reproduce_cmd->add_option("--out", reproduce_out, "Output directory (default out/reproduce)");
  auto* examples_opt =
      reproduce_cmd->add_option("--examples", examples_dir, "Folder of the shipped scenarios and fu2003_table2.csv")
          ->capture_default_str();
  reproduce_cmd->add_flag("--dry-run", reproduce_dry_run,
                          "Print the scenarios' folder and the runs this reproduce would make; run nothing");
  reproduce_cmd->add_option("--threads", reproduce.threads, "OpenMP threads (default 0: all cores)")
      ->check(thread_range);
  reproduce_cmd->add_flag("--quiet", reproduce.quiet, "Print nothing on success, no progress line");

  aggpack::SweepOptions sweep;
  std::string sweep_out = sweep.out.string(), fa_text, sweep_stop;
  auto* sweep_cmd = app.add_subcommand("sweep", "Density against sand fraction for a coarse/fine mix: the densest blend");
  sweep_cmd->add_option("scenario", sweep.scenario, "Scenario with a coarse/fine mix (TOML)")->required();
  sweep_cmd->add_option("--fa", fa_text, "Fine aggregate %: FROM:TO:STEP or a list, e.g. 25:45:5 or 29,35,43")
      ->required();
  std::string sweep_seeds;
  auto* sweep_seeds_opt = sweep_cmd->add_option("--seeds", sweep_seeds, "Seeds per point (default 3)");
  sweep_cmd->add_option("--out", sweep_out, "Output directory (default out/sweep)");
  sweep_cmd->add_option("--set", sweep.sets, "Override a scenario key in every run: key.path=value");
  std::string sweep_cuts;
  sweep_cmd->add_option("--cut-offs", sweep_cuts,
                        "Three or more d_min of the fine grading: each blend's whole grading estimated from them");
  sweep_cmd->add_option("--calibration", sweep.calibration, "CPM's K and beta (with --cut-offs) from aggpack calibrate");
  auto* sweep_stop_opt =
      sweep_cmd->add_option("--stop-after", sweep_stop, "Stop each run after this stage (deposition, dynamics)");
  sweep_cmd->add_option("--threads", sweep.threads, "OpenMP threads (default 0: all cores)")->check(thread_range);
  sweep_cmd->add_flag("--resume", sweep.resume,
                      "Continue an interrupted sweep into the same --out: runs it finished or began are taken up "
                      "from their checkpoints, not run again");
  sweep_cmd->add_flag("--quiet", sweep.quiet, "Print nothing on success, no progress line");

  std::string export_scenario, export_out;
  std::vector<std::string> export_sets;
  bool export_tap = false;
  auto* export_cmd = app.add_subcommand(
      "export-lammps",
      "Write a bed and a LAMMPS deck: a scenario's first DEM step (settle, pour or tap), or a run's final bed to settle");
  export_cmd->add_option("scenario_or_run", export_scenario, "Scenario file (TOML), or the folder of a finished run")
      ->required();
  export_cmd->add_option("--out", export_out, "Folder for bed.data and the deck")->required();
  export_cmd->add_option("--set", export_sets, "Override a scenario key: key.path=value (TOML value)");
  export_cmd->add_flag("--tap", export_tap, "With a run's folder: a deck that taps the bed ([tapping]) instead");

  std::string import_file, import_scenario, import_out;
  std::optional<std::int64_t> import_timestep;
  aggpack::RunOptions import_options;
  auto* import_cmd = app.add_subcommand(
      "import-lammps", "Analyse a LAMMPS dump or data file in a scenario's container: aggpack's usual outputs");
  import_cmd->add_option("file", import_file, "LAMMPS text dump (ITEM: ...) or data file (atom_style sphere)")
      ->required();
  import_cmd->add_option("--scenario", import_scenario, "Scenario giving the container, material and analysis")
      ->required();
  auto* import_out_opt = import_cmd->add_option("--out", import_out, "Output directory (overrides output.directory)");
  import_cmd->add_option("--timestep", import_timestep, "The dump's snapshot to read (default: the last)");
  import_cmd->add_option("--set", import_options.overrides.set, "Override a scenario key: key.path=value");
  import_cmd->add_flag("--quiet", import_options.quiet, "Print nothing on success");

  // CLI11 would say "A subcommand is required" for a misspelt one: name it, with the list.
  if (argc > 1 && argv[1][0] != '-') {
    const std::string word = argv[1];
    std::vector<std::string> names;
    for (const CLI::App* sub : app.get_subcommands({})) names.push_back(sub->get_name());
    if (std::find(names.begin(), names.end(), word) == names.end()) {
      fmt::print(stderr, "aggpack: error: unknown subcommand '{}'; the subcommands are: {} (aggpack --help)\n", word,
                 fmt::join(names, ", "));
      return 2;
    }
  }

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }

  try {
    if (*run_cmd) {
      if (*out_opt) run.overrides.output_directory = out_dir;
      if (*seed_opt) run.overrides.seed = seed_argument(seed);
      if (*stop_opt) run.stop_after = stop_after;
      if (*every_opt) run.overrides.set.push_back("output.checkpoint_every=" + seconds_argument(checkpoint_every));
      if (no_checkpoint) run.overrides.set.push_back("output.checkpoint=false");
      return run_until_done_or_stopped(run, [&] { return aggpack::run_scenario(scenario, run, std::cout); });
    } else if (*export_cmd) {
      aggpack::ScenarioOverrides overrides;
      overrides.set = export_sets;
      aggpack::export_lammps(export_scenario, overrides, export_out, export_tap, std::cout);
    } else if (*import_cmd) {
      if (*import_out_opt) import_options.overrides.output_directory = import_out;
      aggpack::import_lammps(import_file, import_timestep, import_scenario, import_options, std::cout);
    } else if (*resume_cmd) {
      if (*resume_every_opt)
        resume.overrides.set.push_back("output.checkpoint_every=" + seconds_argument(resume_every));
      return run_until_done_or_stopped(resume, [&] { return aggpack::resume_run(resume_dir, resume, std::cout); });
    } else if (*reproduce_cmd) {
      reproduce.out = reproduce_out;
      if (examples_dir.empty())
        throw aggpack::InputError("reproduce: cannot tell where this aggpack is installed (no /proc/self/exe), so "
                                  "not where its shipped scenarios are: give --examples DIR");
      if (!*examples_opt && !std::filesystem::is_directory(examples_dir))
        throw aggpack::InputError(fmt::format(
            "reproduce: no shipped scenarios in {}, where an installed aggpack keeps them (share/aggpack/examples "
            "beside its bin/; cmake --install puts them there): give --examples DIR",
            examples_dir));
      reproduce.examples = examples_dir;
      if (*reproduce_seeds_opt) reproduce.seeds = count_argument(reproduce_seeds, "--seeds");
      if (reproduce_dry_run) {
        fmt::print("{}", aggpack::describe(aggpack::plan_reproduce(reproduce)));
        return 0;
      }
      for (int k = 0; k < argc; ++k) reproduce.command_line += (k ? " " : "") + std::string(k ? argv[k] : "aggpack");
      aggpack::reproduce(reproduce, std::cout);
    } else if (*sweep_cmd) {
      sweep.out = sweep_out;
      if (*sweep_seeds_opt) sweep.seeds = count_argument(sweep_seeds, "--seeds");
      sweep.fa_percent = aggpack::parse_fa_points(fa_text);
      if (!sweep_cuts.empty()) {
        sweep.cut_offs = lengths_argument(sweep_cuts, "--cut-offs");
        sweep.cut_off_texts = list_parts(sweep_cuts);
      }
      if (*sweep_stop_opt) sweep.stop_after = sweep_stop;
      aggpack::sweep(sweep, std::cout);
    } else if (*check_cmd) {
      aggpack::ScenarioOverrides overrides;
      overrides.set = check_sets;
      const auto sc = aggpack::check_scenario(scenario, overrides);
      fmt::print("{}: ok ({})\n", scenario, sc.title);
    } else if (*analyze_cmd) {
      return analyze_command(analyze);
    } else if (*whole_cmd) {
      whole.cut_offs = lengths_argument(whole_cuts, "--cut-offs");
      whole.cut_off_texts = list_parts(whole_cuts);
      // The files' folders are checked (and made) before the simulations, not after them.
      for (const auto& [option, target] : {std::pair{"--out", whole_out}, std::pair{"--plot", whole_plot}}) {
        if (target.empty()) continue;
        const std::filesystem::path out = target;
        if (std::filesystem::is_directory(out))
          throw aggpack::InputError(fmt::format("{} {}: a folder; expected a file's name", option, target));
        aggpack::check_output_directory(out.has_parent_path() ? out.parent_path() : ".", true);
      }
      const aggpack::WholeGradingEstimate e = aggpack::estimate_whole_grading(whole, std::cout);
      if (!whole_out.empty()) aggpack::write_file_atomically(whole_out, aggpack::to_json(e).dump(1) + "\n");
      if (!whole_plot.empty()) {
        const aggpack::Plot plot = aggpack::whole_grading_plot(e);
        aggpack::write_file_atomically(whole_plot, aggpack::svg_plot(plot));
        // The figure's data beside it, under the same name (not over a file named .csv itself).
        std::filesystem::path data = whole_plot;
        if (data.extension() != ".csv") aggpack::write_file_atomically(data.replace_extension(".csv"), aggpack::plot_csv(plot));
      }
      fmt::print("{}", aggpack::describe(e));
    } else if (*calibrate_cmd) {
      // The file's folder is checked (and made) before the simulations, not after them.
      const std::filesystem::path out = calibration_out;
      if (std::filesystem::is_directory(out))
        throw aggpack::InputError(fmt::format("--out {}: a folder; expected the calibration file's name", calibration_out));
      aggpack::check_output_directory(out.has_parent_path() ? out.parent_path() : ".", true);
      const aggpack::Calibration c = aggpack::calibrate(calibration, std::cout);
      aggpack::write_file_atomically(calibration_out, aggpack::to_json(c).dump(1) + "\n");
      if (!calibration.quiet)
        fmt::print("aggpack: calibrated CPM from {} ({}; {} seeds): K = {:.3g} ({:.3g} to {:.3g}), beta = {:.4f} ({:.4f} "
                   "to {:.4f}); monosized {:.4f} ± {:.4f}, mix {:.4f} ± {:.4f}; wrote {}\n",
                   c.scenario, c.protocol, c.seeds, c.compaction_index, c.compaction_low, c.compaction_high, c.beta,
                   c.beta_low, c.beta_high, c.monosized.mean, c.monosized.standard_error, c.mix.mean,
                   c.mix.standard_error, calibration_out);
    } else if (*predict_cmd) {
      if (*predict_ca_fa_opt) predict.ca_fa = positive_argument(predict_ca_fa, "--ca-fa");
      const aggpack::Predictions p = aggpack::predict(predict);
      if (predict_json) fmt::print("{}\n", aggpack::to_json(p).dump(1));
      else
        fmt::print("aggpack {}: analytic predictions for {}, no simulation\n  K = {:g}: {}\n  beta = {:g}: {}\n{}{}",
                   aggpack::kVersion, predict.input, p.parameters.compaction_index, p.parameters.compaction_source,
                   p.parameters.beta, p.parameters.beta_source,
                   p.parameters.beta_fine ? fmt::format("  beta of the fine aggregate = {:g}: {}\n", *p.parameters.beta_fine,
                                                        p.parameters.beta_fine_source)
                                          : "",
                   aggpack::describe(p));
    } else if (*grading_cmd) {
      if (grading_list) {
        for (const auto& n : aggpack::named_grading_names()) fmt::print("grading {}\n", n);
        for (const auto& n : aggpack::named_band_names()) fmt::print("band {}\n", n);
        return 0;
      }
      if (grading_query.grading.empty())
        throw aggpack::InputError("grading: give a shipped grading name or a CSV file (--list shows the names)");
      if (!grading_unit.empty()) {
        const auto factor = aggpack::metres_per_unit(grading_unit);
        if (!factor)
          throw aggpack::InputError(
              fmt::format("--length-unit {}: unknown unit; expected m, cm, mm, um, in, ft or yd", grading_unit));
        grading_query.length_unit = static_cast<double>(*factor);
      }
      if (*d_min_opt) grading_query.d_min = length_argument(d_min_text, "--d-min");
      if (*d_max_opt) grading_query.d_max = length_argument(d_max_text, "--d-max");
      const auto description = aggpack::describe_grading(grading_query);
      if (grading_json) std::cout << aggpack::to_json(description).dump(2) << "\n";
      else fmt::print("{}", aggpack::format_grading(description));
    }
  } catch (const aggpack::InputError& e) {
    fmt::print(stderr, "aggpack: error: {}\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "aggpack: internal error: {}\n", e.what());
    return 1;
  }
  return 0;
}
