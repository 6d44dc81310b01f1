#pragma once
#include <chrono>
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
class Progress {
 public:
  Progress() = default;  // disabled
  // `columns`: the terminal's width; by default asked of the terminal at every refresh (it
  // may be resized), else $COLUMNS, else 80.
  explicit Progress(std::ostream& terminal, std::optional<int> columns = std::nullopt)
      : out_(&terminal), columns_(columns) {}

  // True when stderr is a terminal and the user did not ask for quiet.
  static bool wanted(bool quiet);

  // How the time left is known: from the stage's pace towards a known end, or only as a
  // bound (a settling run that stops when quiet, or at max_time at the latest).
  enum class TimeLeft { Estimate, AtMost };

  void set_run(std::string run) { run_ = std::move(run); }
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

 private:
  using Clock = std::chrono::steady_clock;
  [[nodiscard]] int columns() const;
  std::ostream* out_ = nullptr;
  std::optional<int> columns_;
  std::string run_, stage_;
  Clock::time_point stage_start_{}, last_print_{};
  bool shown_ = false;
};

}  // namespace aggpack
