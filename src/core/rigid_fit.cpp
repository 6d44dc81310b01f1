#include "aggpack/core/rigid_fit.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace aggpack {

namespace {

using Matrix4 = std::array<std::array<double, 4>, 4>;

// The unit eigenvector of the largest eigenvalue of a symmetric 4 x 4 matrix, by cyclic
// Jacobi rotations (Numerical Recipes' jacobi): a few sweeps for a matrix this small.
std::array<double, 4> largest_eigenvector(Matrix4 a) {
  Matrix4 v{};
  for (std::size_t i = 0; i < 4; ++i) v[i][i] = 1.0;
  for (int sweep = 0; sweep < 64; ++sweep) {
    double off = 0.0, scale = 0.0;
    for (std::size_t p = 0; p < 4; ++p)
      for (std::size_t q = 0; q < 4; ++q) (p == q ? scale : off) += a[p][q] * a[p][q];
    if (off <= 1e-32 * scale || off == 0.0) break;
    for (std::size_t p = 0; p < 3; ++p)
      for (std::size_t q = p + 1; q < 4; ++q) {
        if (a[p][q] == 0.0) continue;
        const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
        const double t = (theta >= 0.0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
        const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
        for (std::size_t k = 0; k < 4; ++k) {  // columns p and q
          const double akp = a[k][p], akq = a[k][q];
          a[k][p] = c * akp - s * akq;
          a[k][q] = s * akp + c * akq;
        }
        for (std::size_t k = 0; k < 4; ++k) {  // rows p and q
          const double apk = a[p][k], aqk = a[q][k];
          a[p][k] = c * apk - s * aqk;
          a[q][k] = s * apk + c * aqk;
        }
        for (std::size_t k = 0; k < 4; ++k) {
          const double vkp = v[k][p], vkq = v[k][q];
          v[k][p] = c * vkp - s * vkq;
          v[k][q] = s * vkp + c * vkq;
        }
      }
  }
  std::size_t best = 0;
  for (std::size_t i = 1; i < 4; ++i)
    if (a[i][i] > a[best][best]) best = i;
  return {v[0][best], v[1][best], v[2][best], v[3][best]};
}

}  // namespace

RigidPose fit_rigid_pose(std::span<const Vec3> offsets, std::span<const Vec3> positions) {
  if (offsets.empty() || offsets.size() != positions.size())
    throw std::invalid_argument("fit_rigid_pose: one position per offset, and at least one");
  const double n = static_cast<double>(offsets.size());
  Vec3 offset_mean{}, position_mean{};
  for (std::size_t i = 0; i < offsets.size(); ++i) {
    offset_mean += offsets[i];
    position_mean += positions[i];
  }
  offset_mean *= 1.0 / n;
  position_mean *= 1.0 / n;
  // S_ab = sum of a_a b_b over the centred pairs (a: body frame, b: space).
  double s[3][3] = {};
  for (std::size_t i = 0; i < offsets.size(); ++i) {
    const Vec3 a = offsets[i] - offset_mean, b = positions[i] - position_mean;
    const double av[3] = {a.x, a.y, a.z}, bv[3] = {b.x, b.y, b.z};
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) s[r][c] += av[r] * bv[c];
  }
  const double xx = s[0][0], xy = s[0][1], xz = s[0][2], yx = s[1][0], yy = s[1][1], yz = s[1][2], zx = s[2][0],
               zy = s[2][1], zz = s[2][2];
  const Matrix4 horn{{{xx + yy + zz, yz - zy, zx - xz, xy - yx},
                      {yz - zy, xx - yy - zz, xy + yx, zx + xz},
                      {zx - xz, xy + yx, -xx + yy - zz, yz + zy},
                      {xy - yx, zx + xz, yz + zy, -xx - yy + zz}}};
  const std::array<double, 4> e = largest_eigenvector(horn);
  RigidPose pose;
  pose.orientation = normalized(Quaternion{e[0], e[1], e[2], e[3]});
  if (pose.orientation.w < 0.0)  // q and -q are one rotation: the one with w >= 0
    pose.orientation = {-pose.orientation.w, -pose.orientation.x, -pose.orientation.y, -pose.orientation.z};
  pose.centre = position_mean - rotate(pose.orientation, offset_mean);
  for (std::size_t i = 0; i < offsets.size(); ++i)
    pose.largest_miss =
        std::max(pose.largest_miss, norm(pose.centre + rotate(pose.orientation, offsets[i]) - positions[i]));
  return pose;
}

}  // namespace aggpack
