#include "aggpack/analysis/coordination.hpp"

#include <algorithm>

#include "aggpack/spatial/multilevel_grid.hpp"

namespace aggpack {

namespace {

// The piece sphere i belongs to: its rigid body (numbered after the spheres), or itself.
std::size_t piece_of(const ParticleStore& p, std::size_t i) {
  return !p.bodies.empty() && p.body[i] != kNoBody ? p.size() + p.body[i] : i;
}

// Calls touch(i, j) for every sphere j touching sphere i (within the tolerance) of another
// piece (the spheres of one grain overlap, and are not in contact), for each i that `keep`s.
template <class Keep, class Touch>
void for_each_contact(const ParticleStore& particles, const Container& container, double tol, Keep&& keep,
                      Touch&& touch) {
  if (particles.empty()) return;
  const double r_max = *std::max_element(particles.radius.begin(), particles.radius.end());
  MultilevelGrid grid(container, particles.radius, container.bounds.volume());
  for (std::size_t i = 0; i < particles.size(); ++i)
    grid.insert(static_cast<std::uint32_t>(i), particles.position[i], particles.radius[i]);
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (!keep(i)) continue;
    const std::size_t own = piece_of(particles, i);
    grid.for_each_near(particles.position[i], particles.radius[i] * (1.0 + tol) + r_max * tol, [&](std::uint32_t j) {
      if (j == i || piece_of(particles, j) == own) return;
      const double reach = (particles.radius[i] + particles.radius[j]) * (1.0 + tol);
      if (norm2(grid.separation(particles.position[i], particles.position[j])) <= reach * reach) touch(i, j);
    });
  }
}

// Adds a piece's count of contacts to the result.
void count_in(CoordinationResult& result, std::size_t k, std::size_t& total) {
  if (result.histogram.size() <= k) result.histogram.resize(k + 1, 0);
  ++result.histogram[k];
  total += k;
  ++result.particles_counted;
}
}  // namespace

std::vector<int> contact_counts(const ParticleStore& particles, const Container& container,
                                double relative_tolerance) {
  std::vector<int> counts(particles.size(), 0);
  for_each_contact(particles, container, relative_tolerance, [](std::size_t) { return true; },
                   [&](std::size_t i, std::size_t) { ++counts[i]; });
  return counts;
}

std::vector<int> grain_contact_counts(const ParticleStore& particles, const Container& container,
                                      double relative_tolerance) {
  std::vector<std::vector<std::size_t>> partners(particles.bodies.size());
  const auto member = [&](std::size_t i) { return !particles.bodies.empty() && particles.body[i] != kNoBody; };
  for_each_contact(particles, container, relative_tolerance, member, [&](std::size_t i, std::size_t j) {
    partners[particles.body[i]].push_back(piece_of(particles, j));
  });
  std::vector<int> counts(partners.size(), 0);
  for (std::size_t b = 0; b < partners.size(); ++b) {
    std::sort(partners[b].begin(), partners[b].end());
    counts[b] = static_cast<int>(std::unique(partners[b].begin(), partners[b].end()) - partners[b].begin());
  }
  return counts;
}

CoordinationResult measure_coordination(const ParticleStore& particles, const Container& container,
                                        const Box& region, double relative_tolerance) {
  CoordinationResult result;
  result.relative_tolerance = relative_tolerance;
  std::size_t total = 0;
  if (particles.bodies.empty()) {  // each sphere a piece: its own contacts
    const auto inside = [&](std::size_t i) { return region.contains(particles.position[i]); };
    std::vector<int> counts(particles.size(), 0);
    for_each_contact(particles, container, relative_tolerance, inside, [&](std::size_t i, std::size_t) { ++counts[i]; });
    for (std::size_t i = 0; i < particles.size(); ++i)
      if (inside(i)) count_in(result, static_cast<std::size_t>(counts[i]), total);
  } else {  // by piece: a grain (its centre of mass in the region) touches each other piece once
    const auto centre = [&](std::size_t piece) {
      return piece < particles.size() ? particles.position[piece] : particles.bodies.position[piece - particles.size()];
    };
    const auto inside = [&](std::size_t i) { return region.contains(centre(piece_of(particles, i))); };
    std::vector<std::vector<std::size_t>> partners(particles.size() + particles.bodies.size());
    for_each_contact(particles, container, relative_tolerance, inside, [&](std::size_t i, std::size_t j) {
      partners[piece_of(particles, i)].push_back(piece_of(particles, j));
    });
    for (std::size_t piece = 0; piece < partners.size(); ++piece) {
      const bool member = piece < particles.size() && particles.body[piece] != kNoBody;
      if (member || !region.contains(centre(piece))) continue;
      std::vector<std::size_t>& touched = partners[piece];
      std::sort(touched.begin(), touched.end());
      count_in(result, static_cast<std::size_t>(std::unique(touched.begin(), touched.end()) - touched.begin()), total);
    }
  }
  if (result.particles_counted > 0)
    result.mean = static_cast<double>(total) / static_cast<double>(result.particles_counted);
  return result;
}

}  // namespace aggpack
