// Drop-and-roll speed and memory: one bed per process, so that the peak resident size
// (getrusage) belongs to this bed alone. Prints one JSON line.
//
//   bench_deposition <count> <mono|range20> [seed]
//
// mono: diameter 1; range20: diameters uniform by number in [0.05, 1] (a 1:20 range).
// The container is square and as wide as the bed will be tall (about cbrt(V_solid/0.58)).

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <string>
#include <vector>

#include "aggpack/deposition/drop_and_roll.hpp"
#include "peak_rss.hpp"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s <count> <mono|range20> [seed]\n", argv[0]);
    return 2;
  }
  const auto count = static_cast<std::size_t>(std::atof(argv[1]));
  const std::string kind = argv[2];
  const std::uint64_t seed = argc > 3 ? std::strtoull(argv[3], nullptr, 10) : 1;
  if (kind != "mono" && kind != "range20") {
    std::fprintf(stderr, "unknown kind %s\n", kind.c_str());
    return 2;
  }
  const long rss_before = peak_rss_kib();
  std::vector<double> radii(count, 0.5);
  if (kind == "range20") {
    aggpack::Rng rng(seed, 99);
    for (double& r : radii) r = 0.5 * rng.uniform(0.05, 1.0);
  }
  double solid = 0.0;
  for (double r : radii) solid += 4.0 / 3.0 * std::numbers::pi * r * r * r;
  const double side = std::cbrt(solid / 0.58);
  const aggpack::Container container = aggpack::Container::square(side, 4.0 * side + 2.0, false);

  aggpack::ParticleStore bed;
  bed.reserve(count);
  const auto t0 = std::chrono::steady_clock::now();
  aggpack::DropAndRoll deposition(bed, container, radii, aggpack::DepositionSettings{}, aggpack::Rng(seed, 2));
  deposition.deposit(radii, aggpack::SphereMaterials::all_of(2650.0));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const auto& st = deposition.stats();
  const long rss = peak_rss_kib();
  std::printf(
      "{\"kind\": \"%s\", \"count\": %zu, \"placed\": %zu, \"seconds\": %.3f, \"spheres_per_second\": %.0f, "
      "\"us_per_sphere\": %.3f, \"events_per_sphere\": %.2f, \"redrops\": %zu, \"ties\": %zu, "
      "\"peak_rss_bytes_per_sphere\": %.1f, \"rss_before_kib\": %ld, \"side\": %.2f}\n",
      kind.c_str(), count, st.placed, seconds, static_cast<double>(st.placed) / seconds,
      1e6 * seconds / static_cast<double>(st.placed), static_cast<double>(st.events) / static_cast<double>(st.placed),
      st.redrops, st.ties_on_top + st.ties_on_ridge, 1024.0 * static_cast<double>(rss) / static_cast<double>(count),
      rss_before, side);
  return st.placed == count ? 0 : 1;
}
