// The specimen cut from a bed and its exact volumes: a ball in a cylinder against closed forms
// and Monte Carlo; the cut's kept and dropped particles.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "aggpack/analysis/sphere_box_volume.hpp"
#include "aggpack/core/error.hpp"
#include "aggpack/specimen/specimen.hpp"

namespace aggpack {
namespace {

constexpr double kPi = std::numbers::pi;
double ball(double r) { return 4.0 / 3.0 * kPi * r * r * r; }

TEST(SphereCylinderVolume, MatchesTheClosedForms) {
  const VerticalCylinder tall{0.0, 0.0, -10.0, 10.0, 2.0};
  EXPECT_NEAR(sphere_cylinder_volume({0.5, 0.3, 1.0}, 1.0, tall), ball(1.0), 1e-10 * ball(1.0));  // inside
  EXPECT_EQ(sphere_cylinder_volume({4.0, 0.0, 0.0}, 1.0, tall), 0.0);                             // outside
  // A ball on the axis of a thinner cylinder: the ball less its two caps beyond the cylinder,
  // V = 4/3 pi (r^3 - (r^2 - R^2)^(3/2)).
  const VerticalCylinder thin{0.0, 0.0, -10.0, 10.0, 0.6};
  const double expected = 4.0 / 3.0 * kPi * (1.0 - std::pow(1.0 - 0.36, 1.5));
  EXPECT_NEAR(sphere_cylinder_volume({0.0, 0.0, 0.0}, 1.0, thin), expected, 1e-10 * ball(1.0));
  // Cut by the end plane through its centre: half of it.
  const VerticalCylinder above{0.0, 0.0, 0.0, 10.0, 2.0};
  EXPECT_NEAR(sphere_cylinder_volume({0.0, 0.0, 0.0}, 1.0, above), 0.5 * ball(1.0), 1e-10 * ball(1.0));
}

// Off the axis, crossing the curved face and an end plane: against Monte Carlo (4 standard errors).
TEST(SphereCylinderVolume, AgreesWithMonteCarloWhereTheCylindersFaceCutsIt) {
  const VerticalCylinder c{0.0, 0.0, -0.3, 5.0, 1.5};
  const Vec3 centre{1.2, 0.4, 0.0};
  const double r = 1.0;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int samples = 2'000'000;
  int in_ball = 0, in_both = 0;
  for (int n = 0; n < samples; ++n) {
    const Vec3 p{centre.x + u(rng), centre.y + u(rng), centre.z + u(rng)};
    const double dx = p.x - centre.x, dy = p.y - centre.y, dz = p.z - centre.z;
    if (dx * dx + dy * dy + dz * dz > r * r) continue;
    ++in_ball;
    in_both += c.contains(p);
  }
  const double share = static_cast<double>(in_both) / in_ball;
  const double exact = sphere_cylinder_volume(centre, r, c) / ball(r);
  EXPECT_GT(share, 0.2);
  EXPECT_LT(share, 0.8);
  EXPECT_NEAR(exact, share, 4.0 * std::sqrt(share * (1.0 - share) / in_ball));
}

PackedParticles three_particles() {
  PackedParticles bed;
  bed.spheres = {{{0.01, 0.01, 0.01}, 0.004}, {{0.02, 0.02, 0.02}, 0.001},  // a stone, a grain of sand
                 {{0.028, 0.01, 0.01}, 0.003}, {{0.032, 0.01, 0.01}, 0.003}};  // a grain of two spheres
  bed.particle_of_sphere = {0, 1, 2, 2};
  bed.particle_size = {0.008, 0.002, 0.006};
  return bed;
}

TEST(CutSpecimen, KeepsWhatIsAboveTheSizeAndCountsTheRestAsMortar) {
  const Box box{{0.0, 0.0, 0.0}, {0.03, 0.03, 0.03}};
  const Specimen s = cut_specimen(three_particles(), {box, 0.005, 0.0});
  EXPECT_EQ(s.kept_particles, 2u);
  EXPECT_EQ(s.dropped_particles, 1u);
  ASSERT_EQ(s.spheres.size(), 3u);  // the stone, the grain's two spheres (one cut by x = 0.03)
  EXPECT_NEAR(s.dropped_volume, ball(0.001), 1e-12 * ball(0.001));
  // The grain's union in the box by slicing, to 1e-9: its spheres' lens (equal balls of radius
  // r, d apart: pi (4r + d)(2r - d)^2 / 12) counted once; the box's face x = 0.03 halves it.
  const double lens = kPi * (4.0 * 0.003 + 0.004) * std::pow(2.0 * 0.003 - 0.004, 2) / 12.0;
  const double grain_in_box = sphere_box_volume({0.028, 0.01, 0.01}, 0.003, box) +
                              sphere_box_volume({0.032, 0.01, 0.01}, 0.003, box) - 0.5 * lens;
  EXPECT_NEAR(s.aggregate_volume, ball(0.004) + grain_in_box, 2e-9 * ball(0.004) + 1e-9 * 2.0 * ball(0.003));
  EXPECT_THROW((void)cut_specimen(three_particles(), {Box{{1.0, 1.0, 1.0}, {1.1, 1.1, 1.1}}, 0.0, 0.0}), InputError);
  EXPECT_THROW((void)cut_specimen(three_particles(), {Box{{0.0, 0.0, 0.0}, {0.0, 0.1, 0.1}}, 0.0, 0.0}), InputError);
}

// A ball wholly inside the cylinder's circle, cut by neither, one or both end planes: the
// closed form (the fast path) against the quadrature of the same lens areas.
TEST(SphereCylinderVolume, ABallInsideTheCirclesIsTheBallBetweenThePlanes) {
  const double r = 1.0;
  const auto cap = [&](double h) { return kPi * h * h * (3.0 * r - h) / 3.0; };  // a cap of height h
  EXPECT_NEAR(sphere_cylinder_volume({0.3, 0.0, 5.0}, r, {0.0, 0.0, 0.0, 10.0, 2.0}), ball(r), 1e-12 * ball(r));
  EXPECT_NEAR(sphere_cylinder_volume({0.3, 0.0, 0.4}, r, {0.0, 0.0, 0.0, 10.0, 2.0}), ball(r) - cap(0.6),
              1e-12 * ball(r));
  EXPECT_NEAR(sphere_cylinder_volume({0.3, 0.0, 0.4}, r, {0.0, 0.0, 0.0, 1.0, 2.0}), ball(r) - cap(0.6) - cap(0.4),
              1e-12 * ball(r));
  EXPECT_EQ(sphere_cylinder_volume({3.5, 0.0, 0.4}, r, {0.0, 0.0, 0.0, 1.0, 2.0}), 0.0);
}

// Grains of sand on a core's rim are cut in milliseconds (were minutes: the lens area's
// roundoff, a small disc against a large one, kept the quadrature from meeting its tolerance),
// each a little less than half inside (the rim is convex), and the cut as fast as its box's.
TEST(CutSpecimen, SandOnACylindersRimIsCutAsFastAsInABox) {
  const VerticalCylinder core{0.0, 0.0, 0.0, 0.05, 0.0254};
  PackedParticles bed;
  for (std::size_t n = 0; n < 400; ++n) {
    const double angle = 2.0 * kPi * static_cast<double>(n) / 400.0, r = 0.0001 + 0.00015 * static_cast<double>(n % 4);
    bed.spheres.push_back({{core.radius * std::cos(angle), core.radius * std::sin(angle), 0.001 + 0.0001 * n}, r});
    bed.particle_of_sphere.push_back(n);
    bed.particle_size.push_back(2.0 * r);
  }
  const auto seconds = [&](const SpecimenRegion& region) {
    const auto start = std::chrono::steady_clock::now();
    const Specimen s = cut_specimen(bed, {region, 0.0, 0.0});
    EXPECT_EQ(s.kept_particles, 400u);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  const double box = seconds(core.bounds()), cylinder = seconds(core);
  EXPECT_LT(cylinder, 20.0 * box + 0.05) << "box " << box << " s, cylinder " << cylinder << " s";
  for (const MemberSphere& s : bed.spheres) {
    const double share = sphere_cylinder_volume(s.centre, s.radius, core) / ball(s.radius);
    EXPECT_GT(share, 0.49);
    EXPECT_LT(share, 0.5);
  }
}

// A particle that reaches into the box by less than gap / 2 is in no export once shrunk: not
// counted as kept (was: counted, "276 particles kept" where 272 were in the geometry), but
// as left out by the gap.
TEST(CutSpecimen, AParticleTheGapTakesOutOfTheRegionIsNotCountedAsKept) {
  PackedParticles bed;
  bed.spheres = {{{0.01, 0.01, 0.01}, 0.004}, {{0.01, 0.01, 0.0235}, 0.004}};  // the second reaches 0.5 mm in
  bed.particle_of_sphere = {0, 1};
  bed.particle_size = {0.008, 0.008};
  const Box box{{0.0, 0.0, 0.0}, {0.02, 0.02, 0.02}};
  const Specimen as_packed = cut_specimen(bed, {box, 0.0, 0.0, 0.0});
  EXPECT_EQ(as_packed.kept_particles, 2u);
  const Specimen shrunk = cut_specimen(bed, {box, 0.0, 0.0, 0.002});  // radii 1 mm less: the second is out
  EXPECT_EQ(shrunk.kept_particles, 1u);
  EXPECT_EQ(shrunk.left_out_by_gap, 1u);
  EXPECT_EQ(shrunk.spheres.size(), 1u);
  EXPECT_EQ(shrunk.particle_of_sphere, std::vector<std::size_t>{0});
}

}  // namespace
}  // namespace aggpack
