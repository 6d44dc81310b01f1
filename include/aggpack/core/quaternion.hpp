#pragma once
// Unit quaternions for the orientation of rigid bodies: q = (w, x, y, z) turns a vector of the
// body frame into the space frame, v_space = q v_body q*.
#include <cmath>

#include "aggpack/core/rng.hpp"
#include "aggpack/core/vec3.hpp"

namespace aggpack {

struct Quaternion {
  double w = 1.0, x = 0.0, y = 0.0, z = 0.0;  // the identity by default
  constexpr bool operator==(const Quaternion&) const = default;
};

constexpr Quaternion operator*(const Quaternion& a, const Quaternion& b) {
  return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
          a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}

constexpr Quaternion conjugate(const Quaternion& q) { return {q.w, -q.x, -q.y, -q.z}; }

inline Quaternion normalized(const Quaternion& q) {
  const double s = 1.0 / std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  return {q.w * s, q.x * s, q.y * s, q.z * s};
}

// The turn by `angle` (rad, right-handed) about the unit vector `axis`.
inline Quaternion axis_angle(const Vec3& axis, double angle) {
  const double s = std::sin(0.5 * angle);
  return {std::cos(0.5 * angle), axis.x * s, axis.y * s, axis.z * s};
}

// An orientation uniformly at random: a point drawn uniformly in the 4-ball (by rejection
// from its cube) and pushed out onto the sphere, whose points are the rotations, uniformly.
// Square roots only: the same bits with every standard library.
inline Quaternion random_orientation(Rng& rng) {
  for (;;) {
    const Quaternion q{rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0)};
    const double n2 = q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z;
    if (n2 <= 1.0 && n2 > 1e-6) return normalized(q);  // near 0 the direction is rounding's
  }
}

// q v q* for a unit q: the body-frame vector v in the space frame.
constexpr Vec3 rotate(const Quaternion& q, const Vec3& v) {
  const Vec3 u{q.x, q.y, q.z};
  const Vec3 t = 2.0 * cross(u, v);
  return v + q.w * t + cross(u, t);
}

// q* v q: the space-frame vector v in the body frame.
constexpr Vec3 rotate_back(const Quaternion& q, const Vec3& v) { return rotate(conjugate(q), v); }

// The rotation of a unit quaternion as a matrix (by rows): cheaper to apply to many vectors.
struct RotationMatrix {
  Vec3 x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
  constexpr bool operator==(const RotationMatrix&) const = default;
  // R v: a body-frame vector in space.
  [[nodiscard]] constexpr Vec3 operator()(const Vec3& v) const { return {dot(x, v), dot(y, v), dot(z, v)}; }
  // R^T v: a space vector in the body frame.
  [[nodiscard]] constexpr Vec3 transposed(const Vec3& v) const { return x * v.x + y * v.y + z * v.z; }
};

constexpr RotationMatrix rotation_matrix(const Quaternion& q) {
  const double xx = q.x * q.x, yy = q.y * q.y, zz = q.z * q.z;
  const double xy = q.x * q.y, xz = q.x * q.z, yz = q.y * q.z, wx = q.w * q.x, wy = q.w * q.y, wz = q.w * q.z;
  return {{1.0 - 2.0 * (yy + zz), 2.0 * (xy - wz), 2.0 * (xz + wy)},
          {2.0 * (xy + wz), 1.0 - 2.0 * (xx + zz), 2.0 * (yz - wx)},
          {2.0 * (xz - wy), 2.0 * (yz + wx), 1.0 - 2.0 * (xx + yy)}};
}

}  // namespace aggpack
