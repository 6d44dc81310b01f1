// The cost of rigid grains in the DEM against spheres, per contact, in one run: two beds of
// the same number of spheres, one of free spheres and one of grains of `--members` spheres
// each (rounded_grain(0.7, 0.7, members), 20 mm long), the spheres of the first bed of the
// grains' mean member radius. Both start on the same lattice, fall and settle for
// `--settle` s simulated (untimed), then are timed in turns (`--rounds`, each `steps`
// steps, beds alternated so that the machine's drift falls on both); the best round of each
// counts. Same material as bench_dynamics (E = 3 GPa, nu = 0.3, e = 0.5, mu = 0.17), dt =
// 5e-6 s, periodic sides. The cost per contact: wall time per step over the list's touching
// sphere pairs (walls left out, each pair once), from contact_statistics() after the round.
// Prints one JSON line with both beds, their ratio and the memory per grain.
//
//   bench_grains [spheres] [steps] [--members N] [--settle S] [--rounds R]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "aggpack/core/rng.hpp"
#include "aggpack/dynamics/dem_system.hpp"
#include "aggpack/grains/grain_shape.hpp"

namespace {

struct Bed {
  aggpack::ParticleStore store;
  aggpack::Container container;
};

struct Shape {
  std::vector<aggpack::Vec3> centres;
  std::vector<double> radii;
  double volume = 0.0, reach = 0.0, mean_radius = 0.0;
  aggpack::Vec3 moments;
};

Shape scaled_template(std::size_t members, double length) {
  const aggpack::GrainTemplate grain = aggpack::rounded_grain(0.7, 0.7, members);
  Shape shape;
  for (const aggpack::MemberSphere& s : grain.spheres) {
    shape.centres.push_back(length * s.centre);
    shape.radii.push_back(length * s.radius);
    shape.reach = std::max(shape.reach, length * (norm(s.centre) + s.radius));
    shape.mean_radius += length * s.radius / static_cast<double>(grain.spheres.size());
  }
  shape.volume = grain.mass.volume * std::pow(length, 3);
  const double l5 = std::pow(length, 5);
  shape.moments = {grain.mass.inertia[0] * l5, grain.mass.inertia[1] * l5, grain.mass.inertia[2] * l5};
  return shape;
}

// Cells of the grain's reach, a grain in each (randomly turned); or the same
// number of spheres (radii 0.9 to 1 of the members' mean) on a lattice of 1.05 mean diameters
// over about the same floor; all thrown at random, up to 0.3 m/s, so that the bed is random.
Bed lattice_bed(const Shape& shape, std::size_t grains, bool as_grains) {
  const double density = 2650.0, cell = 2.05 * shape.reach, r = shape.mean_radius;
  // A bed some 4 side lengths deep (a thin one would be a floor's layer, its contacts the walls').
  const auto side = static_cast<std::size_t>(std::max(3.0, std::round(std::cbrt(static_cast<double>(grains) / 8.0))));
  const std::size_t members = shape.radii.size();
  if (!as_grains) {
    const double spacing = 2.1 * r;
    const auto per_side = static_cast<std::size_t>(std::llround(static_cast<double>(side) * cell / spacing));
    Bed bed{{}, aggpack::Container::square(static_cast<double>(per_side) * spacing, 1000.0 * cell, true)};
    aggpack::Rng rng(38, 12);
    for (std::size_t k = 0; k < grains * members; ++k) {
      const std::size_t i = bed.store.add({(0.5 + static_cast<double>(k % per_side)) * spacing,
                                           (0.5 + static_cast<double>((k / per_side) % per_side)) * spacing,
                                           (0.5 + static_cast<double>(k / (per_side * per_side))) * spacing},
                                          rng.uniform(0.9, 1.0) * r, density);
      bed.store.velocity[i] = {rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3)};
    }
    return bed;
  }
  Bed bed{{}, aggpack::Container::square(static_cast<double>(side) * cell, 1000.0 * cell, true)};
  aggpack::Rng rng(38, 11);
  for (std::size_t k = 0; k < grains; ++k) {
    const aggpack::Vec3 centre{(0.5 + static_cast<double>(k % side)) * cell,
                               (0.5 + static_cast<double>((k / side) % side)) * cell,
                               (0.5 + static_cast<double>(k / (side * side))) * cell};
    const aggpack::Quaternion q = normalized(aggpack::Quaternion{rng.uniform(-1, 1), rng.uniform(-1, 1),
                                                                 rng.uniform(-1, 1), rng.uniform(-1, 1)});
    const std::size_t b = bed.store.add_body(centre, q, {shape.centres, shape.radii, shape.volume, shape.moments}, density);
    bed.store.bodies.velocity[b] = {rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3)};
  }
  return bed;
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t spheres = 20000, steps = 1000, members = 4, rounds = 3;
  double settle_time = 0.8;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    const bool has_value = a + 1 < argc;
    if (arg == "--members" && has_value) members = std::strtoull(argv[++a], nullptr, 10);
    else if (arg == "--settle" && has_value) settle_time = std::atof(argv[++a]);
    else if (arg == "--rounds" && has_value) rounds = std::strtoull(argv[++a], nullptr, 10);
    else if (a == 1) spheres = static_cast<std::size_t>(std::atof(argv[a]));
    else if (a == 2) steps = std::strtoull(argv[a], nullptr, 10);
    else {
      std::fprintf(stderr, "usage: %s [spheres] [steps] [--members N] [--settle S] [--rounds R]\n", argv[0]);
      return 2;
    }
  }
  if (members < 2 || members > 64 || spheres < 100 || steps == 0 || rounds == 0 || !(settle_time >= 0.0)) {
    std::fprintf(stderr, "expected 2 to 64 members, at least 100 spheres, steps and rounds > 0, a settling time >= 0\n");
    return 2;
  }
  const Shape shape = scaled_template(members, 0.02);
  const std::size_t grains = spheres / members;
  aggpack::ContactParameters material;
  material.youngs_modulus = 3e9;
  material.poisson_ratio = 0.3;
  material.wall_youngs_modulus = 3e9;
  material.wall_poisson_ratio = 0.3;
  material.restitution = 0.5;
  const aggpack::ContactModel model = aggpack::make_contact_model(material);
  aggpack::DemSettings settings;
  settings.time_step = 5e-6;
  settings.adapt_threads = false;

  Bed beds[2] = {lattice_bed(shape, grains, false), lattice_bed(shape, grains, true)};
  std::vector<std::unique_ptr<aggpack::DemSystem>> dems;
  for (Bed& bed : beds) dems.push_back(std::make_unique<aggpack::DemSystem>(bed.store, bed.container, model, settings));
  const auto settle_start = std::chrono::steady_clock::now();
  for (auto& dem : dems) dem->run(static_cast<std::size_t>(std::llround(settle_time / settings.time_step)));
  const double settle_wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - settle_start).count();
  double best[2] = {1e300, 1e300};
  std::size_t pairs[2] = {0, 0}, rebuilds[2] = {dems[0]->rebuilds(), dems[1]->rebuilds()};
  for (std::size_t round = 0; round < rounds; ++round)
    for (std::size_t b = 0; b < 2; ++b) {
      const auto t0 = std::chrono::steady_clock::now();
      dems[b]->run(steps);
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      best[b] = std::min(best[b], seconds / static_cast<double>(steps));
      pairs[b] = dems[b]->contact_statistics().contacts / 2;  // counted once for each free side
    }
  for (std::size_t b = 0; b < 2; ++b) rebuilds[b] = dems[b]->rebuilds() - rebuilds[b];
  const auto per_contact = [&](std::size_t b) { return best[b] / static_cast<double>(std::max<std::size_t>(1, pairs[b])); };
  double top = 0.0;
  for (std::size_t i = 0; i < beds[1].store.size(); ++i)
    top = std::max(top, beds[1].store.position[i].z + beds[1].store.radius[i]);
  std::printf(
      "{\"spheres\": %zu, \"grains\": %zu, \"members\": %zu, \"threads\": %d, \"steps\": %zu, \"rounds\": %zu, "
      "\"settle_simulated_s\": %.3f, \"settle_wall_s\": %.1f, "
      "\"sphere_bed\": {\"s_per_step\": %.4g, \"contacts\": %zu, \"ns_per_contact_step\": %.2f, \"dem_bytes_per_sphere\": %.1f, "
      "\"list_entries_per_sphere\": %.2f, \"rebuilds\": %zu}, "
      "\"grain_bed\": {\"s_per_step\": %.4g, \"contacts\": %zu, \"ns_per_contact_step\": %.2f, \"dem_bytes_per_grain\": %.1f, "
      "\"dem_bytes_per_member\": %.1f, \"list_entries_per_member\": %.2f, \"rebuilds\": %zu, \"bed_top_m\": %.4f}, "
      "\"grain_over_sphere_per_contact\": %.3f}\n",
      grains * members, grains, members, dems[0]->threads(), steps, rounds, settle_time, settle_wall, best[0], pairs[0],
      1e9 * per_contact(0), static_cast<double>(dems[0]->memory_bytes()) / static_cast<double>(beds[0].store.size()),
      static_cast<double>(dems[0]->list_entries()) / static_cast<double>(beds[0].store.size()), rebuilds[0],
      best[1], pairs[1], 1e9 * per_contact(1), static_cast<double>(dems[1]->memory_bytes()) / static_cast<double>(grains),
      static_cast<double>(dems[1]->memory_bytes()) / static_cast<double>(beds[1].store.size()),
      static_cast<double>(dems[1]->list_entries()) / static_cast<double>(beds[1].store.size()), rebuilds[1], top,
      per_contact(1) / per_contact(0));
  return 0;
}
