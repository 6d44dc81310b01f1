// The volume of a union of spheres inside a box: one sphere and disjoint spheres against the
// exact sphere-box volume (analysis/, an independent closed form), the whole union against
// its mass properties, boxes that split the union adding up to it, and Monte Carlo on an
// overlapping cluster cut by one, two and three planes.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>
#include <vector>

#include "aggpack/analysis/sphere_box_volume.hpp"
#include "aggpack/grains/union_mass_properties.hpp"

namespace aggpack {
namespace {

const std::vector<MemberSphere> kCluster{{{0.0, 0.0, 0.0}, 1.0},    {{0.9, 0.4, 0.1}, 0.7},
                                         {{1.5, -0.3, 0.6}, 0.5},   {{-0.6, 0.8, -0.5}, 0.6},
                                         {{-0.2, -0.9, 0.7}, 0.45}, {{2.05, -0.3, 0.6}, 0.3}};

// Boxes cutting the cluster by one plane (x), two (x, y) and three (x, y, z); the rest far.
const std::vector<Box> kCuts{{{0.3, -5, -5}, {5, 5, 5}}, {{0.3, -0.2, -5}, {5, 5, 5}}, {{0.3, -0.2, 0.25}, {5, 5, 5}},
                             {{-0.4, -0.5, -0.3}, {1.1, 0.6, 0.4}}};

TEST(UnionBoxVolume, OneSphereIsTheExactSphereBoxVolume) {
  const MemberSphere s{{0.2, -0.1, 0.3}, 0.8};
  const double ball = 4.0 / 3.0 * std::numbers::pi * 0.512;
  for (const Box& box : kCuts)
    EXPECT_NEAR(union_volume_in_box(std::vector{s}, box), sphere_box_volume(s.centre, s.radius, box), 1e-9 * ball);
}

TEST(UnionBoxVolume, DisjointSpheresAddTheirSphereBoxVolumes) {
  const std::vector<MemberSphere> apart{{{0, 0, 0}, 0.5}, {{1.2, 0.1, 0}, 0.6}, {{0.4, 1.3, 0.5}, 0.4}};
  for (const Box& box : kCuts) {
    double exact = 0.0;
    for (const MemberSphere& s : apart) exact += sphere_box_volume(s.centre, s.radius, box);
    EXPECT_NEAR(union_volume_in_box(apart, box), exact, 1e-9);
  }
}

// A box around the whole union holds its volume; boxes that split it hold it between them,
// whichever way and wherever the cut falls, each point once.
TEST(UnionBoxVolume, BoxesThatSplitTheUnionAddUpToIt) {
  const double whole = union_mass_properties(kCluster, 1e-11).volume;
  EXPECT_NEAR(union_volume_in_box(kCluster, {{-9, -9, -9}, {9, 9, 9}}), whole, 1e-9 * whole);
  for (int axis = 0; axis < 3; ++axis)
    for (const double cut : {-0.7, 0.05, 0.9, 1.6}) {
      Box below{{-9, -9, -9}, {9, 9, 9}}, above = below;
      (axis == 0 ? below.hi.x : axis == 1 ? below.hi.y : below.hi.z) = cut;
      (axis == 0 ? above.lo.x : axis == 1 ? above.lo.y : above.lo.z) = cut;
      EXPECT_NEAR(union_volume_in_box(kCluster, below) + union_volume_in_box(kCluster, above), whole, 1e-9 * whole)
          << "axis " << axis << " at " << cut;
    }
  // Eight octants about a point inside.
  double octants = 0.0;
  for (int k = 0; k < 8; ++k) {
    Box b{{-9, -9, -9}, {9, 9, 9}};
    const Vec3 at{0.35, -0.15, 0.2};
    (k & 1 ? b.lo.x : b.hi.x) = at.x;
    (k & 2 ? b.lo.y : b.hi.y) = at.y;
    (k & 4 ? b.lo.z : b.hi.z) = at.z;
    octants += union_volume_in_box(kCluster, b);
  }
  EXPECT_NEAR(octants, whole, 1e-9 * whole);
}

// Monte Carlo: 2 x 10^6 points in the part of the box around the cluster, each estimate
// within 5 of its standard errors (about 1e-3 of the volume: a test that can fail).
TEST(UnionBoxVolume, AnOverlappingClusterCutByOneTwoAndThreePlanesAgreesWithMonteCarlo) {
  std::mt19937_64 rng(38);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Box around{{-1.2, -1.35, -1.1}, {2.35, 1.2, 1.15}};
  for (const Box& cut : kCuts) {
    const Box b{{std::max(cut.lo.x, around.lo.x), std::max(cut.lo.y, around.lo.y), std::max(cut.lo.z, around.lo.z)},
                {std::min(cut.hi.x, around.hi.x), std::min(cut.hi.y, around.hi.y), std::min(cut.hi.z, around.hi.z)}};
    constexpr int kSamples = 2'000'000;
    int inside = 0;
    for (int n = 0; n < kSamples; ++n) {
      const Vec3 q{b.lo.x + (b.hi.x - b.lo.x) * u(rng), b.lo.y + (b.hi.y - b.lo.y) * u(rng),
                   b.lo.z + (b.hi.z - b.lo.z) * u(rng)};
      for (const MemberSphere& s : kCluster)
        if (norm2(q - s.centre) <= s.radius * s.radius) {
          ++inside;
          break;
        }
    }
    const double p = static_cast<double>(inside) / kSamples;
    const double estimate = b.volume() * p, error = b.volume() * std::sqrt(p * (1 - p) / kSamples);
    const double volume = union_volume_in_box(kCluster, cut);
    EXPECT_NEAR(volume, estimate, 5.0 * error);
    EXPECT_LT(error, 2e-3 * volume);
    // The default tolerance against a tight one.
    EXPECT_NEAR(volume, union_volume_in_box(kCluster, cut, 1e-12), 1e-8 * volume);
  }
}

TEST(UnionBoxVolume, ABoxMissingTheUnionOrFlatHoldsNothingAndBadInputIsRefused) {
  EXPECT_EQ(union_volume_in_box(kCluster, {{5, 5, 5}, {6, 6, 6}}), 0.0);
  EXPECT_EQ(union_volume_in_box(kCluster, {{0, 0, 0}, {0, 1, 1}}), 0.0);
  EXPECT_THROW((void)union_volume_in_box({}, {{0, 0, 0}, {1, 1, 1}}), std::invalid_argument);
  EXPECT_THROW((void)union_volume_in_box(kCluster, {{0, 0, 0}, {-1, 1, 1}}), std::invalid_argument);
  const std::vector<MemberSphere> bad{{{0, 0, 0}, -1.0}};
  EXPECT_THROW((void)union_volume_in_box(bad, {{0, 0, 0}, {1, 1, 1}}), std::invalid_argument);
}

}  // namespace
}  // namespace aggpack
