#include "aggpack/dynamics/rigid_rotation.hpp"

#include <cmath>

namespace aggpack {
namespace {

// sin x and cos x: their Taylor series for the small angles of a step (|x| < 0.1: the terms
// left out are below 1e-22 of the sum, so the result is the library's to rounding; fewer
// terms below 1e-3), the library's beyond. A body turns a few hundredths of a radian per step or less, and the
// library's call cost as much as the rest of the turn.
void sin_cos(double x, double& sine, double& cosine) {
  if (std::abs(x) < 1e-3) {  // a grain nearly at rest: the terms left out are below 1e-21
    const double x2 = x * x;
    sine = x + x * x2 * (-1.0 / 6 + x2 * (1.0 / 120));
    cosine = 1.0 + x2 * (-0.5 + x2 * (1.0 / 24));
    return;
  }
  if (std::abs(x) < 0.1) {
    // Horner's form in x², by products (a division costs as much as the rest).
    constexpr double s3 = -1.0 / 6, s5 = 1.0 / 120, s7 = -1.0 / 5040, s9 = 1.0 / 362880, s11 = -1.0 / 39916800;
    constexpr double c2 = -1.0 / 2, c4 = 1.0 / 24, c6 = -1.0 / 720, c8 = 1.0 / 40320, c10 = -1.0 / 3628800;
    const double x2 = x * x;
    sine = x + x * x2 * (s3 + x2 * (s5 + x2 * (s7 + x2 * (s9 + x2 * s11))));
    cosine = 1.0 + x2 * (c2 + x2 * (c4 + x2 * (c6 + x2 * (c8 + x2 * c10))));
    return;
  }
  sine = std::sin(x);
  cosine = std::cos(x);
}

// The exact rotation of the body about its own axis `axis` (0, 1, 2) for `dt`: the flow of
// the kinetic energy's part L_k² / (2 I_k), under which L_k stays and the body turns at
// L_k / I_k. The angular momentum in the body frame turns back by the same angle.
void rotate_about_body_axis(int axis, Quaternion& q, Vec3& body_momentum, const Vec3& inverse_inertia, double dt) {
  const double angle = dt * body_momentum[axis] * inverse_inertia[axis];
  double half_s, half_c;
  sin_cos(0.5 * angle, half_s, half_c);
  // The whole angle's from the half's (one sine and cosine per turn, not two).
  const double c = half_c * half_c - half_s * half_s, s = 2.0 * half_s * half_c;
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

Vec3 angular_velocity_of(const RotationMatrix& orientation, const Vec3& angular_momentum, const Vec3& inverse_inertia) {
  const Vec3 l = orientation.transposed(angular_momentum);
  return orientation({l.x * inverse_inertia.x, l.y * inverse_inertia.y, l.z * inverse_inertia.z});
}

}  // namespace aggpack
