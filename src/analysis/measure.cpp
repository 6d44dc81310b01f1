#include "aggpack/analysis/measure.hpp"

#include <algorithm>
#include <numbers>

#include "aggpack/analysis/density.hpp"
#include "aggpack/core/error.hpp"

namespace aggpack {

MeasureContent measure_content(const ParticleStore& particles, const Container& container) {
  if (!container.is_cylinder())
    throw InputError("the content of a measure needs a cylindrical container (container.shape = \"cylinder\")");
  MeasureContent m;
  m.diameter = 2.0 * container.radius();
  m.rim = container.rim;
  m.volume = container.cross_section_area() * m.rim;
  const double floor = container.bounds.lo.z, rim = floor + m.rim;
  // Every particle lies inside the wall, so the rim's plane is the one cut: a box over the
  // whole footprint (widened by the largest sphere, for one pressed a contact's overlap into
  // the wall) from the floor up to the rim holds exactly the measure's solid.
  double reach = 0.0;
  for (std::size_t i = 0; i < particles.size(); ++i) reach = std::max(reach, 2.0 * particles.radius[i]);
  for (std::size_t b = 0; b < particles.bodies.size(); ++b)
    for (std::uint32_t i = particles.bodies.first_member[b];
         i < particles.bodies.first_member[b] + particles.bodies.member_count[b]; ++i)
      reach = std::max(reach, 2.0 * (norm(particles.body_offset[i]) + particles.radius[i]));
  const Box below_rim{{container.bounds.lo.x - reach, container.bounds.lo.y - reach, floor - reach},
                      {container.bounds.hi.x + reach, container.bounds.hi.y + reach, rim}};
  const double solid = solid_volume_in_box(particles, container, below_rim);
  // The centres' rule: spheres of no grain by their centre, grains by their centre of mass.
  double whole = 0.0;
  const auto count = [&](double centre_z, double low, double high, double volume) {
    if (centre_z < rim) {
      ++m.particles;
      whole += volume;
    }
    if (low < rim && high > rim) ++m.particles_cut;
  };
  const bool grains = !particles.bodies.empty();
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (grains && particles.body[i] != kNoBody) continue;
    const double r = particles.radius[i], z = particles.position[i].z;
    count(z, z - r, z + r, 4.0 / 3.0 * std::numbers::pi * r * r * r);
  }
  for (std::size_t b = 0; b < particles.bodies.size(); ++b) {
    double low = particles.bodies.position[b].z, high = low;
    for (std::uint32_t i = particles.bodies.first_member[b];
         i < particles.bodies.first_member[b] + particles.bodies.member_count[b]; ++i) {
      low = std::min(low, particles.position[i].z - particles.radius[i]);
      high = std::max(high, particles.position[i].z + particles.radius[i]);
    }
    count(particles.bodies.position[b].z, low, high, particles.bodies.volume[b]);
  }
  m.packing_density = solid / m.volume;
  m.packing_density_whole_particles = whole / m.volume;
  return m;
}

}  // namespace aggpack
