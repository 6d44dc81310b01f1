#include "aggpack/analysis/density.hpp"

#include <gtest/gtest.h>

#include <numbers>
#include <random>

#include "aggpack/core/error.hpp"
#include "lattices.hpp"

namespace aggpack {
namespace {

constexpr double kPi = std::numbers::pi;

// Boxes with sides a whole number of periods, at random offsets well inside the lattice.
void expect_lattice_density(const ParticleStore& p, double period, int cells, double expected) {
  const Container container = Container::square(cells * period, cells * period, false);
  std::mt19937_64 gen(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    const int kx = 1 + trial % 3, ky = 1 + (trial / 3) % 3, kz = 2 + trial % 2;
    const Vec3 lo{period * (1 + 2 * u(gen)), period * (1 + 2 * u(gen)), period * (1 + 2 * u(gen))};
    const Box box{lo, lo + Vec3{kx * period, ky * period, kz * period}};
    EXPECT_NEAR(solid_volume_in_box(p, container, box) / box.volume(), expected, 1e-9) << "trial " << trial;
  }
}

TEST(Density, SimpleCubicLatticeIsPiOverSixInWholePeriodBoxesAtAnyOffset) {
  const double a = 0.0254;
  expect_lattice_density(testing::simple_cubic(8, a), a, 8, kPi / 6);
}

TEST(Density, FaceCentredCubicLatticeIsPiOverThreeRootTwo) {
  const double a = 0.01;
  expect_lattice_density(testing::face_centred_cubic(7, a), a, 7, kPi / (3 * std::sqrt(2.0)));
}

TEST(Density, PeriodicImagesCountTheWholeSphereInTheFootprint) {
  ParticleStore p;
  p.add({0.05, 0.98, 0.5}, 0.1, 1.0);  // crosses x = 0 and y = 1
  const Container periodic = Container::square(1.0, 1.0, true);
  const Container walls = Container::square(1.0, 1.0, false);
  const Box footprint{{0, 0, 0}, {1, 1, 1}};
  EXPECT_NEAR(solid_volume_in_box(p, periodic, footprint), 4.0 / 3.0 * kPi * 1e-3, 1e-15);
  // With walls only the part inside the footprint counts: x in [0, 0.15], y in [0.88, 1].
  const double inside = solid_volume_in_box(p, walls, {{-1, 0, 0}, {1, 1, 1}}) -
                        solid_volume_in_box(p, walls, {{-1, 0, 0}, {0, 1, 1}});
  EXPECT_NEAR(solid_volume_in_box(p, walls, footprint), inside, 1e-15);
  EXPECT_LT(inside, 0.9 * 4.0 / 3.0 * kPi * 1e-3);
}

TEST(Density, VerticalProfileOfTheLatticeAndItsTotal) {
  const double a = 1.0;
  const ParticleStore p = testing::simple_cubic(4, a);
  const Container c = Container::square(4 * a, 4 * a, false);
  const Profile half_period = vertical_profile(p, c, 0.5 * a);
  ASSERT_EQ(half_period.solid_fraction.size(), 8u);
  for (double f : half_period.solid_fraction) EXPECT_NEAR(f, kPi / 6, 1e-12);
  const Profile quarter = vertical_profile(p, c, 0.25 * a);
  // A slice from a sphere's bottom to a quarter of its height is a cap of height a/4.
  const double cap = kPi * 0.0625 * (1.5 - 0.25) / 3.0;
  EXPECT_NEAR(quarter.solid_fraction[0], 16 * cap / (16 * 0.25), 1e-12);
  double total = 0.0;
  for (double f : quarter.solid_fraction) total += f * 16 * 0.25;
  EXPECT_NEAR(total, 64 * kPi / 6, 1e-10);
}

TEST(Density, WallProfileShellsAddUpToTheSolidInTheirHeightRange) {
  const ParticleStore p = testing::face_centred_cubic(5, 1.0);
  const Container c = Container::square(5.0, 5.0, false);
  const double t = 0.3, z_lo = 1.0, z_hi = 4.0;
  const Profile wall = wall_distance_profile(p, c, t, z_lo, z_hi);
  double solid = 0.0;
  for (std::size_t k = 0; k < wall.position.size(); ++k) {
    const double a = k * t, b = a + t;
    solid += wall.solid_fraction[k] * ((5 - 2 * a) * (5 - 2 * a) - (5 - 2 * b) * (5 - 2 * b)) * (z_hi - z_lo);
  }
  const double inset = t * wall.position.size();
  const Box covered{{0, 0, z_lo}, {5, 5, z_hi}}, rest{{inset, inset, z_lo}, {5 - inset, 5 - inset, z_hi}};
  EXPECT_NEAR(solid, solid_volume_in_box(p, c, covered) - solid_volume_in_box(p, c, rest), 1e-10);
  EXPECT_LT(wall.solid_fraction[0], wall.solid_fraction[3]);  // the wall effect
}

TEST(Density, BedSurfaceOfALatticeIsItsTop) {
  const ParticleStore p = testing::simple_cubic(6, 0.5);
  const BedGeometry bed = measure_bed(p, Container::square(3.0, 10.0, false));
  EXPECT_NEAR(bed.surface, 3.0, 1e-12);
  EXPECT_NEAR(bed.top, 3.0, 1e-12);
  EXPECT_DOUBLE_EQ(bed.d_max, 0.5);
}

TEST(Density, VirtualCubeIsCentredAndRefusedWhenTooLarge) {
  const ParticleStore p = testing::simple_cubic(10, 1.0);
  const Container c = Container::square(10.0, 20.0, false);
  const BedGeometry bed = measure_bed(p, c);
  const Box box = place_virtual_cube(8.0, c, bed);
  EXPECT_NEAR(box.lo.x, 1.0, 1e-12);
  EXPECT_NEAR(box.lo.z, 1.0, 1e-12);
  EXPECT_NEAR(box.hi.z, 9.0, 1e-12);
  try {
    place_virtual_cube(8.5, c, bed);
    FAIL() << "an 8.5 cube in a 10-high bed of d = 1 must be refused";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("largest admissible side is 8"), std::string::npos) << e.what();
  }
}

TEST(Density, MeanAndSampleStandardDeviationOverBoxes) {
  ParticleStore p;
  p.add({0.5, 0.5, 0.5}, 0.5, 1.0);
  const Container c = Container::square(1.0, 1.0, false);
  const std::vector<Box> boxes{{{0, 0, 0}, {1, 1, 1}}, {{0, 0, 0}, {1, 1, 0.5}}, {{0.5, 0.5, 0.5}, {1, 1, 1}}};
  const DensityResult r = measure_density(p, c, boxes);
  // The whole, half and eighth of the sphere in the whole, half and eighth of its cube.
  for (const auto& b : r.boxes) EXPECT_NEAR(b.density, kPi / 6, 1e-14);
  EXPECT_NEAR(r.sd, 0.0, 1e-14);
  const DensityResult two = measure_density(p, c, std::vector<Box>{{{0, 0, 0}, {1, 1, 1}}, {{0, 0, 0}, {2, 1, 1}}});
  EXPECT_NEAR(two.mean, 0.75 * kPi / 6, 1e-14);
  EXPECT_NEAR(two.sd, std::sqrt(2 * std::pow(0.25 * kPi / 6, 2)), 1e-14);
}

}  // namespace
}  // namespace aggpack

namespace aggpack {
namespace {

TEST(Density, BoundingContainerAndProfilesOfAFloorBelowZero) {
  ParticleStore p;
  p.add({1.0, 2.0, -3.0}, 0.5, 1.0);
  p.add({2.0, 2.5, -2.0}, 0.25, 1.0);
  const Container c = bounding_container(p);
  EXPECT_EQ(c.bounds.lo, (Vec3{0.5, 1.5, -3.5}));
  EXPECT_EQ(c.bounds.hi, (Vec3{2.25, 2.75, -1.75}));
  const Profile v = vertical_profile(p, c, 0.25);
  ASSERT_EQ(v.position.size(), 7u);  // floor -3.5 to top -1.75
  double solid = 0.0;
  for (double f : v.solid_fraction) solid += f * c.length_x() * c.length_y() * 0.25;
  EXPECT_NEAR(solid, 4.0 / 3.0 * std::numbers::pi * (0.125 + 0.015625), 1e-12);
}

}  // namespace
}  // namespace aggpack
