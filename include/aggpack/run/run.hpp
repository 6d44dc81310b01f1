#pragma once
#include <filesystem>
#include <functional>
#include <optional>
#include <ostream>
#include <string>

#include <nlohmann/json.hpp>

#include "aggpack/core/stop_request.hpp"
#include "aggpack/run/checkpoint.hpp"
#include "aggpack/run/protocol.hpp"
#include "aggpack/io/scenario.hpp"
#include "aggpack/run/progress.hpp"
#include "aggpack/run/run_report.hpp"

namespace aggpack {

// How to run a scenario, beyond the scenario itself.
struct RunControls {
  int threads = 0;                        // OpenMP threads of the DEM; 0: OpenMP's default
  std::optional<std::string> stop_after;  // end the protocol after this stage
  // Called once every check before work has passed, before the first step (aggpack run makes
  // and probes its output folder here, so a refused input leaves no folder behind).
  std::function<void()> before_work;
  // Checked at every safe point: once requested, the run returns what it has done, with
  // RunReport::interrupted set (null: never stops early).
  const StopRequest* stop = nullptr;
  // Checkpoints into `directory` at safe points (run/checkpoint.hpp), each with `header`
  // (the scenario as given); none when unset.
  struct Checkpoints {
    std::filesystem::path directory;
    double every_seconds = 60.0;
    Checkpoint header;
  };
  std::optional<Checkpoints> checkpoints;
  // Also checkpoint once every step is done, before the final analysis, whenever that comes
  // (a campaign keeps that checkpoint so that, resumed, it does not run the steps again).
  bool checkpoint_before_final_analysis = false;
  // The bed to start from for a scenario whose particles are "-" (particles.from = "-"):
  // its spheres' positions, radii, velocities and materials (indices of the scenario's), checked
  // as a particle file's are. Null otherwise; given for any other scenario, it is refused.
  const ParticleStore* starting_bed = nullptr;
  // A checkpoint of this scenario to continue from (aggpack resume); null: start afresh.
  const Checkpoint* resume_from = nullptr;
  // Steps to run instead of the scenario's protocol (aggpack export-lammps: those before its
  // first DEM step); none: the scenario's.
  std::optional<Protocol> protocol;
  // The analysis of the bed at the end (aggpack export-lammps: none, the bed is only a start).
  bool final_analysis = true;
  // Called with each frame of the DEM as it is taken (output.frame_interval: at the first
  // sample, then at the first sample at or after each multiple of the interval of the series'
  // time), in aggpack's own settle, pour and tap steps: `file` is the frame's name relative to
  // the output folder (frame_file_name), `time` its series time, `bed` the bed then, `report`
  // the run so far (its scenario and sizes). The run records the frames it has handed on in
  // RunReport::frames (checkpointed: a resumed run hands on only those after its checkpoint,
  // the same ones an uninterrupted run would). Unset: no frames are taken.
  std::function<void(const std::string& file, double time, const ParticleStore& bed, const RunReport& report)>
      on_frame;
};

// The library's entry point: runs the scenario's protocol and its final analysis. Writes no
// file and prints nothing; progress goes to `progress`. Throws InputError for bad input.
RunReport run(const Scenario& scenario, const RunControls& controls, Progress& progress);

// particles.csv, supports.csv, timeseries.csv, particles.vtp and summary.json into `dir`,
// each atomically (README, "Output files"). `seconds_so_far` is the run's wall time before
// the outputs, for summary.json's total. `written_while_running`: the files the run wrote into
// `dir` as it went (its frames, its LAMMPS decks and runs; paths relative to `dir`), listed with
// the outputs in the folder's manifest. Returns the summary it wrote. InputError naming `dir`
// when it cannot be made.
nlohmann::json write_outputs(const RunReport& report, const std::filesystem::path& dir, double seconds_so_far,
                             const std::vector<std::string>& written_while_running = {});

struct RunOptions {
  ScenarioOverrides overrides;  // output.checkpoint and output.checkpoint_every among them
  int threads = 0;  // 0: OpenMP's default
  std::optional<std::string> stop_after;
  bool quiet = false;
  Progress* progress = nullptr;  // live progress on a terminal; none when null
  const StopRequest* stop = nullptr;  // SIGINT and SIGTERM, from the CLI's handler
  // Leave a run with a DEM stage its checkpoint, taken before the final analysis, instead of
  // removing it at the end: resumed, it then only analyses and writes (Campaign's resume).
  bool keep_dem_checkpoint = false;
  // Write into a folder that holds files no aggpack run wrote (left alone); otherwise such a
  // folder is refused. An earlier run's files (its manifest) are replaced either way.
  bool overwrite = false;
};

struct RunResult {
  std::filesystem::path output_directory;
  RunReport report;
  nlohmann::json summary;   // what summary.json holds
  double wall_clock_s = 0.0;  // the whole run, outputs included
};

// `aggpack run`: loads the scenario, runs it, writes the outputs and prints the result lines
// to `log` (unless quiet). Nothing is written when the input is bad.
RunResult run_scenario(const std::filesystem::path& scenario_file, const RunOptions& options, std::ostream& log);
// The same on a scenario's text in memory (the Python module's scenarios): `scenario_file`
// names it in messages, anchors its relative paths and is recorded in its checkpoint, which
// keeps the text, so that resume_run continues it as it does a file's run.
RunResult run_scenario_text(const std::string& text, const std::filesystem::path& scenario_file,
                            const RunOptions& options, std::ostream& log);

// The same for a scenario made in memory (aggpack import-lammps); it writes no checkpoint (it
// has no scenario text for resume to make it again from).
RunResult run_prepared_scenario(Scenario scenario, const RunOptions& options, std::ostream& log);

// `aggpack resume`: continues the run whose checkpoint is in `run_directory` (written by
// run_scenario or an earlier resume) with the scenario, overrides and seed it recorded, into
// the same folder; the outputs are those the run would have written uninterrupted, bit for
// bit. `options.overrides` may only change output.checkpoint and output.checkpoint_every;
// its stop_after is ignored (the checkpoint's holds).
RunResult resume_run(const std::filesystem::path& run_directory, const RunOptions& options, std::ostream& log);

// Validates a scenario (and the particle file it names) without running or writing. `watch`
// is told of the grains' templates as they are made (they can take minutes).
Scenario check_scenario(const std::filesystem::path& scenario_file, const ScenarioOverrides& overrides,
                        const LibraryWatch& watch = {});
// The same checks on a scenario already read (its particle file, grains, output folder, boxes).
void check_loaded_scenario(const Scenario& scenario, const ParticleStore* starting_bed = nullptr,
                           const LibraryWatch& watch = {});
// All of them but the output folder's, for a run in memory, which writes none (a study's).
void check_scenario_inputs(const Scenario& scenario, const ParticleStore* starting_bed = nullptr,
                           const LibraryWatch& watch = {});

}  // namespace aggpack
