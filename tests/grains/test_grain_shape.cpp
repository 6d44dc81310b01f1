// Grain shapes: the ellipsoid's hull, its filling with tangent spheres (inside the exact
// ellipsoid, converging to its volume and dimensions), the principal axes and dimensions.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>
#include <vector>

#include "aggpack/grains/grain_shape.hpp"

namespace aggpack {
namespace {

double ellipsoid_value(const Vec3& p, const Vec3& a) {
  return p.x * p.x / (a.x * a.x) + p.y * p.y / (a.y * a.y) + p.z * p.z / (a.z * a.z);
}

TEST(EllipsoidHull, IsAClosedOutwardPolyhedronWithItsVerticesOnTheEllipsoid) {
  const Vec3 axes{1.0, 0.6, 0.35};
  for (int s = 0; s <= 3; ++s) {
    const ConvexHull h = ellipsoid_hull(axes, s);
    EXPECT_EQ(h.triangles.size(), 20u << (2 * s));
    EXPECT_EQ(h.vertices.size(), 10u * (1u << (2 * s)) + 2u);  // Euler: V = F / 2 + 2
    for (const Vec3& v : h.vertices) EXPECT_NEAR(ellipsoid_value(v, axes), 1.0, 1e-12);
    // Outward: each triangle's normal points away from the centre, and the polyhedron's
    // volume by the divergence theorem is positive and below the ellipsoid's.
    double volume = 0.0;
    for (const auto& [a, b, c] : h.triangles) {
      const Vec3 &pa = h.vertices[a], &pb = h.vertices[b], &pc = h.vertices[c];
      EXPECT_GT(dot(cross(pb - pa, pc - pa), pa + pb + pc), 0.0);
      volume += dot(pa, cross(pb, pc)) / 6.0;
    }
    const double exact = 4.0 / 3.0 * std::numbers::pi * axes.x * axes.y * axes.z;
    EXPECT_GT(volume, 0.0);
    EXPECT_LT(volume, exact);
    if (s == 3) {
      EXPECT_GT(volume, 0.99 * exact);
    }
  }
}

TEST(FillConvex, TheFirstSphereIsTheLargestThatFits) {
  const std::vector<MemberSphere> one = fill_convex(ellipsoid_surface({1.0, 1.0, 1.0}, 3), 1);
  ASSERT_EQ(one.size(), 1u);
  // Every tangent plane of a ball is at its radius from the centre: the sphere is the ball.
  EXPECT_NEAR(one[0].radius, 1.0, 1e-12);
  EXPECT_NEAR(norm(one[0].centre), 0.0, 1e-12);
  // And a second sphere has nowhere to go.
  EXPECT_EQ(fill_convex(ellipsoid_surface({1.0, 1.0, 1.0}, 3), 5).size(), 1u);
  // In an ellipsoid the largest sphere comes first: tangent at a pole of the shortest axis,
  // it grows until it meets the other pole, r = c (the curvature there, a²/c, is larger).
  const std::vector<MemberSphere> core = fill_convex(ellipsoid_surface({1.0, 0.6, 0.35}, 4), 1);
  EXPECT_NEAR(core[0].radius, 0.35, 1e-9);
  EXPECT_NEAR(norm(core[0].centre), 0.0, 1e-9);
}

// Every member sphere lies inside the exact ellipsoid, up to how far the tangent planes' body
// reaches beyond it (below 5e-3 of the smallest semi-axis at 2562 points), and as spheres are
// added the union's volume grows towards the ellipsoid's and its dimensions towards the
// ellipsoid's diameters.
TEST(FillConvex, SpheresStayInsideAndConvergeToTheEllipsoid) {
  const Vec3 axes{1.0, 0.6, 0.35};
  const ConvexSurface surface = ellipsoid_surface(axes, 4);
  const double exact = 4.0 / 3.0 * std::numbers::pi * axes.x * axes.y * axes.z;
  double previous = 0.0;
  for (const std::size_t count : {2u, 5u, 10u, 20u, 40u}) {
    SCOPED_TRACE(testing::Message() << count << " spheres");
    const std::vector<MemberSphere> spheres = fill_convex(surface, count);
    ASSERT_EQ(spheres.size(), count);
    // The sphere shrunk by 5e-3 of c is inside the ellipsoid: checked on 2562 of its points.
    for (const MemberSphere& s : spheres)
      for (const SurfacePoint& u : ellipsoid_surface({1.0, 1.0, 1.0}, 4))
        EXPECT_LE(ellipsoid_value(s.centre + u.position * (s.radius - 5e-3 * axes.z), axes), 1.0);
    const MassProperties m = union_mass_properties(spheres, 1e-6);
    EXPECT_GE(m.volume, previous * (1.0 - 1e-9));
    EXPECT_LT(m.volume, exact);
    previous = m.volume;
    if (count == 40) {
      EXPECT_GT(m.volume, 0.9 * exact);
      const GrainDimensions d = grain_dimensions(spheres, m);
      EXPECT_NEAR(d.length, 2.0 * axes.x, 0.02 * 2.0 * axes.x);
      EXPECT_NEAR(d.width, 2.0 * axes.y, 0.02 * 2.0 * axes.y);
      EXPECT_NEAR(d.thickness, 2.0 * axes.z, 0.02 * 2.0 * axes.z);
      EXPECT_NEAR(std::abs(d.axes[0].x), 1.0, 1e-3);  // the long axis is x, the thin one z
      EXPECT_NEAR(std::abs(d.axes[2].z), 1.0, 1e-3);
    }
  }
}

TEST(GrainDimensions, FollowTheGrainWhenItTurns) {
  const std::vector<MemberSphere> spheres = fill_convex(ellipsoid_surface({1.0, 0.6, 0.35}, 3), 20);
  const MassProperties m = union_mass_properties(spheres, 1e-8);
  const GrainDimensions d = grain_dimensions(spheres, m);
  // A rotation by 30 degrees about z, then 50 about x.
  const double a = 30.0 * std::numbers::pi / 180.0, b = 50.0 * std::numbers::pi / 180.0;
  const auto turn = [&](const Vec3& p) {
    const Vec3 q{std::cos(a) * p.x - std::sin(a) * p.y, std::sin(a) * p.x + std::cos(a) * p.y, p.z};
    return Vec3{q.x, std::cos(b) * q.y - std::sin(b) * q.z, std::sin(b) * q.y + std::cos(b) * q.z};
  };
  std::vector<MemberSphere> turned;
  for (const MemberSphere& s : spheres) turned.push_back({turn(s.centre), s.radius});
  const MassProperties mt = union_mass_properties(turned, 1e-8);
  const GrainDimensions dt = grain_dimensions(turned, mt);
  EXPECT_NEAR(dt.length, d.length, 1e-6);
  EXPECT_NEAR(dt.width, d.width, 1e-6);
  EXPECT_NEAR(dt.thickness, d.thickness, 1e-6);
  for (std::size_t k = 0; k < 3; ++k) EXPECT_NEAR(std::abs(dot(dt.axes[k], turn(d.axes[k]))), 1.0, 1e-6);
  EXPECT_NEAR(dot(cross(dt.axes[0], dt.axes[1]), dt.axes[2]), 1.0, 1e-12);  // right-handed
}

// A rounded grain's spheres measure the proportions asked for, in its body frame: the centre
// of mass at the origin, the inertia diagonal, the length along x and equal to 1.
TEST(RoundedGrain, MeasuresItsProportionsInItsBodyFrame) {
  for (const auto& [elongation, flatness] : {std::pair{0.8, 0.9}, std::pair{0.5, 0.4}}) {
    SCOPED_TRACE(testing::Message() << "I/L " << elongation << ", S/I " << flatness);
    const GrainTemplate t = rounded_grain(elongation, flatness, 32);
    EXPECT_EQ(t.spheres.size(), 32u);
    EXPECT_NEAR(t.dimensions.length, 1.0, 1e-12);
    EXPECT_NEAR(t.dimensions.width / t.dimensions.length, elongation, 0.005);
    EXPECT_NEAR(t.dimensions.thickness / t.dimensions.width, flatness, 0.005);
    // The mass properties carried into the body frame are those of its spheres there.
    const MassProperties again = union_mass_properties(t.spheres, 1e-8);
    EXPECT_NEAR(again.volume, t.mass.volume, 1e-7 * t.mass.volume);
    EXPECT_NEAR(norm(again.centre_of_mass), 0.0, 1e-7);
    for (std::size_t k = 0; k < 6; ++k) EXPECT_NEAR(again.inertia[k], t.mass.inertia[k], 1e-7 * t.mass.inertia[2]);
    for (std::size_t k = 3; k < 6; ++k) EXPECT_NEAR(t.mass.inertia[k], 0.0, 1e-9 * t.mass.inertia[0]);
    EXPECT_LT(t.mass.inertia[0], t.mass.inertia[1]);  // the least inertia about the length
    EXPECT_LT(t.mass.inertia[1], t.mass.inertia[2]);
    EXPECT_NEAR(std::abs(t.dimensions.axes[0].x), 1.0, 1e-9);
  }
  // A grain as wide and thick as long is the ball of diameter 1, one sphere.
  const GrainTemplate ball = rounded_grain(1.0, 1.0, 8);
  ASSERT_EQ(ball.spheres.size(), 1u);
  EXPECT_NEAR(ball.mass.volume, std::numbers::pi / 6.0, 1e-9);
  EXPECT_THROW((void)rounded_grain(0.0, 0.5, 8), std::invalid_argument);
  EXPECT_THROW((void)rounded_grain(0.5, 1.2, 8), std::invalid_argument);
  EXPECT_THROW((void)rounded_grain(0.5, 0.5, 0), std::invalid_argument);
}

// The hull of a box's corners and points inside it: the box, 12 triangles facing out.
TEST(ConvexHullOf, FindsABoxAmongItsInnerPointsAndFacesOut) {
  std::vector<Vec3> points;
  for (int k = 0; k < 8; ++k) points.push_back({k & 1 ? 2.0 : 0.0, k & 2 ? 1.0 : 0.0, k & 4 ? 1.0 : 0.0});
  for (int k = 0; k < 20; ++k) points.push_back({0.1 + 0.09 * k, 0.2 + 0.03 * k, 0.9 - 0.04 * k});
  const ConvexHull h = convex_hull_of(points);
  EXPECT_EQ(h.vertices.size(), 8u);
  EXPECT_EQ(h.triangles.size(), 12u);
  double volume = 0.0;
  for (const auto& [a, b, c] : h.triangles) volume += dot(h.vertices[a], cross(h.vertices[b], h.vertices[c])) / 6.0;
  EXPECT_NEAR(volume, 2.0, 1e-12);
  // The largest sphere tangent to the box at one of its points: at most half its smallest
  // side (reached at a point on a face's middle line; the points lie within 0.1 of one),
  // and inside the box.
  for (const MemberSphere& s : fill_convex(hull_surface(h, 0.1), 6)) {
    EXPECT_LE(s.radius, 0.5 + 1e-12);
    EXPECT_GE(s.centre.x - s.radius, -1e-12);
    EXPECT_LE(s.centre.x + s.radius, 2.0 + 1e-12);
    EXPECT_GE(std::min(s.centre.y, s.centre.z) - s.radius, -1e-12);
    EXPECT_LE(std::max(s.centre.y, s.centre.z) + s.radius, 1.0 + 1e-12);
  }
  EXPECT_GT(fill_convex(hull_surface(h, 0.1), 1)[0].radius, 0.4);
  // Points in one plane have no hull of volume.
  EXPECT_THROW((void)convex_hull_of({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0.5, 0.2, 0}}),
               std::invalid_argument);
  EXPECT_THROW((void)convex_hull_of({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}), std::invalid_argument);
  EXPECT_THROW((void)convex_hull_of({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, std::nan("")}}), std::invalid_argument);
}

// An angular grain: its proportions as asked, its mass properties those of its spheres in its
// body frame, the same grain for the same seed and another for another seed.
TEST(AngularGrain, MeasuresItsProportionsAndFollowsItsSeed) {
  const GrainTemplate t = angular_grain(0.5, 0.4, 16, 16, 1);
  EXPECT_EQ(t.spheres.size(), 16u);
  EXPECT_NEAR(t.dimensions.length, 1.0, 1e-12);
  EXPECT_NEAR(t.dimensions.width / t.dimensions.length, 0.5, 0.005);
  EXPECT_NEAR(t.dimensions.thickness / t.dimensions.width, 0.4, 0.005);
  const MassProperties recomputed = union_mass_properties(t.spheres, 1e-8);
  EXPECT_NEAR(recomputed.volume, t.mass.volume, 1e-7 * t.mass.volume);
  EXPECT_NEAR(norm(recomputed.centre_of_mass), 0.0, 1e-7);
  for (std::size_t k = 0; k < 6; ++k) EXPECT_NEAR(recomputed.inertia[k], t.mass.inertia[k], 1e-7 * t.mass.inertia[2]);
  // The seed (on grains of 4 spheres, cheaper): the same bits again, another grain for another.
  const GrainTemplate once = angular_grain(0.7, 0.6, 16, 4, 1), again = angular_grain(0.7, 0.6, 16, 4, 1),
                      other = angular_grain(0.7, 0.6, 16, 4, 2);
  ASSERT_EQ(again.spheres.size(), once.spheres.size());
  for (std::size_t k = 0; k < once.spheres.size(); ++k) {
    EXPECT_EQ(again.spheres[k].centre, once.spheres[k].centre);
    EXPECT_EQ(again.spheres[k].radius, once.spheres[k].radius);
  }
  EXPECT_NE(other.mass.volume, once.mass.volume);
  EXPECT_THROW((void)angular_grain(0.5, 0.4, 3, 16, 1), std::invalid_argument);
}

// Issue 55, item 3: a grain of one sphere is a sphere, angular as rounded; its axes are not
// squeezed on in search of proportions it cannot have (an angular hull's surface points then
// grew without bound: minutes and 0.9 GB). At once, and measuring 1 : 1 : 1.
TEST(AngularGrain, OfOneSphereIsASphereAtOnce) {
  for (const auto& grain : {angular_grain(0.6, 0.5, 12, 1, 7), rounded_grain(0.6, 0.5, 1)}) {
    ASSERT_EQ(grain.spheres.size(), 1u);
    EXPECT_NEAR(grain.dimensions.width, grain.dimensions.length, 1e-12);
    EXPECT_NEAR(grain.dimensions.thickness, grain.dimensions.length, 1e-12);
    EXPECT_NEAR(norm(grain.spheres.front().centre), 0.0, 1e-12);
  }
}

TEST(SymmetricEigen, DiagonalisesASymmetricTensor) {
  const InertiaTensor t{4.0, 3.0, 2.0, 0.5, -0.3, 0.8};
  const SymmetricEigen e = symmetric_eigen(t);
  EXPECT_LE(e.values[0], e.values[1]);
  EXPECT_LE(e.values[1], e.values[2]);
  EXPECT_NEAR(e.values[0] + e.values[1] + e.values[2], 9.0, 1e-12);  // the trace
  for (std::size_t k = 0; k < 3; ++k) {
    const Vec3& v = e.vectors[k];
    const Vec3 tv{t[0] * v.x + t[3] * v.y + t[4] * v.z, t[3] * v.x + t[1] * v.y + t[5] * v.z,
                  t[4] * v.x + t[5] * v.y + t[2] * v.z};
    EXPECT_NEAR(norm(tv - v * e.values[k]), 0.0, 1e-12);
    EXPECT_NEAR(norm(v), 1.0, 1e-12);
  }
}

TEST(GrainShape, RefusesWhatCannotBeAGrain) {
  EXPECT_THROW((void)ellipsoid_hull({1.0, 0.0, 0.5}, 2), std::invalid_argument);
  EXPECT_THROW((void)ellipsoid_hull({1.0, 0.5, std::nan("")}, 2), std::invalid_argument);
  EXPECT_THROW((void)ellipsoid_hull({1.0, 0.5, 0.5}, 7), std::invalid_argument);
  EXPECT_THROW((void)fill_convex(ellipsoid_surface({1.0, 0.5, 0.5}, 1), 0), std::invalid_argument);
  EXPECT_THROW((void)fill_convex(ConvexSurface{}, 3), std::invalid_argument);
  // A surface in one plane bounds nothing; a normal that is not a unit vector is refused.
  const ConvexSurface flat{{{0, 0, 0}, {0, 0, 1}}, {{1, 0, 0}, {0, 0, 1}}, {{0, 1, 0}, {0, 0, 1}}};
  EXPECT_THROW((void)fill_convex(flat, 2), std::invalid_argument);
  const ConvexSurface unnormal{{{0, 0, 1}, {0, 0, 2}}, {{0, 0, -1}, {0, 0, -1}}};
  EXPECT_THROW((void)fill_convex(unnormal, 2), std::invalid_argument);
  EXPECT_THROW((void)grain_dimensions({}, MassProperties{}), std::invalid_argument);
}

}  // namespace
}  // namespace aggpack
