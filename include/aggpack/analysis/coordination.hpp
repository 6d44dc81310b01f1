#pragma once
#include <cstddef>
#include <vector>

#include "aggpack/core/box.hpp"
#include "aggpack/core/container.hpp"
#include "aggpack/core/particle_store.hpp"

namespace aggpack {

// Sphere-sphere contacts of the spheres whose centres lie in `region`: i and j touch when
// |x_i - x_j| <= (r_i + r_j)(1 + relative_tolerance). Neighbours outside the region count.
// Wall and floor contacts are not counted (a virtual box keeps clear of them). With rigid
// grains, by grain: a grain (its centre of mass in the region) or a sphere of no grain counts
// each other grain or sphere it touches once, however many of their spheres touch; the
// spheres of one grain overlap and are not in contact.
struct CoordinationResult {
  double mean = 0.0;
  std::size_t particles_counted = 0;
  std::vector<std::size_t> histogram;  // histogram[k]: spheres (or grains) with k contacts
  double relative_tolerance = 0.0;
};
CoordinationResult measure_coordination(const ParticleStore& particles, const Container& container,
                                        const Box& region, double relative_tolerance);

// Contact count of every sphere (same rule; a grain's own spheres left out), for tests and
// per-particle output.
std::vector<int> contact_counts(const ParticleStore& particles, const Container& container,
                                double relative_tolerance);
// Contact count of every rigid grain, by grain: each other grain or sphere it touches once,
// however many of their spheres touch (grains.csv's coordination).
std::vector<int> grain_contact_counts(const ParticleStore& particles, const Container& container,
                                      double relative_tolerance);

}  // namespace aggpack
