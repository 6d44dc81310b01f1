// DemSystem's rigid bodies: taken in from the store, kicked, turned and moved, their members
// placed from their pose, and their members' loads summed onto them.
#include <cstdint>
#include <stdexcept>

#include <fmt/format.h>

#include "aggpack/core/quaternion.hpp"
#include "aggpack/dynamics/dem_system.hpp"
#include "aggpack/dynamics/rigid_rotation.hpp"

namespace aggpack {

// The store's bodies from body_.size() on, whose members are the new slots' (slot = store
// index until the list build): records taken from the store, members placed from their pose.
void DemSystem::admit_bodies(std::uint32_t first) {
  if (p_.bodies.empty()) return;
  const RigidBodies& bodies = p_.bodies;
  body_of_.resize(n_, kNoBody);  // the spheres admitted before the first body are of none
  body_offset_.resize(n_);
  arm_.resize(n_);
  image_.resize(n_);
  for (std::uint32_t i = first; i < n_; ++i) {
    body_of_[i] = p_.body[i];
    body_offset_[i] = p_.body_offset[i];
  }
  for (std::size_t b = body_.size(); b < bodies.size(); ++b) {
    Body body;
    body.first_member = bodies.first_member[b];
    body.member_count = bodies.member_count[b];
    if (body.first_member < first || body.member_count == 0 || body.first_member + body.member_count > n_)
      throw std::invalid_argument(fmt::format("DemSystem: the members of body {} are not among the new particles", b));
    body.position = bodies.position[b];
    body.orientation = bodies.orientation[b];
    body.velocity = bodies.velocity[b];
    body.mass = bodies.mass[b];
    const Vec3& moments = bodies.principal_inertia[b];
    body.inverse_inertia = {1.0 / moments.x, 1.0 / moments.y, 1.0 / moments.z};
    // L = R I R^T w: the momentum of the store's angular velocity.
    const Vec3 spin = rotate_back(body.orientation, bodies.angular_velocity[b]);
    body.angular_momentum = rotate(body.orientation, {moments.x * spin.x, moments.y * spin.y, moments.z * spin.z});
    body.rotation = rotation_matrix(body.orientation);
    // A body is frozen whole (a layer below the one that settles) or not at all; a frozen one
    // stands still, its members with it.
    const bool frozen = frozen_[body.first_member] != 0;
    if (frozen) body.velocity = body.angular_momentum = {};
    body.angular_velocity = angular_velocity_of(body.rotation, body.angular_momentum, body.inverse_inertia);
    for (std::uint32_t i = body.first_member; i < body.first_member + body.member_count; ++i) {
      if (p_.body[i] != b || (frozen_[i] != 0) != frozen)
        throw std::invalid_argument(
            fmt::format("DemSystem: particle {} is not body {}'s member, or is frozen where its body is not", i, b));
      Grain& g = grain_[i];
      g.mass = body.mass;
      g.inverse_inertia = 0.0;  // a member does not turn on its own
      image_[i] = {};
    }
    place_members(body);
    body_.push_back(body);
    body_load_.push_back({frozen ? Vec3{} : body.mass * settings_.gravity, {}});  // a new body touches nothing
  }
}

void DemSystem::place_members(const Body& body) {
  for (std::uint32_t i = body.first_member; i < body.first_member + body.member_count; ++i) {
    const Vec3 arm = body.rotation(body_offset_[i]);
    arm_[i] = arm;
    Grain& g = grain_[slot_of_[i]];
    g.position = body.position + arm + image_[i];
    g.velocity = body.velocity + cross(body.angular_velocity, arm);
    g.angular_velocity = body.angular_velocity;
  }
}

void DemSystem::kick_bodies(double half_step) {
#pragma omp parallel for schedule(static) if (threaded_) num_threads(threads_)
  for (std::size_t b = 0; b < body_.size(); ++b) {
    Body& body = body_[b];
    if (is_frozen_body(body)) continue;
    body.velocity += body_load_[b].force * (half_step / body.mass);
    body.angular_momentum += body_load_[b].torque * half_step;
    body.angular_velocity = angular_velocity_of(body.rotation, body.angular_momentum, body.inverse_inertia);
    for (std::uint32_t i = body.first_member; i < body.first_member + body.member_count; ++i) {
      Grain& g = grain_[slot_of_[i]];
      g.velocity = body.velocity + cross(body.angular_velocity, arm_[i]);
      g.angular_velocity = body.angular_velocity;
    }
  }
}

void DemSystem::drift_bodies(double dt) {
#pragma omp parallel for schedule(static) if (threaded_) num_threads(threads_)
  for (std::size_t b = 0; b < body_.size(); ++b) {
    Body& body = body_[b];
    if (is_frozen_body(body)) continue;
    body.position += body.velocity * dt;
    rotate_freely(body.orientation, body.angular_momentum, body.inverse_inertia, dt);
    body.rotation = rotation_matrix(body.orientation);
    body.angular_velocity = angular_velocity_of(body.rotation, body.angular_momentum, body.inverse_inertia);
    place_members(body);
  }
}

void DemSystem::sum_body_loads() {
#pragma omp parallel for schedule(static) if (threaded_) num_threads(threads_)
  for (std::size_t b = 0; b < body_.size(); ++b) {
    const Body& body = body_[b];
    if (is_frozen_body(body)) {
      body_load_[b] = {};
      continue;
    }
    Vec3 force = body.mass * settings_.gravity, torque{};
    for (std::uint32_t i = body.first_member; i < body.first_member + body.member_count; ++i) {
      const ForceTorque& member = load_[slot_of_[i]];
      force += member.force;
      torque += cross(arm_[i], member.force) + member.torque;
    }
    body_load_[b] = {force, torque};
  }
}

}  // namespace aggpack
