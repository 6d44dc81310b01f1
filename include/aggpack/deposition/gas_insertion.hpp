#pragma once
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "aggpack/core/container.hpp"
#include "aggpack/core/rng.hpp"
#include "aggpack/core/vec3.hpp"

namespace aggpack {

// A pour ([pour]): the spheres are inserted as a random gas above the bed, in batches, and
// fall through the DEM until the bed is quiet.
struct PourSettings {
  double solid_fraction = 0.2;    // of the insertion slab
  std::size_t batches = 1;        // equal parts by count; the next once the last has fallen its slab's height
  double velocity = 0.0;          // m/s, initial downward speed
  std::optional<double> gap;      // m, from the bed's top to the slab's bottom; default one largest diameter
  // m above the container's floor: each particle comes in at the speed of a free fall from
  // there to its height (with `velocity` as the speed it leaves from there), as aggregate
  // discharged from a shovel held at that height; none: every particle at `velocity`.
  std::optional<double> release_height;
};

// Where a pour puts its spheres: a slab of the container's footprint between two heights.
struct InsertionRegion {
  double bottom = 0.0, top = 0.0;  // m, heights of the slab (sphere surfaces stay inside)
};

// The slab that holds spheres of total solid volume `solid_volume` at `solid_fraction` over
// the container's footprint, its bottom at `bottom`.
InsertionRegion insertion_region(const Container& container, double bottom, double solid_volume, double solid_fraction);

// A random gas: the spheres of `radii`, largest first, each at a uniformly random position of
// the region where it lies wholly inside the slab and the side walls (periodic sides: anywhere
// in x and y, by the minimum image) and overlaps no sphere placed before it (random sequential
// addition). Positions are returned in the order of `radii`. Deterministic for a given rng state. InputError when a sphere finds no room
// in `max_attempts` tries (the fraction is too high for random addition, about 0.38 at most).
std::vector<Vec3> random_gas(const Container& container, const InsertionRegion& region, std::span<const double> radii,
                             Rng& rng, std::size_t max_attempts = 100000);

// The pour's own random stream (one per part of the drop sequence), apart from every other stage's.
[[nodiscard]] Rng pour_stream(std::uint64_t seed, std::uint32_t part);

}  // namespace aggpack
