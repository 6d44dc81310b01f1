// The specimen cut from a bed and its exact volumes: a ball in a cylinder against closed forms
// and Monte Carlo; the cut's kept and dropped particles.
#include <gtest/gtest.h>

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

}  // namespace
}  // namespace aggpack
