// DEM speed and memory on a bed at rest: 1 in spheres (E = 3 GPa, nu = 0.3, e = 0.5,
// mu = 0.17, Hertz + Mindlin + restitution damping, dt = 1e-5 s), periodic sides and a
// floor.
//
//  1. The bed is deposited and settled (untimed) until it is quiet: translational kinetic
//     energy below `--quiet` m g d per sphere over a 0.02 s window (minutes to an hour:
//     that is what the file `--bed` keeps; when it exists the bed is read from it).
//  2. The bed is a LAMMPS data file (`--bed`); a new system is made on exactly that bed,
//     at rest and with no contact history: the start every peer code gets from the file.
//  3. `--warmup` steps (untimed) let the tangential springs build up again; then `steps`
//     steps are timed. The rms speed and the coordination before and after the timed
//     steps show that the bed stayed at rest.
// `--contact` times the same bed with another contact model (the bed is settled without):
// `plain` (the default), `torque` (constant-torque rolling resistance mu_r = 0.1), `spring`
// (the spring-dashpot rolling law, mu_r = 0.1, k_roll = 5000 N/m, gamma_roll = 0.01 N s/m) or
// `materials` (half the spheres of a second, identical material: the contact-by-contact path
// of a run of several materials, the same physics).
// Prints one JSON line.
//
//   bench_dynamics <count> [steps] [--bed FILE] [--warmup N] [--quiet F] [--contact MODEL]
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <string>
#include <vector>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <fmt/os.h>

#include "aggpack/deposition/drop_and_roll.hpp"
#include "aggpack/dynamics/dem_system.hpp"
#include "aggpack/dynamics/materials.hpp"
#include "aggpack/dynamics/settle.hpp"
#include "aggpack/io/lammps_data.hpp"
#include "peak_rss.hpp"

namespace {

double rms_speed(const aggpack::ParticleStore& bed) {
  double sum = 0.0;
  for (const aggpack::Vec3& v : bed.velocity) sum += norm2(v);
  return std::sqrt(sum / static_cast<double>(std::max<std::size_t>(1, bed.size())));
}

// Reads the Atoms section of a file written by aggpack::lammps_data (and nothing else).
bool read_bed(const std::string& path, aggpack::ParticleStore& bed, double density) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line) && line.rfind("Atoms", 0) != 0) {
  }
  if (!in) return false;
  std::getline(in, line);  // blank
  while (std::getline(in, line) && !line.empty()) {
    std::istringstream row(line);
    std::size_t id, type;
    double diameter, rho;
    aggpack::Vec3 x;
    row >> id >> type >> diameter >> rho >> x.x >> x.y >> x.z;
    bed.add(x, 0.5 * diameter, density);
  }
  return !bed.empty();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s <count> [steps] [--bed FILE] [--warmup N] [--quiet F]\n", argv[0]);
    return 2;
  }
  const auto count = static_cast<std::size_t>(std::atof(argv[1]));
  std::size_t steps = 1000, warmup = 500;
  double quiet_below = 1e-6;
  std::string bed_file, contact = "plain";
  for (int a = 2; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg == "--bed" && a + 1 < argc) bed_file = argv[++a];
    else if (arg == "--warmup" && a + 1 < argc) warmup = std::strtoull(argv[++a], nullptr, 10);
    else if (arg == "--quiet" && a + 1 < argc) quiet_below = std::atof(argv[++a]);
    else if (arg == "--contact" && a + 1 < argc) contact = argv[++a];
    else steps = std::strtoull(argv[a], nullptr, 10);
  }
  const double density = 2650.0, r = 0.0127;
  const std::vector<double> radii(count, r);
  const double solid = static_cast<double>(count) * 4.0 / 3.0 * std::numbers::pi * r * r * r;
  const double side = std::max(8.0 * r, std::cbrt(solid / 0.58));
  const aggpack::Container container = aggpack::Container::square(side, 100.0 * side, true);

  aggpack::ContactParameters material;
  material.youngs_modulus = 3e9;
  material.poisson_ratio = 0.3;
  material.wall_youngs_modulus = 3e9;
  material.wall_poisson_ratio = 0.3;
  material.restitution = 0.5;
  const aggpack::ContactModel model = aggpack::make_contact_model(material);
  aggpack::DemSettings settings;
  settings.time_step = 1e-5;
  settings.adapt_threads = false;  // the scaling of OMP_NUM_THREADS threads, not the governor's choice

  aggpack::ParticleStore bed;
  aggpack::SettleResult settled;
  double settle_seconds = 0.0;
  const bool cached = !bed_file.empty() && std::filesystem::exists(bed_file);
  if (cached) {
    if (!read_bed(bed_file, bed, density) || bed.size() != count) {
      std::fprintf(stderr, "%s: not a bed of %zu spheres written by bench_dynamics\n", bed_file.c_str(), count);
      return 2;
    }
  } else {
    bed.reserve(count);
    aggpack::DropAndRoll deposition(bed, container, radii, aggpack::DepositionSettings{}, aggpack::Rng(1, 2));
    deposition.deposit(radii, aggpack::SphereMaterials::all_of(density));
    const auto settle_start = std::chrono::steady_clock::now();
    aggpack::DemSystem settling(bed, container, model, settings);
    aggpack::QuietCriterion quiet;
    quiet.max_time = 4.0;
    quiet.window = 0.02;
    quiet.kinetic_fraction = quiet_below;
    settled = aggpack::settle(settling, bed, quiet, nullptr, nullptr);
    settling.finish();
    settle_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - settle_start).count();
    if (settled.end != aggpack::SettleEnd::Quiet) {
      std::fprintf(stderr, "the bed was not quiet after %.1f s simulated\n", settled.simulated_time);
      return 1;
    }
    if (!bed_file.empty()) {
      double top = 0.0;
      for (std::size_t i = 0; i < bed.size(); ++i) top = std::max(top, bed.position[i].z + bed.radius[i]);
      fmt::output_file(bed_file).print("{}", aggpack::lammps_data(bed, container, std::vector<double>{density}, top + 0.1));
    }
  }
  for (std::size_t i = 0; i < bed.size(); ++i) bed.velocity[i] = bed.angular_velocity[i] = {};
  aggpack::ContactModel timed_model = model;
  if (contact == "torque" || contact == "spring") {
    aggpack::ContactParameters rolling = material;
    rolling.rolling_friction = 0.1;
    if (contact == "spring") {
      rolling.rolling_model = aggpack::RollingModel::SpringDashpot;
      rolling.rolling_stiffness = 5000.0;
      rolling.rolling_damping = 0.01;
    }
    timed_model = aggpack::make_contact_model(rolling);
  } else if (contact == "materials") {
    const std::vector<aggpack::ContactParameters> two(2, material);
    timed_model = aggpack::make_contact_model(two, {});
    for (std::size_t i = 0; i < bed.size(); ++i) bed.material[i] = static_cast<std::uint8_t>(i % 2);
  } else if (contact != "plain") {
    std::fprintf(stderr, "--contact %s: expected plain, torque, spring or materials\n", contact.c_str());
    return 2;
  }

  const long rss_before = peak_rss_kib();
  aggpack::DemSystem dem(bed, container, timed_model, settings);
  dem.run(warmup);
  const double rms_before = rms_speed(bed);
  const double coordination_before = dem.contact_statistics().coordination;
  const std::size_t rebuilds_before = dem.rebuilds();
  const auto t0 = std::chrono::steady_clock::now();
  dem.run(steps);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const auto stats = dem.contact_statistics();
  const long rss = peak_rss_kib();
  std::printf(
      "{\"contact\": \"%s\", \"count\": %zu, \"threads\": %d, \"steps\": %zu, \"seconds\": %.3f, \"particle_steps_per_second\": %.4g, "
      "\"bed_from_file\": %s, \"settle_simulated_s\": %.3f, \"settle_wall_s\": %.1f, "
      "\"rms_speed_before\": %.3g, \"rms_speed_after\": %.3g, \"coordination_before\": %.3f, "
      "\"coordination_after\": %.3f, \"rebuilds\": %zu, \"list_entries_per_sphere\": %.2f, "
      "\"cross_block_entries_per_sphere\": %.2f, \"dem_bytes_per_sphere\": %.1f, \"store_bytes_per_sphere\": %zu, "
      "\"peak_rss_bytes_per_sphere\": %.1f, \"rss_before_dem_kib\": %ld, \"max_overlap\": %.3g}\n",
      contact.c_str(), count, dem.threads(), steps, seconds, static_cast<double>(count * steps) / seconds,
      cached ? "true" : "false", settled.simulated_time, settle_seconds,
      rms_before, rms_speed(bed), coordination_before, stats.coordination, dem.rebuilds() - rebuilds_before,
      static_cast<double>(dem.list_entries()) / static_cast<double>(count),
      static_cast<double>(dem.cross_block_entries()) / static_cast<double>(count),
      static_cast<double>(dem.memory_bytes()) / static_cast<double>(count),
      3 * sizeof(aggpack::Vec3) + 2 * sizeof(double) + sizeof(std::uint32_t),
      1024.0 * static_cast<double>(rss) / static_cast<double>(count), rss_before, stats.max_overlap);
  return 0;
}
