// What a run pays to make its grains' templates before the DEM (issue 38: 10 % of the CI
// cross-check's pour of one template), and the tangent spheres' search that dominates it on
// each Highway target of this machine, side by side in one run. The search over an
// ellipsoid's 2562 points is O(points²); every target gives the same bits (test_grains).
//
//   bench/bench_grain_templates [--benchmark_repetitions=N]
#include <benchmark/benchmark.h>

#include <cstdint>
#include <string>
#include <vector>

#include "aggpack/grains/grain_shape.hpp"
#include "grains/tangent_radii.hpp"

namespace {

using aggpack::grains_internal::PlaneColumns;

// The CI cross-check's template (rounded, 3 spheres, I/L 0.6, S/I 0.8), made whole: the fit of
// its proportions fills the ellipsoid some twenty times.
void BM_RoundedTemplate(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(aggpack::rounded_grain(0.6, 0.8, 3));
}
BENCHMARK(BM_RoundedTemplate)->Unit(benchmark::kMillisecond);

// A Table 2 study's template: angular, 12 corners, 6 spheres (about 1000 surface points on a
// few dozen face planes: the search is cheap there).
void BM_AngularTemplate(benchmark::State& state) {
  std::uint64_t seed = 1;
  for (auto _ : state) benchmark::DoNotOptimize(aggpack::angular_grain(0.7, 0.6, 12, 6, seed++));
}
BENCHMARK(BM_AngularTemplate)->Unit(benchmark::kMillisecond);

// One search over an ellipsoid's 2562 points (each its own plane), on one named target.
void BM_TangentRadii(benchmark::State& state, const std::string& target) {
  const aggpack::ConvexSurface surface = aggpack::ellipsoid_surface({1.0, 0.6, 0.48}, 4);
  PlaneColumns planes;
  for (const aggpack::SurfacePoint& p : surface) planes.add(p.normal, dot(p.normal, p.position));
  for (auto _ : state) benchmark::DoNotOptimize(aggpack::grains_internal::tangent_radii_on(target, planes, surface));
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(surface.size() * surface.size()));
}

}  // namespace

int main(int argc, char** argv) {
  for (const std::string& target : aggpack::grains_internal::tangent_radii_targets())
    benchmark::RegisterBenchmark(("BM_TangentRadii/" + target).c_str(), BM_TangentRadii, target)
        ->Unit(benchmark::kMillisecond);
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
}
