#include "aggpack/core/particle_store.hpp"

#include <gtest/gtest.h>

#include <numbers>

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

}  // namespace
}  // namespace aggpack
