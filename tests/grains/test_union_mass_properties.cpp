// The mass properties of unions of spheres against closed forms (one sphere, disjoint
// spheres by parallel axes, a two-sphere dumbbell as a solid of revolution integrated
// independently) and against Monte Carlo on an asymmetric cluster.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>
#include <vector>

#include "aggpack/grains/union_mass_properties.hpp"

namespace aggpack {
namespace {

constexpr double kPi = std::numbers::pi;

double ball_volume(double r) {
  return 4.0 / 3.0 * kPi * r * r * r;
}

// Expects every component of two tensors within `tolerance` (absolute).
void expect_tensor_near(const InertiaTensor& got, const InertiaTensor& want, double tolerance) {
  for (std::size_t k = 0; k < 6; ++k) EXPECT_NEAR(got[k], want[k], tolerance) << "component " << k;
}

TEST(UnionMassProperties, OneSphereIsTheBall) {
  const double r = 0.7;
  const std::vector<MemberSphere> one{{{1.0, -2.0, 3.0}, r}};
  const MassProperties p = union_mass_properties(one);
  const double v = ball_volume(r), i = 0.4 * v * r * r;
  EXPECT_NEAR(p.volume, v, 1e-12 * v);
  EXPECT_NEAR(p.centre_of_mass.x, 1.0, 1e-12);
  EXPECT_NEAR(p.centre_of_mass.y, -2.0, 1e-12);
  EXPECT_NEAR(p.centre_of_mass.z, 3.0, 1e-12);
  expect_tensor_near(p.inertia, {i, i, i, 0.0, 0.0, 0.0}, 1e-11 * i);
}

TEST(UnionMassProperties, DisjointSpheresAddByParallelAxes) {
  const std::vector<MemberSphere> two{{{0.0, 0.0, 0.0}, 1.0}, {{3.0, 1.0, -2.0}, 0.5}};
  const MassProperties p = union_mass_properties(two);
  const double v1 = ball_volume(1.0), v2 = ball_volume(0.5), v = v1 + v2;
  const Vec3 c = (two[0].centre * v1 + two[1].centre * v2) * (1.0 / v);
  InertiaTensor want{};
  for (std::size_t k = 0; k < 2; ++k) {
    const double vk = k == 0 ? v1 : v2, own = 0.4 * vk * two[k].radius * two[k].radius;
    const Vec3 d = two[k].centre - c;
    const std::array<double, 6> shift{
        d.y * d.y + d.z * d.z, d.x * d.x + d.z * d.z, d.x * d.x + d.y * d.y, -d.x * d.y, -d.x * d.z, -d.y * d.z};
    for (std::size_t j = 0; j < 6; ++j) want[j] += (j < 3 ? own : 0.0) + vk * shift[j];
  }
  EXPECT_NEAR(p.volume, v, 1e-11 * v);
  EXPECT_NEAR(p.centre_of_mass.x, c.x, 1e-11);
  EXPECT_NEAR(p.centre_of_mass.y, c.y, 1e-11);
  EXPECT_NEAR(p.centre_of_mass.z, c.z, 1e-11);
  expect_tensor_near(p.inertia, want, 1e-10 * want[0]);
}

// Two overlapping spheres (radii r1 at s = 0, r2 at s = d on one axis): a solid of revolution
// whose radius² is r1² - s² up to where the spheres' surfaces cross, then r2² - (s - d)².
// Its volume, centroid and moments, integrated along the axis piece by piece with 4-point
// Gauss-Legendre (exact for these polynomials of degree 6 at most): an independent method.
struct Dumbbell {
  double r1, r2, d;
  double volume = 0.0, centroid = 0.0, axial = 0.0, transverse = 0.0;

  Dumbbell(double r1_, double r2_, double d_) : r1(r1_), r2(r2_), d(d_) {
    const double cross = (d * d + r1 * r1 - r2 * r2) / (2.0 * d);
    const auto rho2 = [&](double s) { return s < cross ? r1 * r1 - s * s : r2 * r2 - (s - d) * (s - d); };
    const std::array<double, 4> node{-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526};
    const std::array<double, 4> weight{0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538};
    const auto integrate = [&](auto f) {
      double sum = 0.0;
      for (const auto& [a, b] : {std::pair{-r1, cross}, std::pair{cross, d + r2}})
        for (std::size_t k = 0; k < 4; ++k) {
          const double s = 0.5 * (a + b) + 0.5 * (b - a) * node[k];
          sum += 0.5 * (b - a) * weight[k] * f(s);
        }
      return sum;
    };
    volume = integrate([&](double s) { return kPi * rho2(s); });
    centroid = integrate([&](double s) { return kPi * rho2(s) * s; }) / volume;
    axial = integrate([&](double s) { return 0.5 * kPi * rho2(s) * rho2(s); });
    transverse = integrate(
        [&](double s) { return 0.25 * kPi * rho2(s) * rho2(s) + kPi * rho2(s) * (s - centroid) * (s - centroid); });
  }
};

TEST(UnionMassProperties, OverlappingPairIsTheSolidOfRevolutionAlongEachAxis) {
  const Dumbbell bell(1.0, 0.6, 1.1);
  // The lens of two spheres, as a check of the oracle itself: V = V1 + V2 - lens.
  const double lens = kPi * std::pow(bell.r1 + bell.r2 - bell.d, 2) *
                      (bell.d * bell.d + 2.0 * bell.d * (bell.r1 + bell.r2) - 3.0 * std::pow(bell.r1 - bell.r2, 2)) /
                      (12.0 * bell.d);
  ASSERT_NEAR(bell.volume, ball_volume(bell.r1) + ball_volume(bell.r2) - lens, 1e-12 * bell.volume);
  const Vec3 base{0.3, -0.2, 0.5};
  for (int axis = 0; axis < 3; ++axis) {
    SCOPED_TRACE(testing::Message() << "along axis " << axis);
    Vec3 unit{};
    (axis == 0 ? unit.x : axis == 1 ? unit.y : unit.z) = 1.0;
    const std::vector<MemberSphere> pair{{base, bell.r1}, {base + unit * bell.d, bell.r2}};
    const MassProperties p = union_mass_properties(pair);
    EXPECT_NEAR(p.volume, bell.volume, 1e-9 * bell.volume);
    const Vec3 c = base + unit * bell.centroid;
    EXPECT_NEAR(p.centre_of_mass.x, c.x, 1e-9);
    EXPECT_NEAR(p.centre_of_mass.y, c.y, 1e-9);
    EXPECT_NEAR(p.centre_of_mass.z, c.z, 1e-9);
    InertiaTensor want{bell.transverse, bell.transverse, bell.transverse, 0.0, 0.0, 0.0};
    want[static_cast<std::size_t>(axis)] = bell.axial;
    expect_tensor_near(p.inertia, want, 1e-9 * bell.transverse);
  }
}

TEST(UnionMassProperties, ASphereInsideAnotherAndTwinSpheresCountOnce) {
  const double r = 1.2;
  const std::vector<MemberSphere> nested{{{0.0, 0.0, 0.0}, r}, {{0.3, 0.2, -0.1}, 0.5}};
  const std::vector<MemberSphere> twins{{{0.0, 0.0, 0.0}, r}, {{0.0, 0.0, 0.0}, r}};
  for (const auto& spheres : {nested, twins}) {
    const MassProperties p = union_mass_properties(spheres);
    EXPECT_NEAR(p.volume, ball_volume(r), 1e-10 * ball_volume(r));
    EXPECT_NEAR(p.inertia[0], 0.4 * ball_volume(r) * r * r, 1e-9 * ball_volume(r) * r * r);
  }
}

// An asymmetric cluster of six spheres (overlapping in chains, one pair nearly tangent)
// against Monte Carlo: 4 x 10^6 points in the bounding box, each estimate within 5 of its
// standard errors; and the quadrature at 1e-6 against itself at 1e-11 within 1e-6.
TEST(UnionMassProperties, AnAsymmetricClusterAgreesWithMonteCarlo) {
  const std::vector<MemberSphere> cluster{{{0.0, 0.0, 0.0}, 1.0},    {{0.9, 0.4, 0.1}, 0.7},
                                          {{1.5, -0.3, 0.6}, 0.5},   {{-0.6, 0.8, -0.5}, 0.6},
                                          {{-0.2, -0.9, 0.7}, 0.45}, {{2.05, -0.3, 0.6}, 0.3}};
  const MassProperties p = union_mass_properties(cluster);
  Vec3 lo{1e9, 1e9, 1e9}, hi{-1e9, -1e9, -1e9};
  for (const MemberSphere& s : cluster)
    for (int a = 0; a < 3; ++a) {
      double& l = a == 0 ? lo.x : a == 1 ? lo.y : lo.z;
      double& h = a == 0 ? hi.x : a == 1 ? hi.y : hi.z;
      l = std::min(l, s.centre[a] - s.radius);
      h = std::max(h, s.centre[a] + s.radius);
    }
  const double box = (hi.x - lo.x) * (hi.y - lo.y) * (hi.z - lo.z);
  std::mt19937_64 rng(20261205);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  constexpr int kSamples = 4'000'000;
  // Per point inside: 1, x, y, z and the second moments about the quadrature's centre of
  // mass (so that the comparison is of the tensor itself); sums and sums of squares.
  std::array<double, 10> sum{}, sum2{};
  const Vec3 c = p.centre_of_mass;
  for (int n = 0; n < kSamples; ++n) {
    const Vec3 q{lo.x + (hi.x - lo.x) * u(rng), lo.y + (hi.y - lo.y) * u(rng), lo.z + (hi.z - lo.z) * u(rng)};
    bool inside = false;
    for (const MemberSphere& s : cluster) inside = inside || norm2(q - s.centre) <= s.radius * s.radius;
    if (!inside) continue;
    const Vec3 d = q - c;
    const std::array<double, 10> f{
        1.0,        q.x,        q.y,       q.z, d.y * d.y + d.z * d.z, d.x * d.x + d.z * d.z, d.x * d.x + d.y * d.y,
        -d.x * d.y, -d.x * d.z, -d.y * d.z};
    for (std::size_t k = 0; k < 10; ++k) sum[k] += f[k], sum2[k] += f[k] * f[k];
  }
  // Each integral is box * mean over all samples; its standard error from the samples' spread.
  std::array<double, 10> estimate{}, error{};
  for (std::size_t k = 0; k < 10; ++k) {
    const double mean = sum[k] / kSamples, var = sum2[k] / kSamples - mean * mean;
    estimate[k] = box * mean;
    error[k] = box * std::sqrt(var / kSamples);
  }
  EXPECT_NEAR(p.volume, estimate[0], 5.0 * error[0]);
  EXPECT_NEAR(p.centre_of_mass.x * p.volume, estimate[1], 5.0 * error[1]);
  EXPECT_NEAR(p.centre_of_mass.y * p.volume, estimate[2], 5.0 * error[2]);
  EXPECT_NEAR(p.centre_of_mass.z * p.volume, estimate[3], 5.0 * error[3]);
  for (std::size_t k = 0; k < 6; ++k)
    EXPECT_NEAR(p.inertia[k], estimate[4 + k], 5.0 * error[4 + k]) << "component " << k;
  // Monte Carlo's own resolution here: about 1e-3 of the volume (a test that can fail).
  EXPECT_LT(error[0], 2e-3 * p.volume);

  const MassProperties fine = union_mass_properties(cluster, 1e-11), coarse = union_mass_properties(cluster, 1e-6);
  EXPECT_NEAR(coarse.volume, fine.volume, 1e-6 * fine.volume);
  for (std::size_t k = 0; k < 6; ++k) EXPECT_NEAR(coarse.inertia[k], fine.inertia[k], 1e-6 * fine.inertia[0]);
}

// Sizes far from 1 and spheres that only touch: lengths are taken in units of the clump, so
// a clump of 1e-70 m is as exact as one of 1 m; tangent spheres add up.
TEST(UnionMassProperties, TinyClumpsAndTouchingSpheres) {
  const std::vector<MemberSphere> tiny{{{0.0, 0.0, 0.0}, 1e-70}, {{1.1e-70, 0.0, 0.0}, 0.6e-70}};
  const Dumbbell bell(1.0, 0.6, 1.1);
  EXPECT_NEAR(union_mass_properties(tiny).volume / 1e-210, bell.volume, 1e-9 * bell.volume);
  const std::vector<MemberSphere> touching{{{0.0, 0.0, 0.0}, 1.0}, {{0.0, 0.0, 1.5}, 0.5}, {{1.5, 0.0, 0.0}, 0.5}};
  EXPECT_NEAR(union_mass_properties(touching).volume, ball_volume(1.0) + 2.0 * ball_volume(0.5), 1e-9);
  // Inside touching: a sphere of 0.5 tangent to the inside of the unit sphere adds nothing.
  const std::vector<MemberSphere> inside{{{0.0, 0.0, 0.0}, 1.0}, {{0.5, 0.0, 0.0}, 0.5}};
  EXPECT_NEAR(union_mass_properties(inside).volume, ball_volume(1.0), 1e-9);
}

TEST(UnionMassProperties, RefusesNoSpheresAndRadiiThatAreNotPositive) {
  EXPECT_THROW((void)union_mass_properties({}), std::invalid_argument);
  for (const double r :
       {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    const std::vector<MemberSphere> bad{{{0.0, 0.0, 0.0}, 1.0}, {{0.5, 0.0, 0.0}, r}};
    EXPECT_THROW((void)union_mass_properties(bad), std::invalid_argument) << "radius " << r;
  }
  const std::vector<MemberSphere> one{{{0.0, 0.0, 0.0}, 1.0}};
  EXPECT_THROW((void)union_mass_properties(one, 0.0), std::invalid_argument);
  EXPECT_THROW((void)union_mass_properties(one, 0.1), std::invalid_argument);
  const std::vector<MemberSphere> lost{{{0.0, 0.0, std::numeric_limits<double>::infinity()}, 1.0}};
  EXPECT_THROW((void)union_mass_properties(lost), std::invalid_argument);
  EXPECT_THROW((void)union_mass_properties(one, 1e-15), std::invalid_argument);
}

}  // namespace
}  // namespace aggpack
