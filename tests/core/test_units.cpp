#include "aggpack/core/units.hpp"

#include <gtest/gtest.h>

namespace aggpack {
namespace {

TEST(Units, EveryUnitConvertsExactly) {
  for (const auto& unit : length_units()) {
    const auto v = parse_length("1 " + std::string(unit.symbol));
    ASSERT_TRUE(v) << unit.symbol;
    EXPECT_EQ(*v, static_cast<double>(unit.metres)) << unit.symbol;
  }
  EXPECT_EQ(*parse_length("1 in"), 0.0254);
  EXPECT_EQ(*parse_length("1 ft"), 0.3048);
  EXPECT_EQ(*parse_length("1 mm"), 0.001);
}

TEST(Units, TheSameLengthInEveryUnitIsTheSameDouble) {
  const double inch = *parse_length("0.0254 m");
  EXPECT_EQ(*parse_length("1 in"), inch);
  EXPECT_EQ(*parse_length("25.4 mm"), inch);
  EXPECT_EQ(*parse_length("2.54 cm"), inch);
  EXPECT_EQ(*parse_length("25400 um"), inch);
  EXPECT_EQ(*parse_length("12 in"), *parse_length("1 ft"));
  EXPECT_EQ(*parse_length("36 in"), *parse_length("1 yd"));
  EXPECT_EQ(*parse_length("0.5 in"), 0.0127);
  EXPECT_EQ(*parse_length("1in"), inch);  // no space
  EXPECT_EQ(*parse_length("  2.5e-2  m "), 0.025);
  EXPECT_EQ(*parse_length("0.3"), 0.3);  // bare number: metres
}

TEST(Units, UnknownUnitsAndGarbageAreErrorsThatSayWhy) {
  std::string why;
  EXPECT_FALSE(parse_length("3 furlongs", &why));
  EXPECT_NE(why.find("unknown length unit 'furlongs'"), std::string::npos) << why;
  EXPECT_NE(why.find("in"), std::string::npos);
  EXPECT_FALSE(parse_length("inch", &why));
  EXPECT_NE(why.find("does not start with a number"), std::string::npos) << why;
  EXPECT_FALSE(parse_length("", &why));
  EXPECT_FALSE(parse_length("1 in extra", &why));
  EXPECT_FALSE(metres_per_unit("IN"));
}

}  // namespace
}  // namespace aggpack

namespace aggpack {
namespace {

TEST(Units, BareNumbersTakeTheGivenUnitAndExplicitUnitsWin) {
  EXPECT_DOUBLE_EQ(*parse_length("10", nullptr, 1e-3L), 0.01);
  EXPECT_DOUBLE_EQ(*parse_length("10 mm", nullptr, 0.0254L), 0.01);
  EXPECT_DOUBLE_EQ(*parse_length("1 in", nullptr, 1e-3L), 0.0254);
  EXPECT_DOUBLE_EQ(*parse_length("2.5"), 2.5);  // metres by default
}

}  // namespace
}  // namespace aggpack
