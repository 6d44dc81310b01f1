#pragma once
#include "aggpack/core/box.hpp"
#include "aggpack/core/vec3.hpp"

namespace aggpack {

// Exact volume of the part of the ball (centre, radius) inside an axis-aligned box,
// in every case: outside, inside, cut by any number of faces, and balls larger than
// the box along any axis.
//
// Per axis the slab [lo, hi] is written as a signed sum of at most three terms, each
// "no constraint" or a half-space {u > t} with t >= 0 relative to the centre. The
// product over the three axes expands into at most 27 orthant pieces, each one of:
// the whole ball, a cap, the region beyond two perpendicular planes, or beyond three.
// Those have closed forms (see docs/ARCHITECTURE.md, "Exact volumes").
double sphere_box_volume(const Vec3& centre, double radius, const Box& box);

// The closed-form pieces, exposed for tests. All offsets are >= 0, ball at the origin.
double ball_cap_volume(double radius, double t);                    // {x > t}
double ball_wedge_volume(double radius, double b, double c);        // {y > b, z > c}
double ball_corner_volume(double radius, double a, double b, double c);  // {x > a, y > b, z > c}

}  // namespace aggpack
