// The standards' numbers and checks: C29's measures and procedures by size, C1252's samples.
#include "aggpack/labtests/standards.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"

namespace aggpack {
namespace {

constexpr double kMm = 1e-3;

Grading grading(std::vector<std::pair<double, double>> mm_passing) {
  std::vector<Sieve> sieves;
  std::vector<std::string> rows;
  for (const auto& [mm, passing] : mm_passing) {
    sieves.push_back({"", mm * kMm, passing});
    rows.push_back(fmt::format("{} mm", mm));
  }
  return make_grading("test", sieves, "test", rows);
}

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Standards, C29MeasuresHaveTheirNominalCapacityAndHeightEqualToDiameter) {
  for (const Measure& m : c29_measures()) {
    EXPECT_NEAR(m.volume_m3(), m.capacity_m3, 1e-12 * m.capacity_m3) << m.name;
    EXPECT_DOUBLE_EQ(m.height_m, m.diameter_m);
  }
  // Table 1: up to 12.5 mm the 2.8 L, up to 25 mm the 9.3 L, up to 37.5 mm the 14 L measure.
  EXPECT_DOUBLE_EQ(c29_measure(9.5 * kMm, "x").capacity_m3, 2.8e-3);
  EXPECT_DOUBLE_EQ(c29_measure(12.5 * kMm, "x").capacity_m3, 2.8e-3);
  EXPECT_DOUBLE_EQ(c29_measure(19 * kMm, "x").capacity_m3, 9.3e-3);
  EXPECT_DOUBLE_EQ(c29_measure(37.5 * kMm, "x").capacity_m3, 14e-3);
  EXPECT_DOUBLE_EQ(c29_measure(125 * kMm, "x").capacity_m3, 100e-3);
  // 9.3 L at height = diameter: (4 V / pi)^(1/3) = 228 mm.
  EXPECT_NEAR(c29_measure(19 * kMm, "x").diameter_m, std::cbrt(4 * 9.3e-3 / std::numbers::pi), 1e-12);
  EXPECT_NE(message_of([] { (void)c29_measure(150 * kMm, "stone.toml: grading"); }).find("stone.toml: grading"),
            std::string::npos);
}

TEST(Standards, C29RefusesAMethodTheStandardDoesNotDefineForTheSize) {
  EXPECT_NO_THROW(check_c29_method(C29Method::Rodding, 37.5 * kMm, "x"));
  EXPECT_NO_THROW(check_c29_method(C29Method::Shovelling, 100 * kMm, "x"));
  EXPECT_NO_THROW(check_c29_method(C29Method::Jigging, 50 * kMm, "x"));
  const std::string rod = message_of([] { check_c29_method(C29Method::Rodding, 50 * kMm, "big.toml: grading"); });
  EXPECT_NE(rod.find("big.toml: grading"), std::string::npos);
  EXPECT_NE(rod.find("37.5 mm"), std::string::npos);
  EXPECT_NE(rod.find("jigging"), std::string::npos) << rod;
  EXPECT_NE(message_of([] { check_c29_method(C29Method::Jigging, 19 * kMm, "x"); }).find("rodding"), std::string::npos);
  EXPECT_NE(message_of([] { check_c29_method(C29Method::Shovelling, 150 * kMm, "x"); }).find("125 mm"),
            std::string::npos);
}

TEST(Standards, C1252SamplesAreTheStandards) {
  double a = 0.0;
  for (const SieveFraction& f : c1252_method_a_fractions()) a += f.mass_kg;
  EXPECT_NEAR(a, kC1252SampleMassKg, 1e-12);  // 44 + 57 + 72 + 17 g
  EXPECT_EQ(c1252_method_b_fractions().size(), 3u);
  // Method A's grading: 17 / 190 passes 0.300 mm, (17 + 72) / 190 passes 0.600 mm.
  const Grading g = grading_of_fractions(c1252_method_a_fractions(), "A");
  EXPECT_NEAR(percent_passing_at(g, 0.300 * kMm), 100.0 * 17 / 190, 1e-9);
  EXPECT_NEAR(percent_passing_at(g, 0.600 * kMm), 100.0 * 89 / 190, 1e-9);
  EXPECT_NEAR(percent_passing_at(g, 2.36 * kMm), 100.0, 1e-9);
  EXPECT_NEAR(percent_passing_at(g, 0.150 * kMm), 0.0, 1e-9);
  // The measure: 39 mm x 86 mm is about the standard's 100 mL.
  EXPECT_NEAR(0.25 * std::numbers::pi * kC1252Diameter * kC1252Diameter * kC1252Height, 100e-6, 3e-6);
}

TEST(Standards, C1252RefusesACoarseAggregateAndASandWithoutTheMethodsFractions) {
  const Grading stone = grading({{4.75, 5}, {9.5, 55}, {19, 95}, {25, 100}});
  const std::string coarse = message_of([&] { check_c1252_grading(C1252Method::C, stone, "stone.toml: grading"); });
  EXPECT_NE(coarse.find("4.75 mm"), std::string::npos) << coarse;
  EXPECT_NE(coarse.find("stone.toml: grading"), std::string::npos);
  // A fine sand with nothing above 0.6 mm cannot give method A's 2.36-1.18 mm fraction.
  const Grading fine = grading({{0.075, 2}, {0.15, 10}, {0.3, 50}, {0.6, 100}});
  EXPECT_NE(message_of([&] { check_c1252_grading(C1252Method::A, fine, "x"); }).find("method C"), std::string::npos);
  EXPECT_NO_THROW(check_c1252_grading(C1252Method::C, fine, "x"));
  const Grading sand = grading({{0.15, 5}, {0.3, 20}, {0.6, 45}, {1.18, 70}, {2.36, 85}, {4.75, 97}, {9.5, 100}});
  EXPECT_NO_THROW(check_c1252_grading(C1252Method::A, sand, "x"));
  EXPECT_NO_THROW(check_c1252_grading(C1252Method::B, sand, "x"));
}

}  // namespace
}  // namespace aggpack
