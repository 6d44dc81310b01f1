#pragma once
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "aggpack/run/run.hpp"

namespace aggpack {

// Mean and sample standard deviation over seeds (sd NaN for fewer than two values).
struct SeedStatistics {
  double mean = std::numeric_limits<double>::quiet_NaN();
  double sd = std::numeric_limits<double>::quiet_NaN();
  std::size_t count = 0;
};
SeedStatistics seed_statistics(const std::vector<double>& values);

// One scenario run of a campaign (reproduce, sweep), with the densities it is judged by.
struct CaseRun {
  RunResult result;
  std::size_t particle_count = 0;  // kept when a campaign drops the bed itself to save memory
  double after_deposition = std::numeric_limits<double>::quiet_NaN();  // mean over the virtual boxes
  double after_dynamics = std::numeric_limits<double>::quiet_NaN();
  [[nodiscard]] double final_density() const { return std::isnan(after_dynamics) ? after_deposition : after_dynamics; }
};

// Runs many scenario runs in a row, numbering them for the progress line (on stderr when it
// is a terminal and not quiet) and timing the whole: the one series runner of reproduce, sweep,
// whole-grading and calibrate. Unless quiet, prints one line per run.
//
// A resumable campaign (reproduce, sweep: hours) can be killed and continued. Each run with a
// DEM stage leaves its checkpoint, taken before its final analysis, in its folder until the
// campaign is complete (remove_checkpoints); resumed, a run whose folder holds a checkpoint
// of that very run (the same scenario text, overrides, seed and version) continues from it (only
// analysing, when its steps were done) instead of starting again: the same bytes either way.
//
// A checking campaign (Mode::check) runs nothing: each run is only checked as `aggpack check`
// checks a scenario, with the run's overrides and seed (its sizes generated, its grains
// fitted), and gives an empty CaseRun. A study goes through its runs so once before the first
// real run: a run that cannot start stops the study at once, not hours into it.
class Campaign {
 public:
  enum class Checkpoints { removed, kept, kept_and_resumed };
  enum class Mode { run, check };
  Campaign(int threads, bool quiet, std::ostream& log, std::size_t planned_runs,
           Checkpoints checkpoints = Checkpoints::removed, Mode mode = Mode::run);
  CaseRun run(const std::string& label, const std::filesystem::path& scenario, const std::vector<std::string>& sets,
              std::uint64_t seed, const std::filesystem::path& out_dir,
              const std::optional<std::string>& stop_after = std::nullopt);
  // The line a run in memory prints on the campaign's log; unset: the standard line, as of a run into a folder.
  using ResultLine = std::function<std::string(const CaseRun&)>;
  // A run of a scenario already loaded (whole-grading, calibrate), with `seed`: numbered and timed
  // as the others, but in memory only (no folder, no file, no checkpoint; the result's summary is
  // empty).
  CaseRun run(const std::string& label, Scenario scenario, std::uint64_t seed, const ResultLine& line = {});
  [[nodiscard]] std::size_t runs_done() const { return done_; }
  [[nodiscard]] std::size_t runs_resumed() const { return resumed_; }  // continued from a checkpoint
  [[nodiscard]] double seconds() const;
  void clear_progress() { progress_.clear(); }
  // The run folders whose checkpoint was kept.
  [[nodiscard]] const std::vector<std::filesystem::path>& kept_checkpoints() const { return kept_; }

 private:
  // Why the checkpoint in `out_dir` cannot continue this run; none when it can.
  [[nodiscard]] static std::optional<std::string> why_not_resumable(const std::filesystem::path& scenario,
                                                                    const std::vector<std::string>& sets,
                                                                    std::uint64_t seed,
                                                                    const std::filesystem::path& out_dir,
                                                                    const std::optional<std::string>& stop_after);
  // The progress line's "[k/N] label seed S", with the time the runs left will take at the pace so far.
  void announce(const std::string& label, std::uint64_t seed);
  // A run's line: its densities, size and wall time (and whether it continued from its checkpoint).
  [[nodiscard]] static std::string result_line(const std::string& label, std::uint64_t seed, const CaseRun& c,
                                               bool resumed);
  // A line on the log, clear of the progress line (none when quiet).
  void print_line(const std::string& line);
  // Mode::check's run: `checks` of the run's scenario; an InputError from them names the run.
  void check(const std::string& label, std::uint64_t seed, const std::function<void()>& checks);
  int threads_;
  std::ostream* log_;  // null when quiet
  Progress progress_;
  std::size_t planned_, done_ = 0, resumed_ = 0;
  Checkpoints checkpoints_;
  Mode mode_;
  std::vector<std::filesystem::path> kept_;  // the run folders whose checkpoint was kept
  std::chrono::steady_clock::time_point start_;
};

// Once a campaign is complete: the checkpoints its runs kept would only mislead a later resume.
void remove_checkpoints(const std::vector<std::filesystem::path>& run_folders);

}  // namespace aggpack
