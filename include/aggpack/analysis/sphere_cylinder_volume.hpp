#pragma once
// The exact volume of a ball inside a vertical cylinder: a concrete specimen's core
// (specimen/) and a cylindrical container's radial shells (density.hpp) share it.
#include "aggpack/core/box.hpp"
#include "aggpack/core/vec3.hpp"

namespace aggpack {

// A cylinder with a vertical axis through (x, y), from z_lo to z_hi (a core drilled from the bed).
struct VerticalCylinder {
  double x = 0.0, y = 0.0, z_lo = 0.0, z_hi = 0.0, radius = 0.0;
  [[nodiscard]] Box bounds() const { return {{x - radius, y - radius, z_lo}, {x + radius, y + radius, z_hi}}; }
  [[nodiscard]] double volume() const;
  [[nodiscard]] bool contains(const Vec3& p) const;
};

// The exact volume of a ball inside a vertical cylinder: the area of the lens where each
// horizontal slice of the ball (a disc) meets the cylinder's (a disc), integrated over z by
// adaptive Gauss-Kronrod quadrature (7/15 points) between the heights where the lens changes
// form, to `relative_tolerance` of the ball's volume.
[[nodiscard]] double sphere_cylinder_volume(const Vec3& centre, double radius, const VerticalCylinder& cylinder,
                                            double relative_tolerance = 1e-10);

}  // namespace aggpack
