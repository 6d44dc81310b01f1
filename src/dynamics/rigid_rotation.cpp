#include "aggpack/dynamics/rigid_rotation.hpp"

#include <cmath>

namespace aggpack {
namespace {

// The exact rotation of the body about its own axis `axis` (0, 1, 2) for `dt`: the flow of
// the kinetic energy's part L_k² / (2 I_k), under which L_k stays and the body turns at
// L_k / I_k. The angular momentum in the body frame turns back by the same angle.
void rotate_about_body_axis(int axis, Quaternion& q, Vec3& body_momentum, const Vec3& inverse_inertia, double dt) {
  const double angle = dt * body_momentum[axis] * inverse_inertia[axis];
  const double c = std::cos(angle), s = std::sin(angle);
  const double half_c = std::cos(0.5 * angle), half_s = std::sin(0.5 * angle);
  Vec3 turn{};
  Vec3& l = body_momentum;
  switch (axis) {
    case 0:
      turn.x = half_s;
      l = {l.x, c * l.y + s * l.z, -s * l.y + c * l.z};
      break;
    case 1:
      turn.y = half_s;
      l = {c * l.x - s * l.z, l.y, s * l.x + c * l.z};
      break;
    default:
      turn.z = half_s;
      l = {c * l.x + s * l.y, -s * l.x + c * l.y, l.z};
      break;
  }
  q = q * Quaternion{half_c, turn.x, turn.y, turn.z};
}

}  // namespace

void rotate_freely(Quaternion& orientation, const Vec3& angular_momentum, const Vec3& inverse_inertia, double dt) {
  Vec3 body_momentum = rotate_back(orientation, angular_momentum);
  const double half = 0.5 * dt;
  rotate_about_body_axis(2, orientation, body_momentum, inverse_inertia, half);
  rotate_about_body_axis(1, orientation, body_momentum, inverse_inertia, half);
  rotate_about_body_axis(0, orientation, body_momentum, inverse_inertia, dt);
  rotate_about_body_axis(1, orientation, body_momentum, inverse_inertia, half);
  rotate_about_body_axis(2, orientation, body_momentum, inverse_inertia, half);
  // Each turn keeps |q| = 1 but for rounding, which would add up over millions of steps.
  orientation = normalized(orientation);
}

Vec3 angular_velocity_of(const Quaternion& orientation, const Vec3& angular_momentum, const Vec3& inverse_inertia) {
  const Vec3 l = rotate_back(orientation, angular_momentum);
  return rotate(orientation, {l.x * inverse_inertia.x, l.y * inverse_inertia.y, l.z * inverse_inertia.z});
}

}  // namespace aggpack
