// The tangent spheres' radii over Highway vectors (src/grains/tangent_radii.cpp, internal to
// the module) against the scalar bound they mirror, equal on every target this machine runs
// (the bounds are never -0 or NaN, so equal values are equal bits); and a point no plane bounds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "aggpack/core/rng.hpp"
#include "grains/tangent_radii.hpp"

namespace aggpack::grains_internal {
namespace {

// The scalar search: each plane in turn, the same operations in the same order.
double scalar_radius(const std::vector<SurfacePoint>& planes, const SurfacePoint& p) {
  double radius = std::numeric_limits<double>::infinity();
  for (const SurfacePoint& plane : planes) {
    const double closing = 1.0 - dot(plane.normal, p.normal);
    if (closing <= 1e-12) continue;
    radius = std::min(radius, std::max(0.0, dot(plane.normal, plane.position) - dot(plane.normal, p.position)) / closing);
  }
  return radius;
}

TEST(TangentRadii, EveryTargetGivesTheScalarSearchsBits) {
  // An ellipsoid's points, each its own plane (31 of them: whole vectors and a rest on every
  // target), and points moved off the surface so that some bounds clamp at zero.
  std::vector<SurfacePoint> surface = ellipsoid_surface({1.0, 0.55, 0.3}, 2);
  surface.resize(31);
  PlaneColumns planes;
  for (const SurfacePoint& s : surface) planes.add(s.normal, dot(s.normal, s.position));
  Rng rng = make_rng(7, RngPurpose::Shapes);
  std::vector<SurfacePoint> points = ellipsoid_surface({1.0, 0.55, 0.3}, 3);
  for (SurfacePoint& p : points) p.position += Vec3{rng.uniform(-0.1, 0.1), rng.uniform(-0.1, 0.1), 0.0};
  std::vector<double> expected;
  for (const SurfacePoint& p : points) expected.push_back(scalar_radius(surface, p));
  ASSERT_TRUE(std::any_of(expected.begin(), expected.end(), [](double r) { return r == 0.0; }));
  ASSERT_TRUE(std::any_of(expected.begin(), expected.end(), [](double r) { return r > 0.1; }));

  const std::vector<std::string> targets = tangent_radii_targets();
  ASSERT_FALSE(targets.empty());
  for (const std::string& target : targets) {
    const std::vector<double> radii = tangent_radii_on(target, planes, points);
    ASSERT_EQ(radii.size(), points.size());
    for (std::size_t k = 0; k < points.size(); ++k)
      ASSERT_EQ(radii[k], expected[k]) << target << ", point " << k;
  }
  EXPECT_EQ(tangent_radii(planes, points), expected);  // the dispatched target
  EXPECT_THROW((void)tangent_radii_on("no such target", planes, points), std::invalid_argument);
}

TEST(TangentRadii, APointThatNoPlaneFacesIsUnbounded) {
  // One plane, the point's own: nothing bounds its sphere.
  PlaneColumns planes;
  planes.add({0.0, 0.0, 1.0}, 1.0);
  const std::vector<SurfacePoint> point{{{0.0, 0.0, 1.0}, {0.0, 0.0, 1.0}}};
  EXPECT_EQ(tangent_radii(planes, point)[0], std::numeric_limits<double>::infinity());
  // The opposite plane z >= -1 bounds it at the gap between them, 2.
  planes = PlaneColumns{};
  planes.add({0.0, 0.0, 1.0}, 1.0);
  planes.add({0.0, 0.0, -1.0}, 1.0);
  EXPECT_EQ(tangent_radii(planes, point)[0], 1.0);  // r (1 - (-1)) = 2: r = 1
  // Columns of unequal length are refused (a vector load would run past the shorter).
  planes.nx.push_back(0.0);
  EXPECT_THROW((void)tangent_radii(planes, point), std::invalid_argument);
}

}  // namespace
}  // namespace aggpack::grains_internal
