// DEM speed and memory on a bed at rest: 1 in spheres (E = 3 GPa, nu = 0.3, e = 0.5,
// mu = 0.17, Hertz + Mindlin + restitution damping, dt = 1e-5 s), periodic sides and a
// floor. The bed is deposited, settled untimed, optionally written as a LAMMPS data file,
// then `steps` steps are timed. Prints one JSON line.
//
//   bench_dynamics <count> [steps] [--lammps-data FILE] [--settle-steps N]   (defaults 2000, 2000)
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/os.h>

#include "aggpack/deposition/drop_and_roll.hpp"
#include "aggpack/dynamics/dem_system.hpp"
#include "aggpack/io/lammps_data.hpp"
#include "peak_rss.hpp"


int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s <count> [steps] [--lammps-data FILE] [--settle-steps N]\n", argv[0]);
    return 2;
  }
  const auto count = static_cast<std::size_t>(std::atof(argv[1]));
  std::size_t steps = 2000, settle_steps = 2000;
  std::string lammps_file;
  for (int a = 2; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg == "--lammps-data" && a + 1 < argc) lammps_file = argv[++a];
    else if (arg == "--settle-steps" && a + 1 < argc) settle_steps = std::strtoull(argv[++a], nullptr, 10);
    else steps = std::strtoull(argv[a], nullptr, 10);
  }
  const double density = 2650.0, r = 0.0127;
  const std::vector<double> radii(count, r);
  const double solid = static_cast<double>(count) * 4.0 / 3.0 * std::numbers::pi * r * r * r;
  const double side = std::max(8.0 * r, std::cbrt(solid / 0.58));
  const aggpack::Container container = aggpack::Container::square(side, 100.0 * side, true);

  aggpack::ParticleStore bed;
  bed.reserve(count);
  aggpack::DropAndRoll deposition(bed, container, radii, aggpack::DepositionSettings{}, aggpack::Rng(1, 2));
  deposition.deposit(radii, density);

  aggpack::ContactParameters material;
  material.youngs_modulus = 3e9;
  material.poisson_ratio = 0.3;
  material.wall_youngs_modulus = 3e9;
  material.wall_poisson_ratio = 0.3;
  material.restitution = 0.5;
  const aggpack::ContactModel model = aggpack::make_contact_model(material);
  aggpack::DemSettings settings;
  settings.time_step = 1e-5;
  const long rss_before = peak_rss_kib();
  aggpack::DemSystem dem(bed, container, model, settings);
  dem.run(settle_steps);
  if (!lammps_file.empty()) {
    double top = 0.0;
    for (std::size_t i = 0; i < bed.size(); ++i) top = std::max(top, bed.position[i].z + bed.radius[i]);
    fmt::output_file(lammps_file).print("{}", aggpack::lammps_data(bed, container, density, top + 0.1));
  }
  const std::size_t rebuilds_before = dem.rebuilds();
  const auto t0 = std::chrono::steady_clock::now();
  dem.run(steps);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const auto stats = dem.contact_statistics();
  const long rss = peak_rss_kib();
  std::printf(
      "{\"count\": %zu, \"threads\": %d, \"steps\": %zu, \"seconds\": %.3f, \"particle_steps_per_second\": %.4g, "
      "\"rebuilds\": %zu, \"coordination\": %.3f, \"list_entries_per_sphere\": %.2f, "
      "\"dem_bytes_per_sphere\": %.1f, \"store_bytes_per_sphere\": %zu, "
      "\"peak_rss_bytes_per_sphere\": %.1f, \"rss_before_dem_kib\": %ld, \"max_overlap\": %.3g}\n",
      count, omp_get_max_threads(), steps, seconds, static_cast<double>(count * steps) / seconds,
      dem.rebuilds() - rebuilds_before, stats.coordination,
      static_cast<double>(dem.list_entries()) / static_cast<double>(count),
      static_cast<double>(dem.memory_bytes()) / static_cast<double>(count),
      3 * sizeof(aggpack::Vec3) + 2 * sizeof(double) + 5, 1024.0 * static_cast<double>(rss) / static_cast<double>(count),
      rss_before, stats.max_overlap);
  return 0;
}
