#include "aggpack/deposition/contact_geometry.hpp"

#include <gtest/gtest.h>

#include <numbers>
#include <random>

namespace aggpack {
namespace {

constexpr Vec3 kUp{0, 0, 1};
Vec3 unit(Vec3 v) { return v * (1.0 / norm(v)); }

TEST(SteepestDescent, TheFloorAloneHolds) {
  const std::vector<Vec3> n{kUp};
  const Descent d = steepest_descent(n);
  EXPECT_TRUE(d.at_rest());
  EXPECT_EQ(d.active_count, 1);
}

TEST(SteepestDescent, OnOneSphereTheSphereRollsAlongTheTangent) {
  const Vec3 n = unit({0.6, 0.0, 0.8});
  const Descent d = steepest_descent(std::vector<Vec3>{n});
  ASSERT_EQ(d.active_count, 1);
  EXPECT_NEAR(d.alpha[0], 0.8, 1e-15);
  // -z + 0.8 n = (0.48, 0, -0.36): tangent to the sphere, downhill.
  EXPECT_NEAR(d.direction.x, 0.48, 1e-15);
  EXPECT_NEAR(d.direction.z, -0.36, 1e-15);
  EXPECT_NEAR(dot(d.direction, n), 0.0, 1e-15);
}

TEST(SteepestDescent, ThreeSupportsAroundTheVerticalHold) {
  std::vector<Vec3> n;
  for (int i = 0; i < 3; ++i) {
    const double a = 2 * std::numbers::pi * i / 3;
    n.push_back(unit({0.5 * std::cos(a), 0.5 * std::sin(a), 0.8}));
  }
  const Descent d = steepest_descent(n);
  EXPECT_TRUE(d.at_rest());
  EXPECT_EQ(d.active_count, 3);
}

// method.md's example: the shortcut "drop the most negative coefficient" keeps n3 alone,
// whose roll runs into n1; the right motion rolls on the pair {n1, n3}.
TEST(SteepestDescent, TheSubsetRuleBeatsDroppingTheMostNegativeCoefficient) {
  const std::vector<Vec3> n{unit({0.552, 0.192, 0.812}), unit({-0.828, -0.045, 0.559}), unit({-0.072, 0.044, 0.997})};
  const Descent d = steepest_descent(n);
  ASSERT_EQ(d.active_count, 2);
  EXPECT_EQ(d.active[0], 0);
  EXPECT_EQ(d.active[1], 2);
  EXPECT_NEAR(d.alpha[0], 0.091, 0.005);
  EXPECT_NEAR(d.alpha[1], 0.926, 0.005);
  const Vec3 shortcut = -kUp + n[2].z * n[2];  // rolling on n3 alone
  EXPECT_LT(dot(shortcut, n[0]), -1e-3) << "the shortcut pushes into n1";
  for (const Vec3& ni : n) EXPECT_GE(dot(d.direction, ni), -1e-12);
}

// Moreau: the descent is feasible, and no feasible direction is closer to -z.
TEST(SteepestDescent, IsTheProjectionOfDownOntoTheFeasibleCone) {
  std::mt19937_64 gen(7);
  std::normal_distribution<double> g;
  for (int trial = 0; trial < 300; ++trial) {
    std::vector<Vec3> n;
    const int k = 1 + trial % 4;
    for (int i = 0; i < k; ++i) n.push_back(unit({g(gen), g(gen), std::abs(g(gen)) - 0.3}));
    const Descent d = steepest_descent(n);
    for (const Vec3& ni : n) ASSERT_GE(dot(d.direction, ni), -1e-10) << trial;
    const double best = norm2(d.direction + kUp);
    for (int s = 0; s < 2000; ++s) {
      Vec3 v{g(gen), g(gen), g(gen)};
      v = d.direction + 0.3 * v;  // near the answer
      bool feasible = true;
      for (const Vec3& ni : n) feasible = feasible && dot(v, ni) >= 0.0;
      if (feasible) {
        ASSERT_GE(norm2(v + kUp), best - 1e-12) << trial;
      }
    }
  }
}

TEST(ArcAngle, KeyGrowsWithTheAngle) {
  double previous = -1.0;
  for (int i = 0; i < 1000; ++i) {
    const double t = 2 * std::numbers::pi * i / 1000;
    const ArcAngle a = ArcAngle::at(t);
    EXPECT_GT(a.key, previous) << t;
    EXPECT_NEAR(a.angle(), t, 1e-12);
    previous = a.key;
  }
  EXPECT_LT(previous, 4.0);
}

TEST(FirstEntry, SolvesTheCosineEquation) {
  const double two_pi = 2 * std::numbers::pi;
  const auto all = ArcAngle::at(two_pi - 1e-9);
  // F = 0.5 + cos t is negative on (2 pi/3, 4 pi/3).
  const auto t = first_entry(0.5, 1.0, 0.0, all, 0.0);
  ASSERT_TRUE(t);
  EXPECT_NEAR(t->angle(), two_pi / 3, 1e-14);
  EXPECT_FALSE(first_entry(0.5, 1.0, 0.0, ArcAngle::at(2.0), 0.0));       // beyond the limit
  EXPECT_FALSE(first_entry(1.5, 1.0, 0.0, all, 0.0));                     // never negative
  EXPECT_FALSE(first_entry(1.0 - 1e-10, 1.0, 0.0, all, 1e-9));            // grazes within the skip
  // Already touching and moving in: F = -sin t (k = 0) enters at once.
  EXPECT_EQ(first_entry(0.0, 0.0, -1.0, ArcAngle::at(1.0), 0.0)->angle(), 0.0);
  // Touching and moving away (F = sin t): next entry at pi.
  EXPECT_NEAR(first_entry(0.0, 0.0, 1.0, ArcAngle::at(4.0), 0.0)->angle(), std::numbers::pi, 1e-14);
  // A general case against the root found by bisection.
  const double k = 0.9, a = -0.8, b = 0.9;  // F(0) > 0, rising first
  const auto root = first_entry(k, a, b, all, 0.0);
  ASSERT_TRUE(root);
  const double hi = root->angle();
  const auto f = [&](double x) { return k + a * std::cos(x) + b * std::sin(x); };
  for (double x = 0.0; x < hi - 1e-9; x += 1e-4) ASSERT_GE(f(x), -1e-12) << x;
  EXPECT_NEAR(f(hi), 0.0, 1e-14);
}

TEST(FirstContact, FindsWhereAnArcMeetsASphere) {
  // Unit circle in the xz-plane about the origin from (1,0,0) towards -z. A sphere of
  // contact distance 1 centred at (0, 0, -2) is only grazed at (0, 0, -1): no entry.
  const Arc arc{{0, 0, 0}, 1.0, {1, 0, 0}, {0, 0, -1}, ArcAngle::at(std::numbers::pi)};
  EXPECT_FALSE(first_contact(arc, Obstacle{0, false, {0, 0, -2}, 1.0}, 0.0));
  const Obstacle ball{0, false, {0, 0, -1.9}, 1.0};  // cut near the bottom: entered before pi/2
  const auto t = first_contact(arc, ball, 0.0);
  ASSERT_TRUE(t);
  EXPECT_LT(t->angle(), std::numbers::pi / 2);
  EXPECT_NEAR(ball.gap(arc.point(*t)), 0.0, 1e-14);
  const Obstacle ball2{0, false, {0, 0, -1.5}, 1.0};
  const auto t2 = first_contact(arc, ball2, 0.0);
  ASSERT_TRUE(t2);
  EXPECT_NEAR(ball2.gap(arc.point(*t2)), 0.0, 1e-14);
  const Obstacle floor{kFloor, true, kUp, -0.5};  // z >= -0.5
  const auto t3 = first_contact(arc, floor, 0.0);
  ASSERT_TRUE(t3);
  EXPECT_NEAR(t3->angle(), std::numbers::pi / 6, 1e-14);
}

TEST(Arc, BoundingBoxContainsEveryPointAndIsTight) {
  std::mt19937_64 gen(3);
  std::normal_distribution<double> g;
  for (int trial = 0; trial < 100; ++trial) {
    const Vec3 e1 = unit({g(gen), g(gen), g(gen)});
    const Vec3 e2 = unit(cross(e1, {g(gen), g(gen), g(gen)}));
    const double t_end = 6.0 * std::abs(std::tanh(g(gen)));
    const Arc arc{{g(gen), g(gen), g(gen)}, 0.5 + std::abs(g(gen)), e1, e2, ArcAngle::at(t_end)};
    Vec3 lo, hi, seen_lo{1e9, 1e9, 1e9}, seen_hi{-1e9, -1e9, -1e9};
    arc.bounding_box(lo, hi);
    for (int s = 0; s <= 20000; ++s) {
      const Vec3 p = arc.point(t_end * s / 20000.0);
      for (int a = 0; a < 3; ++a) {
        ASSERT_GE(p[a], lo[a] - 1e-12);
        ASSERT_LE(p[a], hi[a] + 1e-12);
      }
      seen_lo = {std::min(seen_lo.x, p.x), std::min(seen_lo.y, p.y), std::min(seen_lo.z, p.z)};
      seen_hi = {std::max(seen_hi.x, p.x), std::max(seen_hi.y, p.y), std::max(seen_hi.z, p.z)};
    }
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(lo[a], seen_lo[a], 1e-6);
      EXPECT_NEAR(hi[a], seen_hi[a], 1e-6);
    }
  }
}

TEST(SupportName, NamesFloorWallsAndParticles) {
  EXPECT_EQ(support_name(kFloor), "floor");
  EXPECT_EQ(support_name(kWallYHigh), "wall_y_high");
  EXPECT_EQ(support_name(42), "42");
  EXPECT_TRUE(is_wall(kWallXLow));
  EXPECT_FALSE(is_wall(kFloor));
}

}  // namespace
}  // namespace aggpack
