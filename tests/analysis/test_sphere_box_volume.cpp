#include "aggpack/analysis/sphere_box_volume.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <random>
#include <vector>

namespace aggpack {
namespace {

constexpr double kPi = std::numbers::pi;
double ball(double r) { return 4.0 / 3.0 * kPi * r * r * r; }

// --- An independent oracle: nested tanh-sinh quadrature in long double of the exact
// chord lengths, split at every kink, so endpoint square roots cost no accuracy.
using LD = long double;
LD tanh_sinh(const std::function<LD(LD)>& f, LD a, LD b) {
  if (!(b > a)) return 0.0L;
  const LD h = 1.0L / 32.0L, half = 0.5L * (b - a), mid = 0.5L * (a + b);
  const LD pi2 = std::numbers::pi_v<LD> / 2.0L;
  LD sum = 0.0L;
  for (int k = -112; k <= 112; ++k) {
    const LD t = h * k;
    const LD u = pi2 * std::sinh(t);
    const LD x = std::tanh(u);
    const LD w = pi2 * std::cosh(t) / (std::cosh(u) * std::cosh(u));
    const LD xi = mid + half * x;
    if (xi <= a || xi >= b) continue;
    sum += w * f(xi);
  }
  return sum * h * half;
}
LD integrate_pieces(const std::function<LD(LD)>& f, LD a, LD b, std::vector<LD> cuts) {
  cuts.push_back(a);
  cuts.push_back(b);
  std::sort(cuts.begin(), cuts.end());
  LD total = 0.0L;
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
    const LD lo = std::max(a, cuts[i]), hi = std::min(b, cuts[i + 1]);
    if (hi > lo) total += tanh_sinh(f, lo, hi);
  }
  return total;
}
double oracle_volume(const Vec3& c, double R, const Box& box) {
  const LD r = R;
  const LD x0 = box.lo.x - c.x, x1 = box.hi.x - c.x, y0 = box.lo.y - c.y, y1 = box.hi.y - c.y;
  const LD z0 = std::max<LD>(box.lo.z - c.z, -r), z1 = std::min<LD>(box.hi.z - c.z, r);
  const auto area = [&](LD z) {
    const LD rho2 = r * r - z * z;
    if (rho2 <= 0) return 0.0L;
    const LD rho = std::sqrt(rho2);
    const LD a = std::max(x0, -rho), b = std::min(x1, rho);
    std::vector<LD> cuts;
    for (LD y : {y0, y1})
      if (std::abs(y) < rho) cuts.push_back(std::sqrt(rho2 - y * y)), cuts.push_back(-std::sqrt(rho2 - y * y));
    const auto chord = [&](LD x) {
      const LD s = std::sqrt(std::max(rho2 - x * x, 0.0L));
      return std::max(0.0L, std::min(y1, s) - std::max(y0, -s));
    };
    return integrate_pieces(chord, a, b, cuts);
  };
  std::vector<LD> cuts;
  for (LD x : {x0, x1})
    for (LD y : {y0, y1, 0.0L})
      for (LD d2 : {x * x + y * y, y * y, x * x})
        if (d2 < r * r) cuts.push_back(std::sqrt(r * r - d2)), cuts.push_back(-std::sqrt(r * r - d2));
  for (LD y : {y0, y1})
    if (y * y < r * r) cuts.push_back(std::sqrt(r * r - y * y)), cuts.push_back(-std::sqrt(r * r - y * y));
  return static_cast<double>(integrate_pieces(area, z0, z1, cuts));
}

TEST(SphereBoxVolume, FaceEdgeAndCornerCentresGiveHalfQuarterEighth) {
  const double R = 0.37;
  const Vec3 c{1.0, 2.0, 3.0};
  const double big = 10.0;
  const Box face{{c.x, c.y - big, c.z - big}, {c.x + big, c.y + big, c.z + big}};
  const Box edge{{c.x, c.y, c.z - big}, {c.x + big, c.y + big, c.z + big}};
  const Box corner{{c.x - big, c.y - big, c.z - big}, {c.x, c.y, c.z}};
  EXPECT_NEAR(sphere_box_volume(c, R, face) / ball(R), 0.5, 1e-14);
  EXPECT_NEAR(sphere_box_volume(c, R, edge) / ball(R), 0.25, 1e-14);
  EXPECT_NEAR(sphere_box_volume(c, R, corner) / ball(R), 0.125, 1e-14);
}

TEST(SphereBoxVolume, CapsMatchTheCapFormula) {
  const double R = 2.0;
  for (double h : {1e-6, 0.01, 0.3, 1.0, 1.7, 2.0, 3.1, 3.99}) {
    const Box box{{-5, -5, R - h}, {5, 5, 5}};  // cut by one face: a cap of height h
    const double expected = kPi * h * h * (3 * R - h) / 3;
    EXPECT_NEAR(sphere_box_volume({0, 0, 0}, R, box), expected, 1e-13 * ball(R)) << "h = " << h;
  }
}

TEST(SphereBoxVolume, OutsideInsideAndBoxInsideSphere) {
  EXPECT_EQ(sphere_box_volume({0, 0, 0}, 1.0, {{1.0, -1, -1}, {2, 1, 1}}), 0.0);    // touching a face
  EXPECT_EQ(sphere_box_volume({0, 0, 0}, 1.0, {{0.8, 0.8, 0.8}, {2, 2, 2}}), 0.0);  // corner beyond the sphere
  EXPECT_NEAR(sphere_box_volume({0, 0, 0}, 1.0, {{-1, -1, -1}, {1, 1, 1}}), ball(1.0), 1e-15);
  const Box small{{-0.2, -0.1, 0.0}, {0.3, 0.25, 0.4}};  // wholly inside the ball
  EXPECT_NEAR(sphere_box_volume({0, 0, 0}, 1.0, small), small.volume(), 1e-15);
}

TEST(SphereBoxVolume, EightOctantsSumToTheSphere) {
  std::mt19937_64 gen(7);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3 c{0.1, -0.2, 0.3};
    const double R = 1.0;
    const Vec3 p{u(gen), u(gen), u(gen)};  // the split point, inside or outside the sphere
    double sum = 0.0;
    for (int o = 0; o < 8; ++o) {
      Box b{{-5, -5, -5}, {5, 5, 5}};
      (o & 1 ? b.lo.x : b.hi.x) = p.x;
      (o & 2 ? b.lo.y : b.hi.y) = p.y;
      (o & 4 ? b.lo.z : b.hi.z) = p.z;
      sum += sphere_box_volume(c, R, b);
    }
    EXPECT_NEAR(sum, ball(R), 1e-13) << "split at " << p.x << " " << p.y << " " << p.z;
  }
}

TEST(SphereBoxVolume, RandomCasesMatchTheQuadratureOracleTo1e12) {
  std::mt19937_64 gen(2024);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int cut_by_three = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const double R = 0.2 + u(gen);
    const Vec3 c{u(gen) - 0.5, u(gen) - 0.5, u(gen) - 0.5};
    // Box sides from much smaller to much larger than the sphere.
    const double sx = 0.1 + 2.5 * u(gen), sy = 0.1 + 2.5 * u(gen), sz = 0.1 + 2.5 * u(gen);
    const Vec3 lo{u(gen) - 1.0 - 0.5 * sx, u(gen) - 1.0 - 0.5 * sy, u(gen) - 1.0 - 0.5 * sz};
    const Box box{lo, lo + Vec3{sx, sy, sz}};
    const double exact = sphere_box_volume(c, R, box);
    const double oracle = oracle_volume(c, R, box);
    EXPECT_NEAR(exact, oracle, 1e-12 * ball(R)) << "trial " << trial;
    if (oracle > 1e-3 * ball(R)) {
      EXPECT_NEAR(exact / oracle, 1.0, 1e-12) << "trial " << trial;
    }
    int faces = 0;
    for (int a = 0; a < 3; ++a) faces += (std::abs(box.lo[a] - c[a]) < R) + (std::abs(box.hi[a] - c[a]) < R);
    cut_by_three += faces >= 3;
  }
  EXPECT_GT(cut_by_three, 10);  // the sample really exercises the three-plane pieces
}

// Monte Carlo with 2e6 samples in the sphere's bounding cube; within 4 standard errors.
void expect_matches_monte_carlo(const Vec3& c, double R, const Box& box, std::uint64_t seed) {
  std::mt19937_64 gen(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int n = 2'000'000;
  int hits = 0;
  for (int i = 0; i < n; ++i) {
    const Vec3 d{u(gen), u(gen), u(gen)};
    if (norm2(d) > 1.0) continue;
    hits += box.contains(c + R * d);
  }
  const double cube = 8 * R * R * R;
  const double p = static_cast<double>(hits) / n;
  const double estimate = p * cube;
  const double standard_error = cube * std::sqrt(p * (1 - p) / n);
  const double exact = sphere_box_volume(c, R, box);
  EXPECT_NEAR(exact, estimate, 4 * standard_error + 1e-15) << "exact " << exact << " MC " << estimate;
}

TEST(SphereBoxVolume, MatchesMonteCarloForEveryKindOfCut) {
  const Vec3 c{0.0, 0.0, 0.0};
  const double R = 1.0;
  expect_matches_monte_carlo(c, R, {{0.3, -5, -5}, {5, 5, 5}}, 1);         // one face
  expect_matches_monte_carlo(c, R, {{-0.4, 0.2, -5}, {5, 5, 5}}, 2);       // two faces
  expect_matches_monte_carlo(c, R, {{0.1, -0.5, 0.35}, {5, 5, 5}}, 3);     // three faces, centre outside
  expect_matches_monte_carlo(c, R, {{-0.6, -0.7, -0.2}, {5, 5, 5}}, 4);    // three faces, centre inside
  expect_matches_monte_carlo(c, R, {{-0.5, -0.3, -0.9}, {0.4, 0.6, 0.2}}, 5);  // sphere larger than the box
  expect_matches_monte_carlo(c, R, {{-0.2, -5, -0.3}, {0.4, 5, 0.5}}, 6);  // two faces per axis on x and z
  expect_matches_monte_carlo(c, R, {{0.5, 0.5, 0.5}, {0.9, 0.9, 0.9}}, 7); // small box at the edge of the ball
}

TEST(SphereBoxVolume, PiecesAreSymmetricInTheirOffsets) {
  const double R = 1.3;
  EXPECT_NEAR(ball_corner_volume(R, 0.1, 0.4, 0.7), ball_corner_volume(R, 0.7, 0.1, 0.4), 1e-14);
  EXPECT_NEAR(ball_corner_volume(R, 0.2, 0.5, 0.0), ball_corner_volume(R, 0.0, 0.2, 0.5), 1e-14);
  EXPECT_NEAR(ball_wedge_volume(R, 0.0, 0.0), ball(R) / 4, 1e-14);
  EXPECT_NEAR(ball_corner_volume(R, 0.0, 0.0, 0.0), ball(R) / 8, 1e-14);
  EXPECT_NEAR(4 * ball_corner_volume(R, 0.0, 0.0, 0.6), ball_cap_volume(R, 0.6), 1e-14);
}

}  // namespace
}  // namespace aggpack
