// The subcommands of one run: run, resume and check; export-lammps and import-lammps.
#include <csignal>
#include <functional>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/run/lammps_steps.hpp"
#include "aggpack/run/preflight.hpp"
#include "aggpack/run/run.hpp"
#include "aggpack/run/run_grains.hpp"
#include "arguments.hpp"
#include "commands.hpp"

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

}  // namespace

const aggpack::StopRequest& stop_on_signals() {
  std::signal(SIGINT, request_stop);
  std::signal(SIGTERM, request_stop);
  return g_stop;
}

namespace {

// `aggpack run` and `aggpack resume`: a progress line unless quiet, SIGINT and SIGTERM
// stopping the run at its next safe point; exit 0, or 128 + the signal (130, 143).
int run_until_done_or_stopped(aggpack::RunOptions& options, const std::function<aggpack::RunResult()>& go) {
  aggpack::Progress progress =
      aggpack::Progress::wanted(options.quiet) ? aggpack::Progress(std::cerr) : aggpack::Progress();
  options.progress = &progress;
  options.stop = &stop_on_signals();
  const aggpack::RunResult result = go();
  options.progress = nullptr;
  return result.report.interrupted ? 128 + result.report.interrupted->signal_number : 0;
}

Subcommand add_run(CLI::App& app) {
  struct Arguments {
    aggpack::RunOptions run;
    std::string scenario, out_dir, seed, stop_after, checkpoint_every;
    std::vector<std::string> calibrations;
    bool no_checkpoint = false;
  };
  const auto a = std::make_shared<Arguments>();
  auto* cmd = app.add_subcommand("run", "Run a scenario and write particles.csv, particles.vtp, summary.json");
  cmd->add_option("scenario", a->scenario, "Scenario file (TOML)")->required();
  auto* out_opt = cmd->add_option("--out", a->out_dir, "Output directory (overrides output.directory)");
  auto* seed_opt = cmd->add_option("--seed", a->seed, "Random seed, 0 to 2^63-1 (overrides seed)");
  add_threads_option(cmd, a->run.threads);
  cmd->add_option("--set", a->run.overrides.set, "Override a scenario key: key.path=value (TOML value)");
  cmd->add_option("--calibration", a->calibrations,
                  "A file aggpack calibrate wrote: with --dem, its fitted keys replace the scenario's (calibrated_by; "
                  "several may be given); else CPM's K and beta for the predictions (models.calibration)");
  auto* stop_opt = cmd->add_option("--stop-after", a->stop_after, "Stop after this stage (deposition, dynamics)");
  cmd->add_flag("--quiet", a->run.quiet, "Print nothing on success");
  cmd->add_flag("--overwrite", a->run.overwrite,
                "Write into an output folder that holds files no aggpack run wrote (they are left alone)");
  // Checkpoints: the CLI's options are overrides of the scenario's output keys, so that the
  // checkpoint records them with the rest.
  auto* every_opt = cmd->add_option("--checkpoint-every", a->checkpoint_every,
                                    "Write checkpoint.bin at most every SECONDS of wall clock (0: at every safe "
                                    "point; overrides output.checkpoint_every, default 60)");
  cmd->add_flag("--no-checkpoint", a->no_checkpoint, "Write no checkpoint (output.checkpoint = false)")
      ->excludes(every_opt);
  return {cmd, [a, out_opt, seed_opt, stop_opt, every_opt] {
            aggpack::RunOptions& run = a->run;
            if (*out_opt) run.overrides.output_directory = a->out_dir;
            if (*seed_opt) run.overrides.seed = seed_argument(a->seed);
            if (*stop_opt) run.stop_after = a->stop_after;
            add_run_calibrations(a->calibrations, run.overrides);
            if (*every_opt)
              run.overrides.set.push_back("output.checkpoint_every=" + seconds_argument(a->checkpoint_every));
            if (a->no_checkpoint) run.overrides.set.push_back("output.checkpoint=false");
            return run_until_done_or_stopped(run, [&] { return aggpack::run_scenario(a->scenario, run, std::cout); });
          }};
}

Subcommand add_resume(CLI::App& app) {
  struct Arguments {
    std::string run_dir, checkpoint_every;
    aggpack::RunOptions resume;
  };
  const auto a = std::make_shared<Arguments>();
  auto* cmd = app.add_subcommand(
      "resume", "Continue an interrupted or killed run from the checkpoint in its folder; same results, bit for bit");
  cmd->add_option("run_dir", a->run_dir, "The run's output folder (holding checkpoint.bin)")->required();
  add_threads_option(cmd, a->resume.threads);
  auto* every_opt =
      cmd->add_option("--checkpoint-every", a->checkpoint_every, "Checkpoint at most every SECONDS from now on");
  cmd->add_flag("--quiet", a->resume.quiet, "Print nothing on success");
  return {cmd, [a, every_opt] {
            aggpack::RunOptions& resume = a->resume;
            if (*every_opt)
              resume.overrides.set.push_back("output.checkpoint_every=" + seconds_argument(a->checkpoint_every));
            return run_until_done_or_stopped(resume,
                                             [&] { return aggpack::resume_run(a->run_dir, resume, std::cout); });
          }};
}

Subcommand add_check(CLI::App& app) {
  struct Arguments {
    std::string scenario;
    std::vector<std::string> sets;
  };
  const auto a = std::make_shared<Arguments>();
  auto* cmd = app.add_subcommand("check", "Validate a scenario without running it");
  cmd->add_option("scenario", a->scenario, "Scenario file (TOML)")->required();
  cmd->add_option("--set", a->sets, "Override a scenario key: key.path=value (TOML value)");
  return {cmd, [a] {
            aggpack::ScenarioOverrides overrides;
            overrides.set = a->sets;
            // The grains' templates can take minutes: their count on stderr as they are made.
            aggpack::Progress progress =
                aggpack::Progress::wanted(false) ? aggpack::Progress(std::cerr) : aggpack::Progress();
            const auto sc =
                aggpack::check_scenario(a->scenario, overrides, aggpack::templates_shown_on(progress, nullptr));
            progress.clear();
            fmt::print("{}: ok ({})\n", a->scenario, sc.title);
            return 0;
          }};
}

Subcommand add_export_lammps(CLI::App& app) {
  struct Arguments {
    std::string scenario_or_run, out;
    std::vector<std::string> sets;
    bool tap = false;
  };
  const auto a = std::make_shared<Arguments>();
  auto* cmd = app.add_subcommand(
      "export-lammps",
      "Write a bed and a LAMMPS deck: a scenario's first DEM step (settle, pour or tap), or a run's final bed to settle");
  cmd->add_option("scenario_or_run", a->scenario_or_run, "Scenario file (TOML), or the folder of a finished run")
      ->required();
  cmd->add_option("--out", a->out, "Folder for bed.data and the deck")->required();
  cmd->add_option("--set", a->sets, "Override a scenario key: key.path=value (TOML value)");
  cmd->add_flag("--tap", a->tap, "With a run's folder: a deck that taps the bed ([tapping]) instead");
  return {cmd, [a] {
            aggpack::ScenarioOverrides overrides;
            overrides.set = a->sets;
            aggpack::export_lammps(a->scenario_or_run, overrides, a->out, a->tap, std::cout);
            return 0;
          }};
}

Subcommand add_import_lammps(CLI::App& app) {
  struct Arguments {
    std::string file, scenario, out;
    std::optional<std::int64_t> timestep;
    aggpack::RunOptions options;
  };
  const auto a = std::make_shared<Arguments>();
  auto* cmd = app.add_subcommand(
      "import-lammps", "Analyse a LAMMPS dump or data file in a scenario's container: aggpack's usual outputs");
  cmd->add_option("file", a->file, "LAMMPS text dump (ITEM: ...) or data file (atom_style sphere)")->required();
  cmd->add_option("--scenario", a->scenario, "Scenario giving the container, material and analysis")->required();
  auto* out_opt = cmd->add_option("--out", a->out, "Output directory (overrides output.directory)");
  cmd->add_option("--timestep", a->timestep, "The dump's snapshot to read (default: the last)");
  cmd->add_option("--set", a->options.overrides.set, "Override a scenario key: key.path=value");
  cmd->add_flag("--quiet", a->options.quiet, "Print nothing on success");
  return {cmd, [a, out_opt] {
            if (*out_opt) a->options.overrides.output_directory = a->out;
            aggpack::import_lammps(a->file, a->timestep, a->scenario, a->options, std::cout);
            return 0;
          }};
}

}  // namespace

CLI::Option* add_threads_option(CLI::App* cmd, int& threads) {
  return cmd
      ->add_option("--threads", threads,
                   "most OpenMP threads (default 0: all cores; the DEM takes fewer when fewer are faster)")
      ->check(CLI::Range(0, aggpack::kMaxThreads, "0 (all cores) or 1 to 256"));
}

// A braced list is evaluated in order: the subcommands are added, and listed, in this order.
std::vector<Subcommand> add_run_commands(CLI::App& app) { return {add_run(app), add_resume(app), add_check(app)}; }

std::vector<Subcommand> add_lammps_commands(CLI::App& app) {
  return {add_export_lammps(app), add_import_lammps(app)};
}
