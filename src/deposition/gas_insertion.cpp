#include "aggpack/deposition/gas_insertion.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/spatial/multilevel_grid.hpp"

namespace aggpack {

InsertionRegion insertion_region(const Container& container, double bottom, double solid_volume,
                                 double solid_fraction) {
  const double area = container.cross_section_area();
  return {bottom, bottom + solid_volume / (solid_fraction * area)};
}

std::vector<Vec3> random_gas(const Container& container, const InsertionRegion& region, std::span<const double> radii,
                             Rng& rng, std::size_t max_attempts) {
  std::vector<Vec3> placed(radii.size());
  if (radii.empty()) return placed;
  // Largest first: a large sphere finds no hole in a gas of small ones. Ties keep the order.
  std::vector<std::uint32_t> order(radii.size());
  for (std::uint32_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return radii[a] > radii[b]; });
  double solid = 0.0;
  for (const double r : radii) solid += 4.0 / 3.0 * std::numbers::pi * r * r * r;
  const Box& b = container.bounds;
  const double slab_volume = container.cross_section_area() * (region.top - region.bottom);
  // The grid's cells are sized for the gas; its z layers are allocated as the slab is filled.
  Container slab = container;
  slab.bounds.lo.z = region.bottom;
  MultilevelGrid grid(slab, radii, slab_volume + 1e-300);
  grid.reserve(radii.size());
  for (std::size_t n = 0; n < order.size(); ++n) {
    const std::uint32_t k = order[n];
    const double r = radii[k];
    // Centres that keep the sphere inside: the slab always, the side walls unless periodic
    // (a cylinder's: within R - r of the axis, the square around that circle sampled and the
    // corners' draws refused, each an attempt).
    const double margin = container.periodic ? 0.0 : r;
    const Vec3 lo{b.lo.x + margin, b.lo.y + margin, region.bottom + r};
    const Vec3 hi{b.hi.x - margin, b.hi.y - margin, region.top - r};
    if (!(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z))
      throw InputError(fmt::format("a sphere of diameter {:.4g} m does not fit the insertion slab of {:.4g} m by "
                                   "{:.4g} m by {:.4g} m",
                                   2.0 * r, container.length_x(), container.length_y(), region.top - region.bottom));
    bool done = false;
    for (std::size_t attempt = 0; attempt < max_attempts && !done; ++attempt) {
      const Vec3 c{rng.uniform(lo.x, hi.x), rng.uniform(lo.y, hi.y), rng.uniform(lo.z, hi.z)};
      Vec3 outward;
      if (container.is_cylinder() && container.plane_distance(Container::kCylinderWall, c, outward) < r) continue;
      bool clear = true;
      grid.for_each_near(c, r, [&](std::uint32_t j) {
        if (!clear) return;
        const double reach = r + radii[j];
        if (norm2(grid.separation(c, placed[j])) < reach * reach) clear = false;
      });
      if (!clear) continue;
      grid.insert(k, c, r);
      placed[k] = c;
      done = true;
    }
    if (!done)
      throw InputError(fmt::format("sphere {} of {} in size order, largest first (diameter {:.4g} m), found no room in "
                                   "the insertion slab after {} random tries: a solid fraction of {:.3f} is too dense for a random "
                                   "gas; expected at most about 0.3",
                                   n + 1, radii.size(), 2.0 * r, max_attempts, solid / slab_volume));
  }
  return placed;
}

Rng pour_stream(std::uint64_t seed, std::uint32_t part) {
  return Rng(seed, static_cast<std::uint64_t>(RngPurpose::Pour) + (std::uint64_t{part} << 32));
}

}  // namespace aggpack
