#pragma once
// The pose of a rigid body from where another code left its member spheres: the rotation and
// translation that best take the body-frame offsets to the given positions (least squares),
// by Horn's quaternion method (J. Opt. Soc. Am. A 4, 629, 1987): the rotation is the
// eigenvector of the largest eigenvalue of a symmetric 4 x 4 matrix made from the pairs. It
// holds for collinear members (a dumbbell) too, where any turn about their line fits.
#include <span>

#include "aggpack/core/quaternion.hpp"
#include "aggpack/core/vec3.hpp"

namespace aggpack {

struct RigidPose {
  Vec3 centre;             // the body frame's origin in space
  Quaternion orientation;  // body frame to space, unit
  double largest_miss = 0.0;  // the farthest a position is from centre + rotate(orientation, offset), m
};

// `offsets` (body frame) and `positions` (space), one pair per member, at least one pair, of
// equal counts (std::invalid_argument otherwise).
[[nodiscard]] RigidPose fit_rigid_pose(std::span<const Vec3> offsets, std::span<const Vec3> positions);

}  // namespace aggpack
