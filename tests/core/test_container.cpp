#include "aggpack/core/container.hpp"

#include <gtest/gtest.h>

#include <numbers>

#include <vector>

namespace aggpack {
namespace {

TEST(Container, MinimumImageIsTheNearestAndExactlyAntisymmetric) {
  const Container periodic = Container::square(1.0, 2.0, true), walls = Container::square(1.0, 2.0, false);
  for (const Vec3 d : {Vec3{0.7, -0.7, 0.3}, Vec3{-0.2, 0.9, 1.5}, Vec3{0.5, -0.5, 0}, Vec3{1.3, -1.4, 0}}) {
    const Vec3 m = periodic.minimum_image(d);
    EXPECT_LE(std::abs(m.x), 0.5);
    EXPECT_LE(std::abs(m.y), 0.5);
    EXPECT_EQ(m.z, d.z);  // never wrapped: the floor is a wall
    EXPECT_EQ(periodic.minimum_image(-1.0 * d), -1.0 * m);
    EXPECT_EQ(walls.minimum_image(d), d);
  }
  EXPECT_EQ(periodic.minimum_image({0.7, 0, 0}).x, 0.7 - 1.0);
}

TEST(Container, ImagesOfASphereAcrossPeriodicSides) {
  const Container c = Container::square(1.0, 1.0, true);
  std::vector<Vec3> images;
  c.for_each_image({0.05, 0.97, 0.5}, 0.1, [&](const Vec3& p) { images.push_back(p); });
  ASSERT_EQ(images.size(), 4u);  // itself, across x = 0, across y = 1, across the corner
  EXPECT_EQ(images[0], (Vec3{0.05, 0.97, 0.5}));
  EXPECT_NEAR(images.back().x, 1.05, 1e-15);
  EXPECT_NEAR(images.back().y, -0.03, 1e-15);
  images.clear();
  Container::square(1.0, 1.0, false).for_each_image({0.05, 0.97, 0.5}, 0.1, [&](const Vec3& p) { images.push_back(p); });
  EXPECT_EQ(images.size(), 1u);
}

TEST(Container, PlanesGiveTheDistanceNormalEquationAndVelocity) {
  const Container c{{{-1, 0, 0.5}, {2, 3, 4}}, false};
  const Vec3 x{0.5, 2.5, 1.0};
  const double expected[5] = {0.5, 1.5, 1.5, 2.5, 0.5};  // floor, x low, x high, y low, y high
  ASSERT_EQ(c.plane_count(), 5u);
  for (unsigned w = 0; w < c.plane_count(); ++w) {
    Vec3 towards;
    EXPECT_DOUBLE_EQ(c.plane_distance(w, x, towards), expected[w]) << w;
    const Container::PlaneEquation p = c.plane(w);
    EXPECT_EQ(p.inward, -1.0 * towards) << w;
    EXPECT_DOUBLE_EQ(dot(p.inward, x) - p.offset, expected[w]) << w;
    EXPECT_EQ(Container::plane_velocity(w, ContainerMotion{}, 1.0), Vec3{});  // at rest unless moved
  }
  // A tap: half a sine period of the displacement, every plane moving up and back as one.
  const double w = 2.0 * std::numbers::pi * 30.0;
  const ContainerMotion tap{0.5, 1e-3, w, 0.5};
  EXPECT_DOUBLE_EQ(tap.end(), 0.5 + 1.0 / 60.0);
  EXPECT_DOUBLE_EQ(tap.offset(0.5 + 1.0 / 120.0), 1e-3);                     // the top, a quarter period in
  EXPECT_NEAR(tap.velocity(0.5 + 1e-9), 1e-3 * w, 1e-9);                      // rising at A w
  EXPECT_NEAR(Container::plane_velocity(3, tap, tap.end() - 1e-9).z, -1e-3 * w, 1e-9);  // coming back at A w
  EXPECT_EQ(tap.offset(0.4), 0.0);
  EXPECT_EQ(tap.velocity(tap.end() + 1e-9), 0.0);  // stopped dead
  EXPECT_EQ(Container::square(1, 1, true).plane_count(), 1u);  // periodic: the floor only
}

}  // namespace
}  // namespace aggpack

namespace aggpack {
namespace {

// A cylinder of diameter 2 about (1, 1): its wall's distance is R less the distance from the
// axis, towards the horizontal direction out of the axis through the point.
TEST(Container, ACylindersWallIsAtTheRadiusFromItsAxis) {
  const Container c = Container::cylinder(2.0, 3.0);
  EXPECT_TRUE(c.is_cylinder());
  EXPECT_FALSE(c.periodic);
  EXPECT_EQ(c.plane_count(), 2u);
  EXPECT_DOUBLE_EQ(c.radius(), 1.0);
  EXPECT_DOUBLE_EQ(c.rim, 3.0);
  EXPECT_DOUBLE_EQ(c.cross_section_area(), std::numbers::pi);
  EXPECT_DOUBLE_EQ(Container::square(2.0, 3.0, false).cross_section_area(), 4.0);
  Vec3 towards;
  // On the axis: the whole radius, some horizontal unit vector.
  EXPECT_DOUBLE_EQ(c.plane_distance(Container::kCylinderWall, {1.0, 1.0, 0.7}, towards), 1.0);
  EXPECT_DOUBLE_EQ(norm(towards), 1.0);
  EXPECT_EQ(towards.z, 0.0);
  // Halfway out along (3, 4) / 5, at any height.
  EXPECT_NEAR(c.plane_distance(Container::kCylinderWall, {1.3, 1.4, 2.5}, towards), 0.5, 1e-15);
  EXPECT_NEAR(towards.x, 0.6, 1e-15);
  EXPECT_NEAR(towards.y, 0.8, 1e-15);
  EXPECT_EQ(towards.z, 0.0);
  // On the wall, and beyond it (negative).
  EXPECT_NEAR(c.plane_distance(Container::kCylinderWall, {1.0 - std::sqrt(0.5), 1.0 + std::sqrt(0.5), 1.0}, towards),
              0.0, 1e-15);
  EXPECT_NEAR(towards.x, -std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(c.plane_distance(Container::kCylinderWall, {3.0, 1.0, 1.0}, towards), -1.0, 1e-15);
  EXPECT_EQ(towards, (Vec3{1.0, 0.0, 0.0}));
  // The floor is a box's floor; the corners of the bounds are outside.
  EXPECT_DOUBLE_EQ(c.plane_distance(Container::kFloor, {1.3, 1.4, 2.5}, towards), 2.5);
  EXPECT_EQ(towards, (Vec3{0, 0, -1}));
  EXPECT_TRUE(c.holds_horizontally({1.5, 1.5, 0.0}));
  EXPECT_FALSE(c.holds_horizontally({0.1, 0.1, 0.0}));
  // The largest centred square keeping 0.1 from the wall: its corners at R - 0.1.
  EXPECT_NEAR(c.widest_centred_square(0.1), std::sqrt(2.0) * 0.9, 1e-15);
  EXPECT_DOUBLE_EQ(Container::square(2.0, 3.0, false).widest_centred_square(0.1), 1.8);
  EXPECT_DOUBLE_EQ(Container::square(2.0, 3.0, true).widest_centred_square(0.1), 2.0);
}

TEST(Container, ShapesHaveTheirNames) {
  EXPECT_EQ(name_of(kContainerShapeNames, ContainerShape::Cylinder), "cylinder");
  EXPECT_EQ(value_of(kContainerShapeNames, "box"), ContainerShape::Box);
  EXPECT_FALSE(value_of(kContainerShapeNames, "cone").has_value());
}

}  // namespace
}  // namespace aggpack
