#include <cmath>
#include <regex>

#include <gtest/gtest.h>

#include "aggpack/report/svg_plot.hpp"

namespace aggpack {
namespace {

TEST(Axis, LinearTicksAreRoundAndCoverTheData) {
  const Axis a = make_axis(0.5731, 0.6123, false);
  EXPECT_LE(a.lo, 0.5731);
  EXPECT_GE(a.hi, 0.6123);
  EXPECT_NEAR(a.lo, 0.57, 1e-12);
  EXPECT_NEAR(a.hi, 0.62, 1e-12);
  ASSERT_GE(a.ticks.size(), 3u);
  const double step = a.ticks[1] - a.ticks[0];
  EXPECT_NEAR(step, 0.01, 1e-12);
  EXPECT_NEAR(a.ticks.front(), a.lo, 1e-12);
  EXPECT_NEAR(a.ticks.back(), a.hi, 1e-12);
}

TEST(Axis, ZeroSpanIsPadded) {
  const Axis a = make_axis(0.6, 0.6, false);
  EXPECT_LT(a.lo, 0.6);
  EXPECT_GT(a.hi, 0.6);
}

TEST(Axis, LogAxisSpansWholeDecades) {
  const Axis a = make_axis(0.075e-3, 25e-3, true);
  EXPECT_NEAR(a.lo, 1e-5, 1e-18);
  EXPECT_NEAR(a.hi, 1e-1, 1e-15);
  EXPECT_NEAR(a.ticks.front(), 1e-5, 1e-18);
  EXPECT_THROW(make_axis(0.0, 1.0, true), std::invalid_argument);
}

TEST(SvgPlot, RangesLabelsAndPointsAreWhereTheyShouldBe) {
  Plot plot;
  plot.title = "density <vs> time";
  plot.x_label = "time (s)";
  plot.y_label = "density";
  plot.series.push_back({"ours", {0.0, 0.5, 1.0}, {0.58, 0.60, 0.61}, {}, Mark::LineAndPoints, false, ""});
  plot.series.push_back({"paper", {0.0, 1.0}, {0.604, 0.604}, {0.01, 0.01}, Mark::Points, true, ""});
  const std::string svg = svg_plot(plot);
  EXPECT_NE(svg.find("data-x-range=\"0 1\""), std::string::npos) << svg.substr(0, 300);
  EXPECT_NE(svg.find("data-y-range=\"0.58 0.62\""), std::string::npos);
  EXPECT_NE(svg.find("density &lt;vs&gt; time"), std::string::npos);
  EXPECT_NE(svg.find(">time (s)<"), std::string::npos);
  EXPECT_NE(svg.find("data-label=\"paper\""), std::string::npos);
  // (0.5, 0.60): the middle of the plot horizontally, half-way up between 0.58 and 0.62.
  EXPECT_NE(svg.find("<circle cx=\"345.00\" cy=\"192.00\""), std::string::npos);
  std::smatch m;
  const std::string bars = svg;
  EXPECT_TRUE(std::regex_search(bars, m, std::regex("<path d=\"M")));  // error bars drawn
  EXPECT_EQ(svg.substr(svg.size() - 7), "</svg>\n");
}

TEST(SvgPlot, FixedRangeIsKeptAndOutsidePointsAreDropped) {
  Plot plot;
  plot.y_range = {{0.5, 0.7}};
  plot.series.push_back({"s", {0, 1, 2}, {0.55, 0.9, 0.65}, {}, Mark::Points, false, ""});
  const std::string svg = svg_plot(plot);
  EXPECT_NE(svg.find("data-y-range=\"0.5 0.7\""), std::string::npos);
  const auto begin = svg.find("data-label=\"s\">"), end = svg.find("</g>", begin);
  ASSERT_NE(begin, std::string::npos);
  const std::string series = svg.substr(begin, end - begin);
  std::size_t circles = 0;
  for (auto at = series.find("<circle"); at != std::string::npos; at = series.find("<circle", at + 1)) ++circles;
  EXPECT_EQ(circles, 2u);  // the point at 0.9 lies above the fixed range
}

}  // namespace
}  // namespace aggpack
