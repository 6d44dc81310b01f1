#include "aggpack/deposition/gas_insertion.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <vector>

#include "aggpack/core/error.hpp"

namespace aggpack {
namespace {

std::vector<double> mixed_radii(std::size_t n) {
  std::vector<double> radii;
  Rng rng(7, 1);
  for (std::size_t i = 0; i < n; ++i) radii.push_back(rng.uniform(0.002, 0.01));
  return radii;
}

double solid_volume(const std::vector<double>& radii) {
  double v = 0.0;
  for (const double r : radii) v += 4.0 / 3.0 * std::numbers::pi * r * r * r;
  return v;
}

// Every pair checked by brute force: no overlap, every sphere wholly inside the slab and walls.
void expect_valid_gas(const Container& c, const InsertionRegion& region, const std::vector<double>& radii,
                      const std::vector<Vec3>& at) {
  ASSERT_EQ(at.size(), radii.size());
  for (std::size_t i = 0; i < at.size(); ++i) {
    const double r = radii[i];
    EXPECT_GE(at[i].z - r, region.bottom);
    EXPECT_LE(at[i].z + r, region.top);
    if (!c.periodic) {
      EXPECT_GE(at[i].x - r, c.bounds.lo.x);
      EXPECT_LE(at[i].x + r, c.bounds.hi.x);
      EXPECT_GE(at[i].y - r, c.bounds.lo.y);
      EXPECT_LE(at[i].y + r, c.bounds.hi.y);
    }
    if (c.is_cylinder()) {
      EXPECT_LE(std::hypot(at[i].x - c.axis_x(), at[i].y - c.axis_y()) + r, c.radius()) << i;
    }
    for (std::size_t j = 0; j < i; ++j)
      ASSERT_GE(norm(c.minimum_image(at[i] - at[j])), r + radii[j]) << i << " " << j;
  }
}

TEST(GasInsertion, RegionHoldsTheSolidAtTheAskedFraction) {
  const Container c = Container::square(0.2, 0.5, false);
  const InsertionRegion region = insertion_region(c, 0.1, 0.004, 0.2);
  EXPECT_DOUBLE_EQ(region.bottom, 0.1);
  EXPECT_NEAR(0.004 / (0.2 * 0.2 * (region.top - region.bottom)), 0.2, 1e-12);
}

TEST(GasInsertion, PlacesEverySphereWithoutOverlapInsideTheSlab) {
  for (const bool periodic : {false, true}) {
    const Container c = Container::square(0.15, 0.3, periodic);
    const std::vector<double> radii = mixed_radii(1500);
    const InsertionRegion region = insertion_region(c, 0.05, solid_volume(radii), 0.25);
    Rng rng = pour_stream(3, 0);
    expect_valid_gas(c, region, radii, random_gas(c, region, radii, rng));
  }
}

// A cylinder's slab: its circle's area times its height; every sphere within R - r of the axis,
// and they spread over the circle (each quadrant a quarter of them, roughly).
TEST(GasInsertion, ACylindersGasFillsItsCircle) {
  const Container c = Container::cylinder(0.15, 0.3);
  const std::vector<double> radii = mixed_radii(1500);
  const InsertionRegion region = insertion_region(c, 0.05, solid_volume(radii), 0.25);
  EXPECT_NEAR(solid_volume(radii) / (std::numbers::pi * 0.075 * 0.075 * (region.top - region.bottom)), 0.25, 1e-12);
  Rng rng = pour_stream(3, 0);
  const std::vector<Vec3> gas = random_gas(c, region, radii, rng);
  expect_valid_gas(c, region, radii, gas);
  std::size_t east = 0;
  for (const Vec3& at : gas) east += at.x > c.axis_x() ? 1 : 0;
  EXPECT_NEAR(static_cast<double>(east) / 1500.0, 0.5, 0.05);
}

TEST(GasInsertion, SameSeedSameGasOtherPartOtherGas) {
  const Container c = Container::square(0.15, 0.3, false);
  const std::vector<double> radii = mixed_radii(300);
  const InsertionRegion region = insertion_region(c, 0.0, solid_volume(radii), 0.2);
  Rng a = pour_stream(5, 0), b = pour_stream(5, 0), other = pour_stream(5, 1);
  const std::vector<Vec3> ga = random_gas(c, region, radii, a), gb = random_gas(c, region, radii, b),
                          go = random_gas(c, region, radii, other);
  EXPECT_EQ(std::memcmp(ga.data(), gb.data(), ga.size() * sizeof(Vec3)), 0);
  EXPECT_NE(std::memcmp(ga.data(), go.data(), ga.size() * sizeof(Vec3)), 0);
}

TEST(GasInsertion, RefusesAFractionTooDenseForARandomGas) {
  const Container c = Container::square(0.1, 0.3, false);
  const std::vector<double> radii(400, 0.005);
  const InsertionRegion region = insertion_region(c, 0.0, solid_volume(radii), 0.6);
  Rng rng = pour_stream(1, 0);
  try {
    (void)random_gas(c, region, radii, rng, 2000);
    FAIL() << "a gas at 0.6 was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("too dense for a random gas"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace aggpack
