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

// sweep.svg read 0.708, 0.710, 0.712, 0.715 for ticks 0.0025 apart.
TEST(SvgPlot, TickLabelsOfAStepOfTwoAndAHalfShowEveryDigit) {
  Plot plot;
  plot.series.push_back({"", {0, 1}, {0.7005, 0.7120}, {}, Mark::Points, false, ""});
  const auto [x, y] = plot_axes(plot);
  ASSERT_NEAR(y.ticks[1] - y.ticks[0], 0.0025, 1e-12);
  const std::string svg = svg_plot(plot);
  for (const char* label : {">0.7000<", ">0.7025<", ">0.7050<", ">0.7075<", ">0.7100<", ">0.7125<"})
    EXPECT_NE(svg.find(label), std::string::npos) << label;
  plot.series = {{"", {0, 1}, {0, 25}, {}, Mark::Points, false, ""}};  // step 5: no decimals
  EXPECT_NE(svg_plot(plot).find(">25<"), std::string::npos);
}

struct Circle {
  double x, y;
};
struct LegendBox {
  double x, y, w, h;
};
std::vector<Circle> data_circles(const std::string& svg) {
  // Only inside the series groups: the legend's own markers are not data.
  std::vector<Circle> out;
  const std::regex group("<g class=\"series\"[^>]*>([\\s\\S]*?)</g>"), circle("<circle cx=\"([0-9.]+)\" cy=\"([0-9.]+)\"");
  for (auto g = std::sregex_iterator(svg.begin(), svg.end(), group); g != std::sregex_iterator(); ++g) {
    const std::string body = (*g)[1];
    for (auto c = std::sregex_iterator(body.begin(), body.end(), circle); c != std::sregex_iterator(); ++c)
      out.push_back({std::stod((*c)[1]), std::stod((*c)[2])});
  }
  return out;
}
LegendBox legend_box(const std::string& svg) {
  std::smatch m;
  EXPECT_TRUE(std::regex_search(svg, m, std::regex("<rect class=\"legend\" x=\"([0-9.]+)\" y=\"([0-9.]+)\" "
                                                   "width=\"([0-9.]+)\" height=\"([0-9.]+)\"")));
  return {std::stod(m[1]), std::stod(m[2]), std::stod(m[3]), std::stod(m[4])};
}
std::size_t points_under(const LegendBox& b, const std::vector<Circle>& circles) {
  std::size_t n = 0;
  for (const Circle& c : circles)
    n += c.x + 3.5 >= b.x && c.x - 3.5 <= b.x + b.w && c.y + 3.5 >= b.y && c.y - 3.5 <= b.y + b.h;
  return n;
}

// Fig. 9: the legend box covered the paper's mix 3 point.
TEST(SvgPlot, TheLegendHidesNoPoint) {
  Plot plot;
  plot.legend_at_bottom = true;
  // Points in the top-right and bottom-right corners, as in Fig. 9.
  plot.series.push_back({"aggpack after deposition", {29, 33, 36, 43}, {0.72, 0.70, 0.62, 0.74}, {}, Mark::Points, false, ""});
  plot.series.push_back({"paper, computed", {30, 43}, {0.64, 0.615}, {}, Mark::Points, false, ""});
  plot.series.push_back({"experiment", {31, 42}, {0.741, 0.703}, {}, Mark::Points, false, ""});
  std::string svg = svg_plot(plot);
  ASSERT_EQ(data_circles(svg).size(), 8u);
  EXPECT_EQ(points_under(legend_box(svg), data_circles(svg)), 0u) << svg;
  EXPECT_NE(svg.find("height=\"400\""), std::string::npos);  // a corner was free: the size is unchanged
  // Points in every corner: the legend moves below the plot, and the picture grows.
  plot.series.push_back({"corners", {29, 29, 43, 43}, {0.615, 0.741, 0.615, 0.741}, {}, Mark::Points, false, ""});
  svg = svg_plot(plot);
  const LegendBox below = legend_box(svg);
  EXPECT_EQ(points_under(below, data_circles(svg)), 0u) << svg;
  EXPECT_GT(below.y, 400.0 - 52.0);  // under the plot area
  EXPECT_NE(svg.find("height=\"" + std::to_string(static_cast<int>(400 + below.h + 4)) + "\""), std::string::npos);
}

// The quick report's compaction plot: a 90-character label made the legend wider than the
// plot, over the y axis. Long labels are wrapped; the box stays inside the plot's width.
TEST(SvgPlot, ALongLabelIsWrappedInsideThePlot) {
  Plot plot;
  const std::string label = "aggpack, seed 1 (2 taps of 2 g at 30 Hz, 0.15 s apart (QUICK: the pour cut at 0.6 s)) and "
                            "a few more words to make it long";
  plot.series.push_back({label, {0, 1, 2}, {0.60, 0.61, 0.62}, {}, Mark::LineAndPoints, false, ""});
  const std::string svg = svg_plot(plot);
  const LegendBox box = legend_box(svg);
  EXPECT_GE(box.x, 70.0) << svg;               // right of the y axis (kLeft)
  EXPECT_LE(box.x + box.w, 640.0 - 20.0) << svg;  // inside the plot's right edge
  // Every word of the label is there, in order, over several lines.
  std::string shown;
  const std::regex text("<text x=\"([0-9.]+)\" y=\"[0-9.]+\">([^<]*)</text>");
  std::size_t lines = 0;
  for (auto t = std::sregex_iterator(svg.begin(), svg.end(), text); t != std::sregex_iterator(); ++t)
    if (std::stod((*t)[1]) > box.x && std::stod((*t)[1]) < box.x + 40) shown += (shown.empty() ? "" : " ") + (*t)[2].str(), ++lines;
  EXPECT_GE(lines, 2u) << svg;
  EXPECT_EQ(shown, label) << svg;
}

// Issue 34, item 15: each report figure's data as a CSV beside its SVG, read back by Python's
// csv module in the reproduce test.
TEST(PlotCsv, OneRowAPointWithTheColumnsUnitsAndTheErrorBars) {
  Plot plot;
  plot.x_column = "fa_percent";
  plot.y_column = "packing_density";
  plot.series.push_back({"aggpack, mean of 3 seeds", {25, 30}, {0.8123456789012345, 0.81}, {0.002, 0.003}, Mark::Line, false, ""});
  plot.series.push_back({"paper \"Table 2\"", {25}, {std::nan("")}, {}, Mark::Points, false, ""});
  EXPECT_EQ(plot_csv(plot),
            "series,fa_percent,packing_density,packing_density_error\n"
            "\"aggpack, mean of 3 seeds\",25,0.8123456789012345,0.002\n"
            "\"aggpack, mean of 3 seeds\",30,0.81,0.003\n"
            "\"paper \"\"Table 2\"\"\",25,,\n");
  plot.series.pop_back();
  plot.series.front().y_error.clear();
  EXPECT_EQ(plot_csv(plot).substr(0, plot_csv(plot).find('\n')), "series,fa_percent,packing_density");
}

}  // namespace
}  // namespace aggpack
