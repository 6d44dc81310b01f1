// The content of a cylindrical measure struck off at its rim, against closed forms (a sphere
// cut by a plane loses a cap, pi h^2 (3r - h) / 3) and Monte Carlo for a grain; and the
// cylinder's profiles, which must account for every sphere's volume.
#include "aggpack/analysis/measure.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "aggpack/analysis/density.hpp"
#include "aggpack/core/error.hpp"
#include "aggpack/core/quaternion.hpp"
#include "aggpack/core/rng.hpp"
#include "aggpack/grains/union_mass_properties.hpp"

namespace aggpack {
namespace {

constexpr double kPi = std::numbers::pi;
double ball(double r) { return 4.0 / 3.0 * kPi * r * r * r; }
double cap(double r, double h) { return kPi * h * h * (3.0 * r - h) / 3.0; }

// Spheres on a square lattice inside a cylinder of diameter 10 cm, in layers whose top layer
// straddles the rim at several heights.
TEST(Measure, SpheresCutByTheRimCountTheirVolumeBelowIt) {
  Container c = Container::cylinder(0.1, 0.12);
  c.rim = 0.05;
  const double r = 0.004;
  ParticleStore p;
  double below = 0.0, whole = 0.0;
  std::size_t centred_below = 0, cut = 0;
  const std::vector<double> heights{0.01, 0.03, 0.047, 0.0495, 0.05, 0.0512, 0.053, 0.06};
  for (std::size_t layer = 0; layer < heights.size(); ++layer)
    for (int i = -4; i <= 4; ++i)
      for (int j = -4; j <= 4; ++j) {
        const Vec3 at{0.05 + 0.0085 * i + 0.0002 * static_cast<double>(layer), 0.05 + 0.0085 * j, heights[layer]};
        if (std::hypot(at.x - 0.05, at.y - 0.05) > 0.05 - r) continue;
        p.add(at, r, 2650.0);
        const double z = heights[layer];
        if (z + r <= c.rim) below += ball(r);
        else if (z - r < c.rim) below += ball(r) - cap(r, z + r - c.rim), ++cut;
        if (z < c.rim) whole += ball(r), ++centred_below;
      }
  const MeasureContent m = measure_content(p, c);
  const double volume = kPi * 0.05 * 0.05 * 0.05;
  EXPECT_DOUBLE_EQ(m.diameter, 0.1);
  EXPECT_DOUBLE_EQ(m.rim, 0.05);
  EXPECT_NEAR(m.volume, volume, 1e-15);
  EXPECT_NEAR(m.packing_density, below / volume, 1e-12);
  EXPECT_NEAR(m.packing_density_whole_particles, whole / volume, 1e-12);
  EXPECT_EQ(m.particles, centred_below);
  EXPECT_EQ(m.particles_cut, cut);
  EXPECT_GT(cut, 50u);
  EXPECT_THROW((void)measure_content(p, Container::square(0.1, 0.12, false)), InputError);
}

// A grain of three overlapping spheres across the rim: its union below the rim (Monte Carlo,
// 400 000 points), and counted whole by its centre of mass.
TEST(Measure, AGrainCountsItsUnionBelowTheRim) {
  std::vector<Vec3> centres{{-0.004, 0.0, -0.002}, {0.002, 0.001, 0.0}, {0.005, -0.001, 0.003}};
  const std::vector<double> radii{0.003, 0.0035, 0.002};
  std::vector<MemberSphere> spheres;
  for (std::size_t k = 0; k < 3; ++k) spheres.push_back({centres[k], radii[k]});
  const MassProperties mass = union_mass_properties(spheres);
  for (Vec3& centre : centres) centre -= mass.centre_of_mass;
  ParticleStore p;
  const Vec3 at{0.03, 0.02, 0.0395};
  const Quaternion q = normalized(Quaternion{0.9, 0.2, -0.3, 0.1});
  p.add_body(at, q, {centres, radii, mass.volume, {1e-12, 1e-12, 1e-12}}, 2650.0);
  Container c = Container::cylinder(0.05, 0.06);
  c.rim = 0.04;
  // Monte Carlo over the grain's bounding cube.
  Rng rng(7, 1);
  const double half = 0.009;
  std::size_t hits = 0;
  constexpr std::size_t kPoints = 400000;
  for (std::size_t n = 0; n < kPoints; ++n) {
    const Vec3 x{at.x + rng.uniform(-half, half), at.y + rng.uniform(-half, half), at.z + rng.uniform(-half, half)};
    if (x.z >= c.rim) continue;
    for (std::size_t k = 0; k < 3; ++k)
      if (norm2(x - (at + rotate(q, centres[k]))) < radii[k] * radii[k]) {
        ++hits;
        break;
      }
  }
  const double sampled = std::pow(2.0 * half, 3) * static_cast<double>(hits) / kPoints;
  const MeasureContent m = measure_content(p, c);
  const double volume = kPi * 0.025 * 0.025 * 0.04;
  EXPECT_GT(sampled, 0.2 * mass.volume);  // really cut
  EXPECT_LT(sampled, 0.8 * mass.volume);
  EXPECT_NEAR(m.packing_density * volume, sampled, 0.01 * mass.volume);
  EXPECT_NEAR(m.packing_density_whole_particles * volume, mass.volume, 1e-12 * mass.volume);  // centre below the rim
  EXPECT_EQ(m.particles, 1u);
  EXPECT_EQ(m.particles_cut, 1u);
}

// Every sphere's volume is in the cylinder's slices and (between its heights) its rings: the
// fractions times each bin's volume sum to the spheres' volume.
TEST(Measure, ACylindersSlicesAndRingsHoldEverySpheresVolume) {
  const Container c = Container::cylinder(0.1, 0.1);
  ParticleStore p;
  const double r = 0.006;
  for (const Vec3& at : {Vec3{0.05, 0.05, 0.03}, Vec3{0.094, 0.05, 0.03}, Vec3{0.02, 0.08, 0.03}, Vec3{0.06, 0.01, 0.03}})
    p.add(at, r, 2650.0);
  const double t = 0.002;
  const Profile slices = vertical_profile(p, c, t);
  double sliced = 0.0;
  for (const double f : slices.solid_fraction) sliced += f * kPi * 0.05 * 0.05 * t;
  EXPECT_NEAR(sliced, 4.0 * ball(r), 1e-9 * ball(r));
  const Profile rings = wall_distance_profile(p, c, t, 0.0, 0.1);
  ASSERT_EQ(rings.position.size(), 25u);
  double ringed = 0.0;
  for (std::size_t k = 0; k < rings.position.size(); ++k) {
    const double a = 0.05 - t * static_cast<double>(k), b = a - t;
    ringed += rings.solid_fraction[k] * kPi * (a * a - b * b) * 0.1;
  }
  EXPECT_NEAR(ringed, 4.0 * ball(r), 1e-8 * ball(r));
  // The sphere touching the wall fills the first ring; none lies beyond 2 r + its distance.
  EXPECT_GT(rings.solid_fraction[0], 0.0);
  EXPECT_NEAR(rings.position[0], 0.5 * t, 1e-15);
}

}  // namespace
}  // namespace aggpack
