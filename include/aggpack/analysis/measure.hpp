#pragma once
// The content of a cylindrical measure (ASTM C29, C1252): what a lab weighs after striking
// the heap off at the rim.
#include <cstddef>

#include "aggpack/core/container.hpp"
#include "aggpack/core/particle_store.hpp"

namespace aggpack {

struct MeasureContent {
  double diameter = 0.0;  // m
  double rim = 0.0;       // m above the floor
  double volume = 0.0;    // pi R^2 rim, m^3
  // Particles whose centre (a grain's centre of mass) lies below the rim, and those the rim's
  // plane cuts.
  std::size_t particles = 0, particles_cut = 0;
  // Struck off by an exact cut at the rim: the solid below the rim's plane over the volume.
  double packing_density = 0.0;
  // Struck off by centres: each particle whose centre is below the rim counted whole.
  double packing_density_whole_particles = 0.0;
};

// The content of a cylindrical container (InputError for a box: it has no rim). Exact: each
// sphere's volume below the rim, each rigid grain's union's (to 1e-6 of its volume).
[[nodiscard]] MeasureContent measure_content(const ParticleStore& particles, const Container& container);

}  // namespace aggpack
