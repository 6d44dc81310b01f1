// Target (issue 2): at least 10 million cut-sphere volumes per second on one core, for a
// uniformly random mix of uncut spheres and spheres cut by one, two and three faces.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "aggpack/analysis/sphere_box_volume.hpp"

namespace {

using aggpack::Box;
using aggpack::Vec3;

struct Case {
  Vec3 centre;
  double radius;
};

// Box [0, 10]^3, R = 1. A cut axis puts the centre within R of a face (inside or outside
// the box); an uncut axis keeps it more than R inside.
std::vector<Case> make_cases(int faces_cut_or_mixed, std::size_t n) {
  std::mt19937_64 gen(12345);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Case> cases;
  for (std::size_t i = 0; i < n; ++i) {
    const int faces = faces_cut_or_mixed >= 0 ? faces_cut_or_mixed : static_cast<int>(i % 4);
    double c[3];
    for (int a = 0; a < 3; ++a) {
      if (a < faces) {
        const double offset = -1.0 + 2.0 * u(gen);  // signed distance from the face
        c[a] = u(gen) < 0.5 ? offset : 10.0 - offset;
      } else {
        c[a] = 1.0 + 8.0 * u(gen);
      }
    }
    cases.push_back({{c[0], c[1], c[2]}, 1.0});
  }
  std::shuffle(cases.begin(), cases.end(), gen);
  return cases;
}

void volumes(benchmark::State& state) {
  const auto cases = make_cases(static_cast<int>(state.range(0)), 1 << 16);
  const Box box{{0, 0, 0}, {10, 10, 10}};
  std::size_t i = 0;
  double sum = 0.0;
  for (auto _ : state) {
    const Case& c = cases[i++ & (cases.size() - 1)];
    sum += aggpack::sphere_box_volume(c.centre, c.radius, box);
  }
  benchmark::DoNotOptimize(sum);
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}

}  // namespace

// -1: the uniform mix of 0, 1, 2 and 3 cut faces (the target); 0..3: each kind alone.
BENCHMARK(volumes)->Arg(-1)->Arg(0)->Arg(1)->Arg(2)->Arg(3)->ArgName("faces");
BENCHMARK_MAIN();
