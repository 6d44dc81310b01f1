#include "aggpack/core/particle_store.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

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
  if (!bodies.empty()) {
    body.push_back(kNoBody);
    body_offset.push_back({});
  }
  return radius.size() - 1;
}

std::size_t ParticleStore::add_body(const Vec3& centre, const Quaternion& orientation, const RigidBodyShape& shape,
                                    double density, std::uint32_t layer_index, std::uint8_t material_index) {
  const Vec3& moments = shape.principal_inertia_per_density;
  if (shape.member_centres.empty() || shape.member_centres.size() != shape.member_radii.size())
    throw std::invalid_argument("ParticleStore::add_body: a body needs one radius per member sphere, and a member");
  if (!(shape.volume > 0.0) || !(moments.x > 0.0) || !(moments.y > 0.0) || !(moments.z > 0.0) ||
      !std::isfinite(shape.volume) || !std::isfinite(moments.x + moments.y + moments.z) || !(shape.scale > 0.0) ||
      !std::isfinite(shape.scale))
    throw std::invalid_argument("ParticleStore::add_body: a body's volume, principal moments and scale must be > 0");
  const double s = shape.scale, s3 = s * s * s;
  if (bodies.empty()) {
    body.assign(size(), kNoBody);
    body_offset.assign(size(), {});
  }
  const auto index = static_cast<std::uint32_t>(bodies.size());
  bodies.first_member.push_back(static_cast<std::uint32_t>(size()));
  bodies.member_count.push_back(static_cast<std::uint32_t>(shape.member_centres.size()));
  bodies.position.push_back(centre);
  bodies.orientation.push_back(orientation);
  bodies.velocity.push_back({});
  bodies.angular_velocity.push_back({});
  bodies.mass.push_back(density * shape.volume * s3);
  bodies.volume.push_back(shape.volume * s3);
  bodies.shape.push_back(shape.id);
  bodies.principal_inertia.push_back((density * s3 * s * s) * moments);
  for (std::size_t k = 0; k < shape.member_centres.size(); ++k) {
    const Vec3 offset = s * shape.member_centres[k];
    add(centre + rotate(orientation, offset), s * shape.member_radii[k], density, layer_index, material_index);
    body.back() = index;
    body_offset.back() = offset;
  }
  return index;
}

double RigidBodyShape::reach() const {
  double farthest = 0.0;
  for (std::size_t k = 0; k < member_centres.size() && k < member_radii.size(); ++k)
    farthest = std::max(farthest, norm(member_centres[k]) + member_radii[k]);
  return scale * farthest;
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
  if (!bodies.empty()) {
    body.reserve(n);
    body_offset.reserve(n);
  }
}

}  // namespace aggpack
