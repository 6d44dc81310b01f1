#pragma once
#include <chrono>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace aggpack {

// Live progress of a long run on a terminal: one line, rewritten in place at most a few times
// a second, naming the run, the stage, how far it is and the time left. The line always fits
// the terminal's width (a wrapped line would leave a stale copy behind at every refresh):
// fields are dropped from the least important end until it does. Does nothing when disabled
// (not a terminal, or --quiet), so callers never need to check.
// One refresh of the line as values, for a listener instead of a terminal (the Python module's
// progress callback).
struct ProgressUpdate {
  std::string run, stage;
  std::vector<std::string> fields;      // most important first
  double done = 0.0;                    // of the stage, in [0, 1] (0: not known)
  std::optional<double> seconds_left;   // smoothed, as the line shows it; none yet
  bool seconds_left_is_bound = false;   // an upper bound (a settle that stops when quiet)
};

class Progress {
 public:
  Progress() = default;  // disabled
  // Each refresh handed to `listener` (at most a few a second), nothing printed.
  explicit Progress(std::function<void(const ProgressUpdate&)> listener) : listener_(std::move(listener)) {}
  // `columns`: the terminal's width; by default asked of the terminal at every refresh (it
  // may be resized), else $COLUMNS, else 80.
  explicit Progress(std::ostream& terminal, std::optional<int> columns = std::nullopt)
      : out_(&terminal), columns_(columns) {}

  // True when stderr is a terminal and the user did not ask for quiet.
  static bool wanted(bool quiet);

  // How the time left is known: from the stage's pace towards a known end, or only as a
  // bound (a settling run that stops when quiet, or at max_time at the latest).
  enum class TimeLeft { Estimate, AtMost };

  // The run, and for a campaign's run the time left in all (told beside the stage's time left).
  void set_run(std::string run, std::optional<double> seconds_left_in_all = std::nullopt) {
    run_ = std::move(run);
    left_in_all_ = seconds_left_in_all;
  }
  void start_stage(std::string stage);
  // `fields`: what the stage reports, most important first. `done` in [0, 1] gives the time
  // left from the stage's pace so far.
  void update(const std::vector<std::string>& fields, double done, TimeLeft kind = TimeLeft::Estimate);
  // True when an update now would be printed (enabled, and not within the refresh interval
  // of the last one): callers can skip preparing a line that would not be shown.
  [[nodiscard]] bool due() const;
  void clear();

  // The line for a terminal `columns` wide: at most columns - 1 characters (UTF-8 counted
  // as characters), so that the cursor never wraps.
  [[nodiscard]] static std::string fit_line(const std::string& run, const std::string& stage,
                                            const std::vector<std::string>& fields, const std::string& time_left,
                                            int columns);
  // The time left to show: the one shown last (none: the first), counted down by the seconds
  // since, moved kTimeLeftWeight of the way to the stage's new estimate. One estimate far off
  // (a DEM's pace changes as the bed settles, and its quiet forecast with it) moves the line
  // by a fraction of its error, not all of it (bench/measure_progress_eta.py, BENCHMARKS.md:
  // 0.4 halved the worst overestimate of Example 1 for a median 1.27 against 1.17 unsmoothed).
  static constexpr double kTimeLeftWeight = 0.4;
  [[nodiscard]] static double smoothed_time_left(std::optional<double> shown, double seconds_since, double estimate);

 private:
  using Clock = std::chrono::steady_clock;
  [[nodiscard]] int columns() const;
  std::ostream* out_ = nullptr;
  std::function<void(const ProgressUpdate&)> listener_;
  std::optional<int> columns_;
  std::string run_, stage_;
  Clock::time_point stage_start_{}, last_print_{};
  std::optional<double> left_in_all_;  // s, a campaign's
  std::optional<double> time_left_;  // s, as last shown
  TimeLeft time_left_kind_ = TimeLeft::Estimate;
  bool shown_ = false;
};

}  // namespace aggpack
