#include "aggpack/core/particle_store.hpp"

#include <gtest/gtest.h>

#include <numbers>
#include <stdexcept>
#include <vector>

#include "aggpack/core/quaternion.hpp"

namespace aggpack {
namespace {

TEST(ParticleStore, AddKeepsEveryArrayInStepAndComputesTheMass) {
  ParticleStore p;
  EXPECT_TRUE(p.empty());
  const auto i = p.add({1, 2, 3}, 0.5, 2000.0, 3);
  const auto j = p.add({4, 5, 6}, 0.25, 2000.0);
  EXPECT_EQ(i, 0u);
  EXPECT_EQ(j, 1u);
  EXPECT_EQ(p.size(), 2u);
  for (std::size_t n : {p.position.size(), p.velocity.size(), p.angular_velocity.size(), p.radius.size(),
                        p.mass.size(), p.layer.size()})
    EXPECT_EQ(n, 2u);
  EXPECT_NEAR(p.mass[0], 2000.0 * 4.0 / 3.0 * std::numbers::pi * 0.125, 1e-12);
  EXPECT_EQ(p.layer[0], 3u);
  EXPECT_EQ(p.velocity[1], Vec3{});
}

// A body's members go to the end of the store, turned by its orientation about its centre;
// the spheres added before and after it are of no body.
TEST(ParticleStore, AddBodyAppendsItsMembersPlacedByItsPose) {
  ParticleStore p;
  p.add({0, 0, 0}, 0.1, 1000.0);
  const std::vector<Vec3> centres{{0.2, 0, 0}, {-0.2, 0, 0}};
  const std::vector<double> radii{0.1, 0.15};
  const RigidBodyShape shape{centres, radii, 0.01, {1e-4, 2e-4, 3e-4}};
  const Quaternion quarter_turn = axis_angle({0, 0, 1}, std::numbers::pi / 2);
  EXPECT_EQ(p.add_body({1, 2, 3}, quarter_turn, shape, 2000.0, 4, 1), 0u);
  p.add({5, 5, 5}, 0.1, 1000.0);
  ASSERT_EQ(p.size(), 4u);
  EXPECT_EQ(p.body, (std::vector<std::uint32_t>{kNoBody, 0, 0, kNoBody}));
  ASSERT_EQ(p.body_offset.size(), 4u);
  EXPECT_EQ(p.body_offset[2], centres[1]);
  EXPECT_NEAR(p.position[1].x, 1.0, 1e-15);  // (0.2, 0, 0) turned a quarter about z: (0, 0.2, 0)
  EXPECT_NEAR(p.position[1].y, 2.2, 1e-15);
  EXPECT_EQ(p.radius[2], 0.15);
  EXPECT_EQ(p.layer[1], 4u);
  EXPECT_EQ(p.material[2], 1u);
  ASSERT_EQ(p.bodies.size(), 1u);
  EXPECT_EQ(p.bodies.first_member[0], 1u);
  EXPECT_EQ(p.bodies.member_count[0], 2u);
  EXPECT_EQ(p.bodies.mass[0], 20.0);
  EXPECT_EQ(p.bodies.principal_inertia[0], (Vec3{0.2, 0.4, 0.6}));
  EXPECT_EQ(p.bodies.orientation[0], quarter_turn);
}

TEST(ParticleStore, AddBodyRefusesAShapeWithoutMembersOrMass) {
  ParticleStore p;
  const std::vector<Vec3> centres{{0, 0, 0}};
  const std::vector<double> radii{0.1}, two_radii{0.1, 0.2};
  EXPECT_THROW(p.add_body({}, {}, {{}, {}, 1.0, {1, 1, 1}}, 1.0), std::invalid_argument);
  EXPECT_THROW(p.add_body({}, {}, {centres, two_radii, 1.0, {1, 1, 1}}, 1.0), std::invalid_argument);
  EXPECT_THROW(p.add_body({}, {}, {centres, radii, 0.0, {1, 1, 1}}, 1.0), std::invalid_argument);
  EXPECT_THROW(p.add_body({}, {}, {centres, radii, 1.0, {1, -1, 1}}, 1.0), std::invalid_argument);
  EXPECT_TRUE(p.empty());
  EXPECT_TRUE(p.bodies.empty());
}

}  // namespace
}  // namespace aggpack
