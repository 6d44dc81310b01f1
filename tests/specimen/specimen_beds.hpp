#pragma once
// Beds for the specimen tests: non-overlapping spheres placed at random (random sequential
// addition), each a particle of its own.
#include <random>

#include "aggpack/specimen/specimen.hpp"

namespace aggpack::testing {

inline PackedParticles random_spheres(std::size_t count, double side, double r_lo, double r_hi, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  PackedParticles bed;
  for (int tries = 0; bed.spheres.size() < count && tries < 200000; ++tries) {
    const double r = r_lo + (r_hi - r_lo) * unit(rng);
    const Vec3 c{side * unit(rng), side * unit(rng), side * unit(rng)};
    bool free = true;
    for (const MemberSphere& s : bed.spheres) {
      const Vec3 d = s.centre - c;
      free = free && dot(d, d) > (s.radius + r) * (s.radius + r);
    }
    if (!free) continue;
    bed.particle_of_sphere.push_back(bed.spheres.size());
    bed.spheres.push_back({c, r});
    bed.particle_size.push_back(2.0 * r);
  }
  return bed;
}

}  // namespace aggpack::testing
