#include "aggpack/core/particle_store.hpp"

#include <numbers>

namespace aggpack {

std::size_t ParticleStore::add(const Vec3& pos, double r, double density, std::uint32_t layer_index,
                               std::uint8_t material_index) {
  position.push_back(pos);
  velocity.push_back({});
  angular_velocity.push_back({});
  radius.push_back(r);
  mass.push_back(sphere_mass(r, density));
  layer.push_back(layer_index);
  material.push_back(material_index);
  return radius.size() - 1;
}

double ParticleStore::sphere_mass(double r, double density) { return density * 4.0 / 3.0 * std::numbers::pi * r * r * r; }

void ParticleStore::reserve(std::size_t n) {
  position.reserve(n);
  velocity.reserve(n);
  angular_velocity.reserve(n);
  radius.reserve(n);
  mass.reserve(n);
  layer.reserve(n);
  material.reserve(n);
}

}  // namespace aggpack
