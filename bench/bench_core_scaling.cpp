// What a second thread can add on this machine, whatever the DEM does (issue 37, target 3).
//
// Three loops with nothing shared between the threads, each run on one thread and then on
// two at once, every thread on its own data; the aggregate rate of two over one is printed:
//   - throughput: 16 independent multiply-add chains, enough to keep the floating-point
//     ports busy. Two real cores give 2; two hardware threads of one core (SMT siblings, as
//     a VM's vCPUs may be) share those ports and give about 1.
//   - latency: one chain of dependent divisions, which leaves the ports idle most of the
//     time. Two cores and two SMT siblings both give about 2.
//   - memory: a triad over 3 arrays of 32 MiB per thread, far beyond the caches. Gives what
//     the memory bandwidth allows a second stream.
// A DEM step is a mix: its contact law is throughput, its gather and scatter are latency and
// memory. If two threads of throughput give well below 2, no thread layout in aggpack can.
//
// Usage: bench_core_scaling [seconds per case, default 1]
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;

// Runs `work(thread, rounds)` on `threads` threads until `seconds` have passed, in rounds
// that double; returns the rounds done per second, summed over the threads.
template <class Work>
double rate(int threads, double seconds, Work work) {
  long rounds = 1;
  for (;;) {
    const Clock::time_point start = Clock::now();
#pragma omp parallel num_threads(threads)
    work(omp_get_thread_num(), rounds);
    const double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
    if (elapsed >= seconds) return static_cast<double>(rounds) * threads / elapsed;
    if (rounds > (long{1} << 40)) {
      std::fprintf(stderr, "bench_core_scaling: a case did no measurable work (compiled away?)\n");
      std::exit(1);
    }
    rounds *= 2;
  }
}

// Each thread writes its result on its own cache line, so that the compiler keeps the loops
// and the threads share nothing.
struct Sink {
  volatile double value[64 * 8];
  void put(int thread, double v) { value[thread * 8] = v; }
};

void throughput(Sink& sink, int thread, long rounds) {
  double a[16];
  for (int k = 0; k < 16; ++k) a[k] = 1.0 + k * 1e-3;
  const double x = 0.999999, y = 1e-7;
  for (long r = 0; r < rounds; ++r)
    for (int i = 0; i < 1024; ++i)
      for (double& v : a) v = v * x + y;
  double s = 0.0;
  for (double v : a) s += v;
  sink.put(thread, s);
}

void latency(Sink& sink, int thread, long rounds) {
  double v = 1.5 + thread;
  for (long r = 0; r < rounds; ++r)
    for (int i = 0; i < 1024; ++i) v = 1.0 / (v + 1e-3) + 1.0;
  sink.put(thread, v);
}

constexpr std::size_t kStreamDoubles = std::size_t{32} << 17;  // 32 MiB per array

// Three arrays per thread: a = b + c / 2.
void memory(Sink& sink, std::vector<std::vector<double>>& arrays, int thread, long rounds) {
  double* a = arrays[3 * thread].data();
  const double* b = arrays[3 * thread + 1].data();
  const double* c = arrays[3 * thread + 2].data();
  for (long r = 0; r < rounds; ++r)
    for (std::size_t i = 0; i < kStreamDoubles; ++i) a[i] = b[i] + 0.5 * c[i];
  sink.put(thread, a[static_cast<std::size_t>(rounds) % kStreamDoubles]);
}

}  // namespace

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? std::atof(argv[1]) : 1.0;
  if (!(seconds > 0.0 && seconds <= 60.0)) {
    std::fprintf(stderr, "bench_core_scaling: the seconds per case must be a number in (0, 60], got '%s'\n", argv[1]);
    return 2;
  }
  Sink sink;
  std::vector<std::vector<double>> arrays(6, std::vector<double>(kStreamDoubles, 1.0));
  struct Case {
    const char* name;
    std::function<void(int, long)> work;
    const char* unit;
    double per_round;
  };
  const Case cases[] = {
      {"throughput", [&](int t, long r) { throughput(sink, t, r); }, "G multiply-adds/s", 16.0 * 1024 / 1e9},
      {"latency", [&](int t, long r) { latency(sink, t, r); }, "G divisions/s", 1024.0 / 1e9},
      {"memory", [&](int t, long r) { memory(sink, arrays, t, r); }, "GB/s", 3.0 * 8.0 * kStreamDoubles / 1e9}};
  for (const Case& c : cases) {
    const double one = rate(1, seconds, c.work), two = rate(2, seconds, c.work);
    std::printf("{\"case\": \"%s\", \"one_thread\": %.3f, \"two_threads\": %.3f, \"unit\": \"%s\", \"two_over_one\": %.2f}\n",
                c.name, one * c.per_round, two * c.per_round, c.unit, two / one);
  }
  return 0;
}
