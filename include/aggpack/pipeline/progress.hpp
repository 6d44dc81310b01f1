#pragma once
#include <chrono>
#include <ostream>
#include <string>

namespace aggpack {

// Live progress of a long run on a terminal: one line, rewritten in place at most a few times
// a second, naming the run, the stage, how far it is and the time left. Does nothing when
// disabled (not a terminal, or --quiet), so callers never need to check.
class Progress {
 public:
  Progress() = default;  // disabled
  explicit Progress(std::ostream& terminal) : out_(&terminal) {}

  // True when stderr is a terminal and the user did not ask for quiet.
  static bool wanted(bool quiet);

  void set_run(std::string run) { run_ = std::move(run); }
  void start_stage(std::string stage);
  // `done` in [0, 1] gives the time left from the stage's pace so far; `is_bound`: the end
  // may come earlier (a settling run that stops when quiet), so the time left is an upper bound.
  void update(const std::string& detail, double done, bool is_bound = false);
  void clear();

 private:
  using Clock = std::chrono::steady_clock;
  std::ostream* out_ = nullptr;
  std::string run_, stage_;
  Clock::time_point stage_start_{}, last_print_{};
  std::size_t last_width_ = 0;
};

}  // namespace aggpack
