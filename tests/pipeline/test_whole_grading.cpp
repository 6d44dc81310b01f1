// The residual line of the whole-grading estimate against its closed forms.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "aggpack/core/error.hpp"
#include "aggpack/pipeline/whole_grading.hpp"

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

}  // namespace
