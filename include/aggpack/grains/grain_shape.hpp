#pragma once
// The shape of a rigid multi-sphere grain: a convex hull (an ellipsoid's for a rounded grain)
// filled with member spheres, and the grain's dimensions as a lab measures them.
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "aggpack/core/vec3.hpp"
#include "aggpack/grains/union_mass_properties.hpp"

namespace aggpack {

// A convex polyhedron given by its triangles, each anticlockwise seen from outside.
struct ConvexHull {
  std::vector<Vec3> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

// The ellipsoid x²/a² + y²/b² + z²/c² = 1 (semi_axes = {a, b, c}) as an inscribed polyhedron:
// an icosahedron's triangles split in four `subdivisions` times (20 x 4^s triangles), its
// vertices on the ellipsoid. Throws std::invalid_argument for semi-axes that are not positive
// and finite, or subdivisions outside [0, 6].
[[nodiscard]] ConvexHull ellipsoid_hull(const Vec3& semi_axes, int subdivisions);

// The convex hull of `points` (at least 4, finite, not all in one plane), by Qhull, without
// the triangles of no area its triangulation may make. Throws std::invalid_argument otherwise.
[[nodiscard]] ConvexHull convex_hull_of(const std::vector<Vec3>& points);

// A convex body as points of its surface, each with its outward unit normal: the body is
// taken as the intersection of the half-spaces behind the tangent planes at these points.
struct SurfacePoint {
  Vec3 position, normal;
};
using ConvexSurface = std::vector<SurfacePoint>;

// The ellipsoid's surface at the vertices of ellipsoid_hull(semi_axes, subdivisions), with
// the ellipsoid's own normals there. The body of its tangent planes holds the ellipsoid and
// lies within a few 1e-3 of its smallest semi-axis outside it at subdivisions 4 (2562 points).
[[nodiscard]] ConvexSurface ellipsoid_surface(const Vec3& semi_axes, int subdivisions);

// A polyhedron's surface: points on each triangle (the centroids of a grid of sub-triangles
// whose sides are at most `spacing`), with the triangle's normal.
[[nodiscard]] ConvexSurface hull_surface(const ConvexHull& hull, double spacing);

// `count` member spheres filling `surface`'s body, each tangent to it at one of its points
// and as large as the tangent planes allow there (Ferellec and McDowell, Granular Matter 12,
// 2010: a sphere tangent at a surface point, grown along the inward normal until it meets the
// surface again). Each next sphere is the one whose point gains most: its radius, or how far
// its point lies outside the spheres chosen so far if that is less. So the body's core comes
// first (the largest sphere), then the regions still uncovered, the tips (small spheres) last:
// an ellipsoid 1 : 0.6 : 0.35 gets 0.53 of its volume with 5 spheres, 0.67 with 10, 0.92 with
// 40 (its length reached from 20 on). Fewer spheres: faster and bumpier; more: closer to the
// body. Deterministic; fewer than `count` only when every point is already on a sphere.
// Throws std::invalid_argument for no points, a count of 0, a point not finite or a normal
// not of unit length, or a surface that bounds no body.
[[nodiscard]] std::vector<MemberSphere> fill_convex(const ConvexSurface& surface, std::size_t count);

// A grain's dimensions as ASTM D4791 measures them: length L, width (intermediate) I and
// thickness S, L >= I >= S, taken as the extents of the spheres' union along its principal
// axes of inertia (longest first), and those axes (unit, right-handed).
struct GrainDimensions {
  double length = 0.0, width = 0.0, thickness = 0.0;
  std::array<Vec3, 3> axes;
};

[[nodiscard]] GrainDimensions grain_dimensions(std::span<const MemberSphere> spheres, const MassProperties& mass);

// A grain template in its body frame: the centre of mass at the origin, the principal axes of
// inertia along x (length), y (width) and z (thickness), and a length L of 1.
struct GrainTemplate {
  std::vector<MemberSphere> spheres;
  MassProperties mass;         // inertia diagonal in this frame
  GrainDimensions dimensions;  // length 1; width = I/L, thickness = S/L as achieved
};

// A rounded grain (gravel) of `count` spheres filling an ellipsoid, whose own spheres measure
// elongation I/L and flatness S/I: the ellipsoid's semi-axes are corrected, at most 30 times,
// until both ratios of the spheres' extents along their principal axes (of their summed
// inertia, overlaps counted twice: the template's own dimensions use the union's, which may
// differ slightly) are within `tolerance`, and the best try is kept (the fill jumps as a new
// sphere changes places, so an exact fit is not guaranteed: the template's dimensions say
// what was achieved). Throws std::invalid_argument for ratios outside (0, 1] or a count of 0.
[[nodiscard]] GrainTemplate rounded_grain(double elongation, double flatness, std::size_t count,
                                          double tolerance = 0.005);

// An angular grain (crushed stone) of `count` spheres filling the convex hull of `corners`
// points in random directions on an ellipsoid (seeded, at least 4), whose own spheres measure
// I/L and S/I: the ellipsoid's axes corrected as for rounded_grain (the hull's faces stay
// the same: an axis scaling maps a hull onto the hull of the mapped points). Throws
// std::invalid_argument as rounded_grain does, or for fewer than 4 corners.
[[nodiscard]] GrainTemplate angular_grain(double elongation, double flatness, std::size_t corners, std::size_t count,
                                          std::uint64_t seed, double tolerance = 0.005);

// The eigenvalues (ascending) and unit eigenvectors of a symmetric tensor stored as
// [xx, yy, zz, xy, xz, yz], by Jacobi rotations.
struct SymmetricEigen {
  std::array<double, 3> values;
  std::array<Vec3, 3> vectors;
};
[[nodiscard]] SymmetricEigen symmetric_eigen(const InertiaTensor& tensor);

}  // namespace aggpack
