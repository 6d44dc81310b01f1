// The residual line of the whole-grading estimate against its closed forms.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <vector>

#include <gtest/gtest.h>

#include "aggpack/core/error.hpp"
#include "aggpack/io/scenario.hpp"
#include "aggpack/studies/whole_grading.hpp"

namespace {

TEST(FitLine, AnExactLineAndItsInterceptsErrorFromThePoints) {
  const std::vector<double> x{1.0, 2.0, 3.0}, y{3.0, 5.0, 7.0};
  const auto exact = aggpack::fit_line(x, y);
  EXPECT_NEAR(exact.intercept, 1.0, 1e-14);
  EXPECT_NEAR(exact.slope, 2.0, 1e-14);
  EXPECT_NEAR(exact.intercept_standard_error, 0.0, 1e-14);
  // Each point known to +-s: the intercept to s sqrt(1/n + mean(x)^2 / Sxx) = s sqrt(7/3).
  const auto measured = aggpack::fit_line(x, y, {0.01, 0.01, 0.01});
  EXPECT_NEAR(measured.intercept_standard_error, 0.01 * std::sqrt(7.0 / 3.0), 1e-15);
  // Scatter about the line: y = 1 + 2x + (+d, -2d, +d), residual variance 6 d^2 / (n - 2).
  const double d = 0.1;
  const auto scattered = aggpack::fit_line(x, {3.0 + d, 5.0 - 2 * d, 7.0 + d});
  EXPECT_NEAR(scattered.slope, 2.0, 1e-14);
  EXPECT_NEAR(scattered.intercept_standard_error, std::sqrt(6 * d * d * 7.0 / 3.0), 1e-12);
  EXPECT_THROW(aggpack::fit_line({1.0}, {1.0}), aggpack::InputError);
  EXPECT_THROW(aggpack::fit_line({1.0, 1.0}, {1.0, 2.0}), aggpack::InputError);
}

// Densities that lie exactly on CPM + r0 + s f (f the volume left out) give back r0 and s, no
// band, and the whole grading at CPM's whole-grading value + r0, in any order of the points.
TEST(WholeGradingFit, AResidualLineIsCarriedToTheWholeGrading) {
  const std::filesystem::path file = std::filesystem::temp_directory_path() / "aggpack_whole_grading_fit.toml";
  std::ofstream(file) << "[container]\nside = \"4 in\"\nheight = \"8 in\"\n[particles]\nca_fa = 1.5\nfill_height = \"4 in\"\n"
                         "[particles.coarse]\nname = \"fu2003_table1_coarse\"\n"
                         "[particles.fine]\nname = \"astm_c33_fine_mid\"\nd_min = \"0.04 in\"\n[deposition]\n";
  const aggpack::Scenario whole = aggpack::load_scenario(file);
  const aggpack::ModelParameters parameters = aggpack::default_model_parameters(false);
  EXPECT_EQ(aggpack::cut_off_key(*whole.particles.graded), "particles.fine.d_min");
  const double r0 = -0.021, slope = 0.13;
  std::vector<aggpack::CutOffPoint> points;
  for (const char* cut : {"0.02 in", "0.1 in", "0.05 in"}) {
    aggpack::ScenarioOverrides o;
    o.set = {std::string("particles.fine.d_min=\"") + cut + "\""};
    const aggpack::Scenario at_cut = aggpack::load_scenario(file, o);
    aggpack::CutOffPoint probe = aggpack::cut_off_point(at_cut, parameters, *at_cut.particles.graded->fine->d_min, {0.6}, 1);
    const double on_line = probe.cpm + r0 + slope * probe.left_out;
    points.push_back(aggpack::cut_off_point(at_cut, parameters, probe.cut_off, {on_line, on_line}, 1));
  }
  const aggpack::WholeGradingEstimate e = aggpack::fit_whole_grading(whole, parameters, points);
  EXPECT_NEAR(e.residual_at_zero, r0, 1e-12);
  EXPECT_NEAR(e.residual_slope, slope, 1e-10);
  EXPECT_NEAR(e.residual_standard_error, 0.0, 1e-12);
  EXPECT_NEAR(e.density, e.cpm_whole + r0, 1e-12);
  // Coarsest cut first; the cut-offs leave out less as they fall; the whole grading leaves out nothing.
  EXPECT_GT(e.points.front().cut_off, e.points.back().cut_off);
  EXPECT_GT(e.points.front().left_out, e.points[1].left_out);
  EXPECT_GT(e.points[1].left_out, e.points.back().left_out);
  EXPECT_NEAR(e.simulated_fraction, 1.0 - e.points.back().left_out, 1e-15);
  EXPECT_TRUE(e.trustworthy());
  // The plot has every point and the estimate.
  const std::string svg = aggpack::whole_grading_svg(e, 0.72);
  EXPECT_NE(svg.find("whole grading: "), std::string::npos);
  EXPECT_NE(svg.find("measured: 0.720"), std::string::npos);
  points.pop_back();
  EXPECT_THROW(aggpack::fit_whole_grading(whole, parameters, points), aggpack::InputError);
  std::filesystem::remove(file);
}

}  // namespace
