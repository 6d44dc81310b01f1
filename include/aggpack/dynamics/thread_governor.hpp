#pragma once
#include <cstddef>
#include <vector>

namespace aggpack {

// How many threads a DEM system's steps use, chosen by measuring them: the most allowed is
// not always the fastest. Threads wait for each other at every step's barriers; when another
// process takes one of the cores, they wait for the scheduler too, a time slice at a time
// (Example 1 poured on two threads beside a busy loop took 3.6 x as long as on one thread,
// a step 100 x as long), and a small bed's steps are too short to pay for a second thread.
//
// The steps run in stretches of about kStretchSeconds on one count. The governor keeps the
// fastest count and now and then tries a neighbouring one (half or double) for a stretch:
// soon after the speed changed, more rarely while the neighbours keep losing. A stretch is
// run in chunks of doubling length, and one that runs far slower than the chosen count's
// recent speed is cut short: a try on a busy core costs a few milliseconds, not seconds (a
// stretch of the chosen count cut short is followed by a whole one before its speed counts:
// a stall of a few milliseconds is not a busy machine).
// Speeds are of the steps alone (the caller leaves its neighbour-list builds out: one costs
// as much as dozens of steps and would weigh on whichever stretch it fell in).
//
// The results of the steps do not depend on the count (DemSystem sums in a fixed order),
// only their speed does: the choice, made from the wall clock, changes no bit of a run.
class ThreadGovernor {
 public:
  // Counts from `most` down by halves to 1; `most` < 2: always 1, nothing measured.
  explicit ThreadGovernor(int most);

  [[nodiscard]] int most() const { return ladder_.front(); }
  // The count for the next steps, and how many of them to run before reporting them.
  [[nodiscard]] int threads() const { return ladder_[stretch_rung_]; }
  [[nodiscard]] std::size_t chunk(std::size_t particles) const;
  // The steps just run on threads(): `steps` steps of `particles` in `seconds` of wall clock.
  void ran(std::size_t steps, std::size_t particles, double seconds);

  [[nodiscard]] int chosen() const { return ladder_[chosen_]; }

  static constexpr double kStretchSeconds = 0.1;
  // A neighbour is tried this long after the last try, the wait doubling (up to the longest)
  // while it loses; at once when the chosen count's speed changed.
  static constexpr double kShortestWait = 1.0, kLongestWait = 32.0;
  // A neighbour is chosen when this much faster than the chosen count's recent speed; the
  // chosen count's speed has changed when a stretch runs outside [kChanged, 1 / kChanged] of
  // it; a stretch is cut short once it has run kJudgeAfter seconds at less than kGiveUp of it.
  static constexpr double kBetterBy = 1.1, kChanged = 0.7, kGiveUp = 0.25, kJudgeAfter = 0.002;

 private:
  void end_stretch(double rate);
  [[nodiscard]] std::size_t neighbour() const;  // the rung to try next

  std::vector<int> ladder_;   // the counts, most first
  std::size_t chosen_ = 0;    // rung of the chosen count
  double chosen_rate_ = 0.0;  // its particle-steps per second, recent stretches (0: none yet)
  bool try_below_ = true;     // which neighbour to try next, alternately
  bool confirming_ = false;   // the chosen count's last stretch was cut short: the next one is whole
  double wait_ = 0.0;         // wall seconds between tries (0 at the start: try at once)
  double since_try_ = 0.0;    // wall seconds run since the last try
  // The stretch in progress: its rung, and its steps (of particles) and seconds so far.
  std::size_t stretch_rung_ = 0;
  std::size_t stretch_steps_ = 0;
  double stretch_work_ = 0.0, stretch_seconds_ = 0.0;
};

}  // namespace aggpack
