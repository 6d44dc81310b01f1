#include "aggpack/deposition/drop_and_roll.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <random>
#include <set>

#include "bed_checks.hpp"

namespace aggpack {
namespace {

constexpr double kDensity = 2650.0;

struct Scene {
  Container container = Container::square(10.0, 10.0, false);
  ParticleStore bed;
  void add(Vec3 c, double r) { bed.add(c, r, kDensity); }
  DropResult drop(double x, double y, double r, std::uint64_t seed = 1) {
    const std::vector<double> radii{r};
    DepositionSettings settings;
    settings.record_paths = true;
    DropAndRoll deposition(bed, container, radii, settings, Rng(seed, 2));
    DropResult res = deposition.drop(x, y, r);
    if (::testing::Test::HasFailure() || std::getenv("AGGPACK_TRACE"))
      for (const Vec3& p : res.path) std::printf("  path %.12f %.12f %.12f\n", p.x, p.y, p.z);
    return res;
  }
};

// The centre at distance s_i = r + r_i from three centres, on the upper side.
Vec3 trilaterate(const std::array<Vec3, 3>& c, const std::array<double, 3>& s) {
  // Subtracting the first equation from the others leaves two planes; their line meets sphere 0.
  const Vec3 a1 = 2.0 * (c[1] - c[0]), a2 = 2.0 * (c[2] - c[0]);
  const double b1 = s[0] * s[0] - s[1] * s[1] + norm2(c[1]) - norm2(c[0]);
  const double b2 = s[0] * s[0] - s[2] * s[2] + norm2(c[2]) - norm2(c[0]);
  const Vec3 dir = cross(a1, a2);
  // A point on both planes: solve in the span of a1, a2.
  const double g11 = dot(a1, a1), g12 = dot(a1, a2), g22 = dot(a2, a2), det = g11 * g22 - g12 * g12;
  const double u = (b1 * g22 - b2 * g12) / det, v = (b2 * g11 - b1 * g12) / det;
  const Vec3 q = u * a1 + v * a2;
  const Vec3 w = q - c[0];
  const double A = norm2(dir), B = 2 * dot(dir, w), C = norm2(w) - s[0] * s[0];
  const double t1 = (-B + std::sqrt(B * B - 4 * A * C)) / (2 * A), t2 = (-B - std::sqrt(B * B - 4 * A * C)) / (2 * A);
  const Vec3 p1 = q + t1 * dir, p2 = q + t2 * dir;
  return p1.z > p2.z ? p1 : p2;
}

void expect_close(const Vec3& got, const Vec3& want, double rel, double scale) {
  EXPECT_NEAR(got.x, want.x, rel * scale);
  EXPECT_NEAR(got.y, want.y, rel * scale);
  EXPECT_NEAR(got.z, want.z, rel * scale);
}

TEST(DropAndRoll, RestsAtTheTetrahedralHeightOnThreeTouchingSpheres) {
  const double R = 0.5;
  Scene s;
  const Vec3 centroid{5.0, 5.0, R};
  const double to_corner = 2 * R / std::sqrt(3.0);  // circumradius of the triangle of centres
  for (int i = 0; i < 3; ++i) {
    const double a = 2 * std::numbers::pi * i / 3 + 0.3;
    s.add(centroid + Vec3{to_corner * std::cos(a), to_corner * std::sin(a), 0}, R);
  }
  const double height = R * (1 + 2 * std::sqrt(2.0 / 3.0));
  std::mt19937_64 gen(11);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 30; ++trial) {
    // Exactly at the centroid (all three hit at once), then off-centre drops that roll in.
    const double dx = trial == 0 ? 0.0 : 0.25 * R * u(gen), dy = trial == 0 ? 0.0 : 0.25 * R * u(gen);
    const DropResult res = s.drop(centroid.x + dx, centroid.y + dy, R);
    ASSERT_TRUE(res.rested);
    EXPECT_NEAR(res.position.z, height, 1e-9 * height) << trial;
    EXPECT_NEAR(res.position.x, centroid.x, 1e-9) << trial;
    EXPECT_NEAR(res.position.y, centroid.y, 1e-9) << trial;
    const std::set<SupportId> supports(res.supports.ids.begin(), res.supports.ids.end());
    EXPECT_EQ(supports, (std::set<SupportId>{0, 1, 2})) << trial;
  }
}

TEST(DropAndRoll, RestsAtTheExactPocketOfThreeUnequalSpheres) {
  Scene s;
  const std::array<double, 3> radii{1.0, 0.8, 0.6};
  // Three floor spheres, each touching the other two.
  const Vec3 c0{4.0, 4.0, radii[0]};
  const Vec3 c1 = c0 + Vec3{std::sqrt(std::pow(radii[0] + radii[1], 2) - std::pow(radii[0] - radii[1], 2)), 0,
                            radii[1] - radii[0]};
  // The third on the floor touching both: horizontal distances s0, s1 from c0, c1.
  const double z2 = radii[2], d01 = c1.x - c0.x;
  const double s0 = std::sqrt(std::pow(radii[0] + radii[2], 2) - std::pow(z2 - c0.z, 2));
  const double s1 = std::sqrt(std::pow(radii[1] + radii[2], 2) - std::pow(z2 - c1.z, 2));
  const double along = (s0 * s0 - s1 * s1 + d01 * d01) / (2 * d01);
  const Vec3 third{c0.x + along, c0.y + std::sqrt(s0 * s0 - along * along), z2};
  s.add(c0, radii[0]);
  s.add(c1, radii[1]);
  s.add(third, radii[2]);
  const double r = 0.7;
  const Vec3 expected = trilaterate({c0, c1, third}, {r + radii[0], r + radii[1], r + radii[2]});
  std::mt19937_64 gen(5);
  std::uniform_real_distribution<double> u(-1, 1);
  // The pocket lies close to the ridge of spheres 1 and 2: drops beyond that ridge rightly
  // roll off outwards, so drop between sphere 0 and the pocket.
  for (int trial = 0; trial < 20; ++trial) {
    const double towards_0 = 0.4 * (u(gen) + 1.0), lateral = 0.03 * u(gen);
    const Vec3 to_0 = c0 - expected;
    const DropResult res = s.drop(expected.x + towards_0 * to_0.x - lateral * to_0.y,
                                  expected.y + towards_0 * to_0.y + lateral * to_0.x, r);
    ASSERT_TRUE(res.rested);
    expect_close(res.position, expected, 1e-9, expected.z);
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(norm(res.position - s.bed.position[i]), r + radii[i], 1e-9 * r);
  }
}

TEST(DropAndRoll, RollsIntoTheGrooveBetweenWallSphereAndFloor) {
  // A small floor sphere near the wall x = 0; a larger sphere dropped between them rolls
  // towards the wall, then down the circle where the wall cuts its sphere of contact.
  Scene s;
  const double R = 0.5, r = 1.0;
  const Vec3 c{1.3, 5.0, R};
  s.add(c, R);
  const DropResult res = s.drop(1.1, 5.1, r);
  ASSERT_TRUE(res.rested);
  const double S = R + r;
  const Vec3 expected{r, c.y + std::sqrt(S * S - std::pow(r - c.x, 2) - std::pow(r - c.z, 2)), r};
  expect_close(res.position, expected, 1e-9, r);
  EXPECT_EQ(res.supports.ids[0], kFloor);
}

TEST(DropAndRoll, RollsOffASingleSphereAndRestsOnTheFloorTouchingIt) {
  for (const double r : {0.5, 0.8}) {  // equal: leaves at the equator just as it lands
    Scene s;
    const double R = 0.5;
    s.add({5.0, 5.0, R}, R);
    const DropResult res = s.drop(5.0 + 0.3 * 0.6, 5.0 + 0.3 * 0.8, r);
    ASSERT_TRUE(res.rested);
    EXPECT_NEAR(res.position.z, r, 1e-12);
    const double horizontal = 2 * std::sqrt(R * r);  // touching the sphere, both on the floor
    expect_close(res.position, Vec3{5.0 + 0.6 * horizontal, 5.0 + 0.8 * horizontal, r}, 1e-9, r);
  }
}

TEST(DropAndRoll, TwoSupportsNeverHoldTheSphereRollsAlongTheGroove) {
  // Two floor spheres with a gap too narrow to pass: the sphere rolls along the groove.
  Scene s;
  const double R = 1.0, r = 1.0, gap = 0.5;
  s.add({3.0, 3.0, R}, R);
  s.add({3.0 + 2 * R + gap, 3.0, R}, R);
  const double mid = 3.0 + R + gap / 2;
  const double rho = std::sqrt(std::pow(R + r, 2) - std::pow(R + gap / 2, 2));
  {
    const DropResult res = s.drop(mid + 0.2, 3.3, r);  // lands on the second, rolls into the groove
    ASSERT_TRUE(res.rested);
    expect_close(res.position, Vec3{mid, 3.0 + rho, r}, 1e-9, r);  // reaches the floor
    EXPECT_EQ(res.supports.ids[0], kFloor);
  }
  // A third sphere along the groove catches it: three supports at the exact pocket.
  s.add({mid, 3.0 + 2.6, R}, R);
  const Vec3 expected = trilaterate({s.bed.position[0], s.bed.position[1], s.bed.position[2]}, {2.0, 2.0, 2.0});
  const DropResult res = s.drop(mid + 0.2, 3.3, r);
  ASSERT_TRUE(res.rested);
  expect_close(res.position, expected, 1e-9, r);
  const std::set<SupportId> supports(res.supports.ids.begin(), res.supports.ids.end());
  EXPECT_EQ(supports, (std::set<SupportId>{0, 1, 2}));
}

// A sphere touching three spheres whose normals are method.md's example must roll on the
// pair {1, 3}; a fourth sphere placed on that circle catches it at a known pocket. The
// shortcut (rolling on 3 alone) would leave sphere 1 and miss the pocket.
TEST(DropAndRoll, TheSubsetRuleFindsThePocket) {
  const auto unit = [](Vec3 v) { return v * (1.0 / norm(v)); };
  const std::array<Vec3, 3> n{unit({0.552, 0.192, 0.812}), unit({-0.828, -0.045, 0.559}),
                              unit({-0.072, 0.044, 0.997})};
  const double r = 0.5, R = 0.5, S = r + R;
  const Vec3 p0{5.0, 5.0, 3.0};
  std::array<Vec3, 4> c;
  for (int i = 0; i < 3; ++i) c[i] = p0 - S * n[i];
  // The circle of supports 1 and 3 (indices 0 and 2) through p0, and its downhill direction.
  const Vec3 axis = unit(c[2] - c[0]);
  const Vec3 m = c[0] + dot(p0 - c[0], axis) * axis;
  const Vec3 e1 = unit(p0 - m);
  Vec3 e2 = unit(cross(axis, e1));
  if (e2.z > 0) e2 = -e2;
  const Arc arc{m, norm(p0 - m), e1, e2, ArcAngle{}};
  const Vec3 q = arc.point(0.15);
  ASSERT_LT(q.z, p0.z);
  const Vec3 n4 = unit(Vec3{0, 0, 1} - 0.3 * unit(q - c[0]) - 0.3 * unit(q - c[2]));
  c[3] = q - S * n4;
  Scene s;
  for (const Vec3& ci : c) s.add(ci, R);
  // Preconditions of the construction: nothing overlaps p0, and sphere 4 is clear of it.
  for (const Vec3& ci : c) ASSERT_GE(norm(p0 - ci), S - 1e-12);
  ASSERT_GT(norm(p0 - c[3]), S + 0.01);
  const DropResult res = s.drop(p0.x, p0.y, r);  // falls onto all three at once
  ASSERT_TRUE(res.rested);
  expect_close(res.position, q, 1e-9, 1.0);
  const std::set<SupportId> supports(res.supports.ids.begin(), res.supports.ids.end());
  EXPECT_EQ(supports, (std::set<SupportId>{0, 2, 3}));
}

TEST(DropAndRoll, LandingExactlyOnTopRollsOffInARandomDirectionAndIsCounted) {
  std::set<int> quadrants;
  for (std::uint64_t seed = 1; seed <= 12; ++seed) {
    Scene s;
    const double R = 0.5;
    s.add({5.0, 5.0, R}, R);
    const DropResult res = s.drop(5.0, 5.0, R, seed);
    ASSERT_TRUE(res.rested);
    EXPECT_EQ(res.ties_on_top, 1);
    const double dx = res.position.x - 5.0, dy = res.position.y - 5.0;
    EXPECT_NEAR(std::hypot(dx, dy), 2 * R, 1e-9);
    EXPECT_NEAR(res.position.z, R, 1e-12);
    quadrants.insert((dx > 0) + 2 * (dy > 0));
  }
  EXPECT_GE(quadrants.size(), 3u);  // the direction is random
}

TEST(DropAndRoll, BalancedOnARidgeRollsOffEitherWayAndIsCounted) {
  std::set<bool> sides;
  for (std::uint64_t seed = 1; seed <= 12; ++seed) {
    Scene s;
    const double R = 1.0;
    s.add({4.0, 5.0, R}, R);
    s.add({6.0, 5.0, R}, R);
    const DropResult res = s.drop(5.0, 5.0, R, seed);  // lands on both at the top of their circle
    ASSERT_TRUE(res.rested);
    EXPECT_EQ(res.ties_on_ridge, 1);
    EXPECT_NEAR(res.position.x, 5.0, 1e-9);
    EXPECT_NEAR(std::abs(res.position.y - 5.0), std::sqrt(3.0), 1e-9);
    sides.insert(res.position.y > 5.0);
  }
  EXPECT_EQ(sides.size(), 2u);
}

// ---- Whole beds, checked by an independent routine (bed_checks.hpp) ----

struct BedCase {
  const char* name;
  std::vector<double> radii;
  bool periodic;
  double side;
};

std::vector<double> shuffled(std::vector<double> v, std::uint64_t seed) {
  std::mt19937_64 gen(seed);
  std::shuffle(v.begin(), v.end(), gen);
  return v;
}

ParticleStore build_bed(const BedCase& c, std::uint64_t seed, DepositionStats* stats = nullptr) {
  ParticleStore bed;
  const Container container = Container::square(c.side, 100.0, c.periodic);
  DropAndRoll deposition(bed, container, c.radii, DepositionSettings{}, Rng(seed, 2));
  deposition.deposit(c.radii, SphereMaterials::all_of(kDensity));
  if (stats) *stats = deposition.stats();
  return bed;
}

std::vector<BedCase> bed_cases() {
  std::vector<BedCase> cases;
  cases.push_back({"monosized", std::vector<double>(10000, 0.5), false, 20.0});
  std::vector<double> binary(6667, 0.25);  // the paper's 0.5 in / 1 in mix, 2:1 by count
  binary.insert(binary.end(), 3333, 0.5);
  cases.push_back({"binary", shuffled(binary, 1), false, 16.0});
  std::vector<double> wide;
  std::mt19937_64 gen(2);
  std::uniform_real_distribution<double> u(0.05, 0.5);  // 1:10 uniform
  for (int i = 0; i < 10000; ++i) wide.push_back(u(gen));
  cases.push_back({"range_1_to_10", wide, false, 12.0});
  cases.push_back({"periodic_monosized", std::vector<double>(10000, 0.5), true, 20.0});
  return cases;
}

TEST(DropAndRollBeds, AreValidByAnIndependentCheck) {
  for (const BedCase& c : bed_cases()) {
    SCOPED_TRACE(c.name);
    DepositionStats stats;
    const ParticleStore bed = build_bed(c, 42, &stats);
    EXPECT_EQ(stats.placed, c.radii.size());
    EXPECT_LT(stats.redrops, c.radii.size() / 1000 + 1) << "redrops are rare";
    const Container container = Container::square(c.side, 100.0, c.periodic);
    const BedReport report = check_bed(bed, container, 1e-9);
    EXPECT_LE(report.worst_overlap, 1e-9) << "relative to the smaller diameter";
    EXPECT_EQ(report.outside_walls, 0u);
    EXPECT_EQ(report.unsupported, 0u) << "first unsupported: " << report.first_unsupported;
    EXPECT_GT(report.on_floor, 0u);
  }
}

TEST(DropAndRollBeds, SameSeedSameBytesOtherSeedOtherPacking) {
  const BedCase c{"small", std::vector<double>(2000, 0.5), false, 10.0};
  const ParticleStore a = build_bed(c, 7), b = build_bed(c, 7), other = build_bed(c, 8);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) ASSERT_EQ(a.position[i], b.position[i]) << i;
  EXPECT_NE(a.position[5], other.position[5]);
}

TEST(DropAndRollBeds, ResumesOnTopOfAnExistingBed) {
  // The layer hook: deposit part, start a new deposition on the same bed, deposit the rest.
  const std::vector<double> radii(3000, 0.5);
  const Container container = Container::square(10.0, 100.0, false);
  ParticleStore bed;
  {
    DropAndRoll first(bed, container, std::span(radii).first(1500), DepositionSettings{}, Rng(3, 2));
    EXPECT_EQ(first.deposit(std::span(radii).first(1500), SphereMaterials::all_of(kDensity), 0), 1500u);
  }
  DropAndRoll second(bed, container, std::span(radii).last(1500), DepositionSettings{}, Rng(3, 102));
  EXPECT_EQ(second.deposit(std::span(radii).last(1500), SphereMaterials::all_of(kDensity), 1), 1500u);
  ASSERT_EQ(bed.size(), 3000u);
  EXPECT_EQ(bed.layer[2999], 1u);
  const BedReport report = check_bed(bed, container, 1e-9);
  EXPECT_LE(report.worst_overlap, 1e-9);
  EXPECT_EQ(report.unsupported, 0u);
}

TEST(DropAndRollBeds, StopsAtTheFillHeight) {
  const std::vector<double> radii(5000, 0.5);
  const Container container = Container::square(10.0, 100.0, false);
  ParticleStore bed;
  DepositionSettings settings;
  settings.fill_height = 4.0;
  DropAndRoll deposition(bed, container, radii, settings, Rng(1, 2));
  const std::size_t placed = deposition.deposit(radii, SphereMaterials::all_of(kDensity));
  EXPECT_LT(placed, 5000u);
  EXPECT_EQ(deposition.stats().end, DepositionEnd::FillHeight);
  for (std::size_t i = 0; i < bed.size(); ++i) ASSERT_LE(bed.position[i].z + 0.5, 4.0 + 1e-9);
  const double solid = static_cast<double>(placed) * 4.0 / 3.0 * std::numbers::pi * 0.125;
  EXPECT_GT(solid / 400.0, 0.3);  // the first sphere above 4.0 ends it: the surface is rough
}

}  // namespace
}  // namespace aggpack

namespace aggpack {
namespace {

// The progress observer sees every `every`-th placement and changes nothing: the same bed
// with and without it.
TEST(DropAndRoll, TheObserverSeesEveryNthPlacementAndChangesNothing) {
  const Container container = Container::square(0.1, 0.2, false);
  const std::vector<double> radii(95, 0.005);
  ParticleStore watched, plain;
  std::vector<std::size_t> seen;
  DropAndRoll a(watched, container, radii, DepositionSettings{}, Rng(7, 2));
  a.deposit(radii, SphereMaterials::all_of(2650.0), 0, {10, [&](std::size_t placed) { seen.push_back(placed); }});
  DropAndRoll b(plain, container, radii, DepositionSettings{}, Rng(7, 2));
  b.deposit(radii, SphereMaterials::all_of(2650.0));
  EXPECT_EQ(seen, (std::vector<std::size_t>{10, 20, 30, 40, 50, 60, 70, 80, 90}));
  ASSERT_EQ(watched.size(), plain.size());
  for (std::size_t i = 0; i < plain.size(); ++i) EXPECT_EQ(watched.position[i], plain.position[i]);
}

}  // namespace
}  // namespace aggpack
