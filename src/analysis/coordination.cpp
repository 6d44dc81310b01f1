#include "aggpack/analysis/coordination.hpp"

#include <algorithm>

#include "aggpack/spatial/multilevel_grid.hpp"

namespace aggpack {

namespace {
template <class Keep>
std::vector<int> count_contacts(const ParticleStore& particles, const Container& container,
                                double tol, Keep&& keep) {
  std::vector<int> counts(particles.size(), 0);
  if (particles.empty()) return counts;
  const double r_max = *std::max_element(particles.radius.begin(), particles.radius.end());
  MultilevelGrid grid(container, particles.radius, container.bounds.volume());
  for (std::size_t i = 0; i < particles.size(); ++i)
    grid.insert(static_cast<std::uint32_t>(i), particles.position[i], particles.radius[i]);
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (!keep(i)) continue;
    grid.for_each_near(particles.position[i], particles.radius[i] * (1.0 + tol) + r_max * tol, [&](std::uint32_t j) {
      if (j == i) return;
      const double reach = (particles.radius[i] + particles.radius[j]) * (1.0 + tol);
      if (norm2(grid.separation(particles.position[i], particles.position[j])) <= reach * reach)
        ++counts[i];
    });
  }
  return counts;
}
}  // namespace

std::vector<int> contact_counts(const ParticleStore& particles, const Container& container,
                                double relative_tolerance) {
  return count_contacts(particles, container, relative_tolerance, [](std::size_t) { return true; });
}

CoordinationResult measure_coordination(const ParticleStore& particles, const Container& container,
                                        const Box& region, double relative_tolerance) {
  CoordinationResult result;
  result.relative_tolerance = relative_tolerance;
  const auto inside = [&](std::size_t i) { return region.contains(particles.position[i]); };
  const std::vector<int> counts = count_contacts(particles, container, relative_tolerance, inside);
  std::size_t total = 0;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (!inside(i)) continue;
    const auto k = static_cast<std::size_t>(counts[i]);
    if (result.histogram.size() <= k) result.histogram.resize(k + 1, 0);
    ++result.histogram[k];
    total += k;
    ++result.particles_counted;
  }
  if (result.particles_counted > 0)
    result.mean = static_cast<double>(total) / static_cast<double>(result.particles_counted);
  return result;
}

}  // namespace aggpack
