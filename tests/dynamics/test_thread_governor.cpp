// The DEM's thread governor against machines simulated by the time a step takes: each test
// says how long a step of its bed takes on each thread count as time goes on, and feeds the
// governor the seconds its chunks would take. It must settle on the fastest count,
// find it again when the machine changes, and lose little time to its tries.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <map>

#include "aggpack/dynamics/thread_governor.hpp"

namespace {

using aggpack::ThreadGovernor;

// Seconds of one step of `particles` on `threads` threads at wall time t.
using Machine = std::function<double(int threads, double t, std::size_t particles)>;

// A step's work at `rate` particle-steps per second.
double work(std::size_t particles, double rate) {
  return static_cast<double>(particles) / rate;
}
// Beside a busy process, each of a step's four barriers waits for a time slice of the
// scheduler on the shared core (about 4 ms): what a thread on that core costs.
constexpr double kBarrierWaits = 4 * 0.004;

struct Simulated {
  std::map<int, double> seconds_on;  // wall seconds spent on each count
  double seconds = 0.0;
};

// Runs `particles` for `duration` wall seconds on `machine` as the governor directs, with a
// deterministic jitter of +-10 % on every chunk (a noisy machine) and, every `stall_every`
// seconds (0: never), a stall of 10 ms (the process descheduled once); `from` is where the
// clock starts.
Simulated simulate(ThreadGovernor& governor, const Machine& machine, double duration, double from = 0.0,
                   std::size_t particles = 20000, double stall_every = 0.0) {
  Simulated s;
  std::uint64_t noise = 12345;
  double next_stall = stall_every;
  while (s.seconds < duration) {
    noise = noise * 6364136223846793005ULL + 1442695040888963407ULL;
    const double jitter = 0.9 + 0.2 * static_cast<double>(noise >> 11) / 9007199254740992.0;
    const int threads = governor.threads();
    const std::size_t steps = governor.chunk(particles);
    double seconds = static_cast<double>(steps) * machine(threads, from + s.seconds, particles) * jitter;
    if (stall_every > 0.0 && s.seconds + seconds >= next_stall) {
      seconds += 0.010;
      next_stall += stall_every;
    }
    governor.ran(steps, particles, seconds);
    s.seconds_on[threads] += seconds;
    s.seconds += seconds;
  }
  return s;
}

TEST(ThreadGovernor, OneThreadAllowedIsOneThreadAlways) {
  ThreadGovernor governor(1);
  EXPECT_EQ(governor.most(), 1);
  EXPECT_EQ(governor.threads(), 1);
  governor.ran(10, 1000, 0.5);
  EXPECT_EQ(governor.threads(), 1);
  EXPECT_GT(governor.chunk(1000), 1000000u);  // nothing to measure: no chunks
}

TEST(ThreadGovernor, AloneItRunsOnTheMostAndTriesFewerRarely) {
  // Two threads 1.9 x one: after its first try it stays on two, trying one thread ever more
  // rarely (the waits double to 32 s): well under 2 % of 200 s on the slower count.
  ThreadGovernor governor(2);
  const Simulated s = simulate(
      governor, [](int threads, double, std::size_t n) { return work(n, threads == 2 ? 1.9e7 : 1e7); }, 200.0);
  EXPECT_EQ(governor.chosen(), 2);
  EXPECT_LT(s.seconds_on.at(1), 0.02 * s.seconds);
}

TEST(ThreadGovernor, AStallOfAFewMillisecondsIsNotABusyMachine) {
  // Alone, two threads the faster, the process stalled for 10 ms three times a second: a
  // stretch cut short by a stall is followed by a whole one, which finds the speed unchanged.
  ThreadGovernor governor(2);
  const Simulated s = simulate(
      governor, [](int threads, double, std::size_t n) { return work(n, threads == 2 ? 1.9e7 : 1e7); }, 200.0, 0.0,
      20000, 0.3);
  EXPECT_EQ(governor.chosen(), 2);
  EXPECT_LT(s.seconds_on.at(1), 0.02 * s.seconds);
}

TEST(ThreadGovernor, BesideABusyCoreItRunsOnOneThread) {
  // Beside another process, a two-thread step waits for the scheduler at every barrier (here
  // 9 x slower than one thread). Every try of two threads is cut short after a step.
  ThreadGovernor governor(2);
  const Simulated s = simulate(
      governor,
      [](int threads, double, std::size_t n) { return threads == 2 ? work(n, 1.9e7) + kBarrierWaits : work(n, 1e7); },
      200.0);
  EXPECT_EQ(governor.chosen(), 1);
  EXPECT_LT(s.seconds_on.at(2), 0.01 * s.seconds);
}

TEST(ThreadGovernor, FollowsTheMachineWhenAnotherProcessComesAndGoes) {
  // Alone for 100 s, then a busy loop for 100 s, then alone again.
  const auto busy = [](double t) { return t >= 100.0 && t < 200.0; };
  const Machine machine = [&](int threads, double t, std::size_t n) {
    if (threads == 1) return work(n, 1e7);
    return work(n, 1.9e7) + (busy(t) ? kBarrierWaits : 0.0);
  };
  ThreadGovernor governor(2);
  const Simulated alone = simulate(governor, machine, 100.0);
  EXPECT_EQ(governor.chosen(), 2);
  // The busy loop comes: the first slow stretch is cut short (after its chunk in progress)
  // and one thread tried at once.
  const Simulated busy_part = simulate(governor, machine, 100.0, alone.seconds);
  EXPECT_EQ(governor.chosen(), 1);
  EXPECT_LT(busy_part.seconds_on.at(2), 2.0);
  // It goes: two threads are found again by the next try, at most the longest wait later.
  const Simulated after = simulate(governor, machine, 100.0, alone.seconds + busy_part.seconds);
  EXPECT_EQ(governor.chosen(), 2);
  EXPECT_LT(after.seconds_on.at(1), ThreadGovernor::kLongestWait + 2.0);
}

TEST(ThreadGovernor, ClimbsTheLadderToTheFastestCount) {
  // Eight allowed, four the fastest (a machine of four cores, say): 8, 4, 2, 1 are tried.
  ThreadGovernor governor(8);
  const Machine machine = [](int threads, double, std::size_t n) {
    switch (threads) {
      case 8:
        return work(n, 2e7);
      case 4:
        return work(n, 3.5e7);
      case 2:
        return work(n, 1.9e7);
      default:
        return work(n, 1e7);
    }
  };
  const Simulated s = simulate(governor, machine, 200.0);
  EXPECT_EQ(governor.chosen(), 4);
  EXPECT_GT(s.seconds_on.at(4), 0.9 * s.seconds);
}

TEST(ThreadGovernor, AStretchIsATenthOfASecondInDoublingChunksWhateverTheBed) {
  // The first stretch (on two threads; then one thread is tried): chunks double from one
  // step, the last one ending the stretch less than one step past a tenth of a second.
  for (const std::size_t particles : {std::size_t{2000}, std::size_t{300000}}) {
    SCOPED_TRACE(particles);
    ThreadGovernor governor(2);
    const double rate = 1e7;
    std::size_t steps = 0;
    double seconds = 0.0;
    while (governor.threads() == 2) {
      const std::size_t chunk = governor.chunk(particles);
      EXPECT_LE(chunk, std::max<std::size_t>(1, steps));
      const double t = static_cast<double>(chunk * particles) / rate;
      governor.ran(chunk, particles, t);
      steps += chunk;
      seconds += t;
    }
    EXPECT_GE(seconds, ThreadGovernor::kStretchSeconds);
    EXPECT_LE(seconds, ThreadGovernor::kStretchSeconds + static_cast<double>(particles) / rate + 1e-12);
  }
}

}  // namespace
