#include "aggpack/dynamics/thread_governor.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace aggpack {

ThreadGovernor::ThreadGovernor(int most) {
  for (int t = std::max(1, most);; t /= 2) {
    ladder_.push_back(t);
    if (t == 1) break;
  }
}

std::size_t ThreadGovernor::chunk(std::size_t particles) const {
  if (ladder_.size() == 1) return std::numeric_limits<std::size_t>::max();
  std::size_t steps = std::max<std::size_t>(1, stretch_steps_);  // doubling
  if (stretch_seconds_ > 0.0) {  // no further than the stretch's end, at its speed so far
    const double per_second =
        stretch_work_ / stretch_seconds_ / static_cast<double>(std::max<std::size_t>(1, particles));
    const double left = std::ceil((kStretchSeconds - stretch_seconds_) * per_second);
    steps = std::min(steps, static_cast<std::size_t>(std::clamp(left, 1.0, 1e9)));
  }
  return steps;
}

void ThreadGovernor::ran(std::size_t steps, std::size_t particles, double seconds) {
  if (ladder_.size() == 1 || steps == 0) return;
  stretch_steps_ += steps;
  stretch_work_ += static_cast<double>(steps) * static_cast<double>(particles);
  stretch_seconds_ += seconds;
  since_try_ += seconds;
  const double rate = stretch_work_ / std::max(stretch_seconds_, 1e-9);
  const bool hopeless =
      chosen_rate_ > 0.0 && !confirming_ && stretch_seconds_ >= kJudgeAfter && rate < kGiveUp * chosen_rate_;
  if (stretch_seconds_ >= kStretchSeconds || hopeless) end_stretch(rate);
}

void ThreadGovernor::end_stretch(double rate) {
  if (stretch_rung_ != chosen_) {  // a neighbour tried
    since_try_ = 0.0;
    if (rate > kBetterBy * chosen_rate_) {
      chosen_ = stretch_rung_;
      chosen_rate_ = rate;
      wait_ = kShortestWait;
    } else {
      try_below_ = !try_below_;
      wait_ = std::clamp(2.0 * wait_, kShortestWait, kLongestWait);
    }
  } else if (stretch_seconds_ < kStretchSeconds) {
    // The chosen count cut short: a stall of a few milliseconds, or another process came. A
    // whole stretch tells which, before its speed is taken.
    confirming_ = true;
  } else {
    confirming_ = false;
    // A speed far from the recent one (another process came or went, the bed changed): the
    // neighbours may now be faster; try one at once, against this speed.
    const bool changed = chosen_rate_ > 0.0 && (rate < kChanged * chosen_rate_ || kChanged * rate > chosen_rate_);
    if (changed) wait_ = 0.0;
    chosen_rate_ = chosen_rate_ > 0.0 && !changed ? 0.5 * (chosen_rate_ + rate) : rate;
  }
  stretch_rung_ = since_try_ >= wait_ && !confirming_ ? neighbour() : chosen_;
  stretch_steps_ = 0;
  stretch_work_ = stretch_seconds_ = 0.0;
}

std::size_t ThreadGovernor::neighbour() const {
  const bool has_below = chosen_ + 1 < ladder_.size(), has_above = chosen_ > 0;
  return has_below && (try_below_ || !has_above) ? chosen_ + 1 : chosen_ - 1;
}

}  // namespace aggpack
