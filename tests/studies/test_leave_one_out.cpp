// "Calibrate on one blend, predict the rest" on a grid, against curves with closed forms.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "aggpack/core/error.hpp"
#include "aggpack/studies/leave_one_out.hpp"

namespace {

using aggpack::GridCurve;
using aggpack::SeedStatistics;

const std::vector<double> kGrid{0.0, 0.1, 0.2, 0.35};

// A blend whose density falls linearly with the parameter, phi(v) = at_zero - slope v, with a
// seed scatter giving standard error `standard_error` over three seeds.
GridCurve line(int mix, double fa, double at_zero, double slope, double measured, double standard_error = 0.002,
               std::size_t seeds = 3) {
  GridCurve c{mix, fa, measured, kGrid, {}};
  for (const double v : kGrid)
    c.density.push_back(
        SeedStatistics{at_zero - slope * v, standard_error * std::sqrt(static_cast<double>(seeds)), seeds});
  return c;
}

// Eight blends whose lab densities all lie on their curves at v* = 0.23, the lab's trend
// -0.02 per 10 points: any choice of the calibration blend finds v* and predicts the others
// exactly.
std::vector<GridCurve> consistent_blends(double slope = 0.1) {
  std::vector<GridCurve> curves;
  for (int k = 0; k < 8; ++k) {
    const double fa = 29.0 + 2.0 * k, at_zero = 0.80 - 0.002 * (fa - 29.0);
    curves.push_back(line(k + 1, fa, at_zero, slope, at_zero - slope * 0.23));
  }
  return curves;
}

TEST(LeaveOneOut, RecoversTheValueEveryBlendWasMadeWithAndPredictsTheOthersExactly) {
  const auto study = aggpack::leave_one_out(consistent_blends());
  ASSERT_EQ(study.choices.size(), 8u);
  EXPECT_NEAR(study.lab_slope_per_10, -0.02, 1e-12);
  for (const auto& choice : study.choices) {
    ASSERT_TRUE(choice.fitted) << choice.calibration_mix;
    EXPECT_NEAR(choice.fitted->value, 0.23, 1e-12);
    EXPECT_FALSE(choice.fitted->at_end);
    // The band: the measurement -+ one standard error (0.002) over the slope (0.1 per unit).
    EXPECT_NEAR(choice.fitted->band_low, 0.21, 1e-12);
    EXPECT_NEAR(choice.fitted->band_high, 0.25, 1e-12);
    ASSERT_EQ(choice.predicted.size(), 7u);
    for (const auto& p : choice.predicted) {
      EXPECT_NE(p.mix, choice.calibration_mix);
      EXPECT_NEAR(p.density, p.measured, 1e-12);
      EXPECT_NEAR(p.band_high - p.band_low, 0.004, 1e-12);  // the band moved along the curve
    }
    EXPECT_NEAR(choice.mean_absolute_error, 0.0, 1e-12);
    EXPECT_NEAR(choice.slope_per_10, -0.02, 1e-12);
    EXPECT_NEAR(choice.lab_slope_per_10, -0.02, 1e-12);
  }
  ASSERT_TRUE(study.median);
}

// A blend's lab value off its curve by 0.01: calibrating on it shifts the value by 0.1 and
// every prediction by 0.01; calibrating elsewhere leaves that blend's own error of 0.01.
TEST(LeaveOneOut, AnOutlyingCalibrationBlendCarriesItsErrorToEveryPrediction) {
  auto curves = consistent_blends();
  curves[2].measured -= 0.01;
  const auto study = aggpack::leave_one_out(curves);
  const auto& on_outlier = study.choices[2];
  ASSERT_TRUE(on_outlier.fitted);
  EXPECT_NEAR(on_outlier.fitted->value, 0.33, 1e-12);
  EXPECT_NEAR(on_outlier.mean_absolute_error, 0.01, 1e-12);
  EXPECT_NEAR(on_outlier.largest_error, -0.01, 1e-12);
  for (const std::size_t k : {0u, 1u, 3u, 7u}) {
    EXPECT_NEAR(study.choices[k].mean_absolute_error, 0.01 / 7.0, 1e-12);
    EXPECT_NEAR(study.choices[k].largest_error, 0.01, 1e-12);
  }
  // Seven choices at 0.01/7 and one at 0.01: the median is one of the seven.
  ASSERT_TRUE(study.median);
  EXPECT_NE(*study.median, 2u);
  EXPECT_NEAR(study.choices[*study.median].mean_absolute_error, 0.01 / 7.0, 1e-12);
}

TEST(LeaveOneOut, SaysWhenAMeasurementIsBeyondTheGridsReach) {
  auto curves = consistent_blends();
  curves[0].measured = 0.70;                                   // the loosest value gives 0.765
  curves[1].measured = curves[1].density.back().mean - 0.001;  // beyond the end by half its standard error
  const auto study = aggpack::leave_one_out(curves);
  EXPECT_FALSE(study.choices[0].fitted);
  EXPECT_TRUE(std::isnan(study.choices[0].mean_absolute_error));
  EXPECT_NE(study.choices[0].why_not_fitted.find("out of reach: 0.8000 at 0 to 0.7650 at 0.35, measured 0.700"),
            std::string::npos)
      << study.choices[0].why_not_fitted;
  ASSERT_TRUE(study.choices[1].fitted);
  EXPECT_TRUE(study.choices[1].fitted->at_end);
  EXPECT_DOUBLE_EQ(study.choices[1].fitted->value, 0.35);
  EXPECT_NEAR(study.choices[1].fitted->band_low, 0.34, 1e-12);  // the measurement + 0.002 crosses at 0.34
  EXPECT_DOUBLE_EQ(study.choices[1].fitted->band_high, 0.35);   // clipped at the grid's end
}

// At the grid's front (the densest value) too, and the nearer end when both are within reach.
TEST(LeaveOneOut, TakesTheNearerGridEndWithinItsStandardError) {
  auto curves = consistent_blends();
  curves[0].measured = curves[0].density.front().mean + 0.0015;
  const auto front = aggpack::crossing_on_grid(curves[0], curves[0].measured);
  ASSERT_TRUE(front);
  EXPECT_TRUE(front->at_end);
  EXPECT_DOUBLE_EQ(front->value, 0.0);
  // A flat curve: both ends within reach, the back nearer.
  GridCurve flat = line(9, 30.0, 0.70, 0.0, 0.0);
  flat.density.front().mean = 0.7015;
  flat.density.back().mean = 0.7005;
  const auto back = aggpack::crossing_on_grid(flat, 0.6999);
  ASSERT_TRUE(back);
  EXPECT_DOUBLE_EQ(back->value, 0.35);
}

// A curve that turns: the first crossing (the lowest value) is taken and the count says there
// were more; the predictions' band reaches the grid value inside it where another curve turns.
TEST(LeaveOneOut, ANonMonotoneCurveTakesTheFirstCrossingAndSaysSo) {
  GridCurve turning = line(1, 29.0, 0.70, 0.0, 0.695);
  for (const auto& [k, phi] : {std::pair{0, 0.70}, {1, 0.69}, {2, 0.70}, {3, 0.69}}) turning.density[k].mean = phi;
  const auto c = aggpack::crossing_on_grid(turning, 0.695);
  ASSERT_TRUE(c);
  EXPECT_NEAR(c->value, 0.05, 1e-12);
  EXPECT_EQ(c->crossings, 3u);

  // Calibrated on a straight blend at 0.1 with a band 0.05-0.15 wide, a blend peaking at 0.1
  // is predicted with a band that reaches its peak.
  std::vector<GridCurve> curves{line(1, 29.0, 0.80, 0.1, 0.79, 0.005), line(2, 30.0, 0.80, 0.1, 0.79, 0.005),
                                line(3, 31.0, 0.70, 0.0, 0.0, 0.005)};
  curves[2].density[0].mean = 0.70, curves[2].density[1].mean = 0.75, curves[2].density[2].mean = 0.70;
  curves[2].density[3].mean = 0.70;
  const auto study = aggpack::leave_one_out(curves);
  ASSERT_TRUE(study.choices[0].fitted);
  EXPECT_NEAR(study.choices[0].fitted->value, 0.1, 1e-12);
  const auto& peaked = study.choices[0].predicted[1];
  ASSERT_EQ(peaked.mix, 3);
  EXPECT_NEAR(peaked.density, 0.75, 1e-12);
  EXPECT_NEAR(peaked.band_high, 0.75, 1e-12);
  EXPECT_LT(peaked.band_low, 0.75);
}

// Five fitted choices of distinct errors: the median is the third best. (Calibrating on blend k
// moves every prediction by k's offset from its curve, so its error to blend j is the
// difference of their offsets.)
TEST(LeaveOneOut, TheMedianChoiceIsTheMiddleByError) {
  std::vector<GridCurve> curves;
  const std::vector<double> offsets{0.0, 0.004, -0.01, 0.02, 0.035};  // each blend's lab value off its curve
  for (std::size_t k = 0; k < offsets.size(); ++k)
    curves.push_back(line(static_cast<int>(k + 1), 30.0 + k, 0.80, 0.2, 0.80 - 0.2 * 0.2 + offsets[k]));
  const auto study = aggpack::leave_one_out(curves);
  std::vector<std::pair<double, std::size_t>> by_error;
  for (std::size_t k = 0; k < study.choices.size(); ++k) {
    ASSERT_TRUE(study.choices[k].fitted) << k;
    double sum = 0.0;
    for (const double o : offsets) sum += std::abs(offsets[k] - o);
    EXPECT_NEAR(study.choices[k].mean_absolute_error, sum / 4.0, 1e-12) << k;
    by_error.emplace_back(study.choices[k].mean_absolute_error, k);
  }
  std::sort(by_error.begin(), by_error.end());
  for (std::size_t k = 0; k + 1 < by_error.size(); ++k) ASSERT_LT(by_error[k].first + 1e-6, by_error[k + 1].first);
  ASSERT_TRUE(study.median);
  EXPECT_EQ(*study.median, by_error[2].second);
  EXPECT_EQ(*study.median, 3u);  // the blend 0.02 off its curve: 0.081 / 4 against 0.065, 0.069, 0.099, 0.126
}

TEST(LeaveOneOut, NothingFittedHasNoMedianAndOneSeedNoBand) {
  auto far = consistent_blends();
  for (auto& c : far) c.measured = 0.5;
  const auto none = aggpack::leave_one_out(far);
  EXPECT_FALSE(none.median);

  std::vector<GridCurve> one_seed;
  for (int k = 0; k < 3; ++k) one_seed.push_back(line(k + 1, 30.0 + k, 0.8, 0.1, 0.78, 0.0, 1));
  const auto study = aggpack::leave_one_out(one_seed);
  ASSERT_TRUE(study.choices[0].fitted);
  EXPECT_NEAR(study.choices[0].fitted->value, 0.2, 1e-12);
  EXPECT_TRUE(std::isnan(study.choices[0].fitted->band_low));
  EXPECT_TRUE(std::isnan(study.choices[0].predicted[0].band_low));
}

TEST(LeaveOneOut, RefusesTooFewBlendsAndDifferentGrids) {
  auto curves = consistent_blends();
  EXPECT_THROW(aggpack::leave_one_out({curves[0], curves[1]}), aggpack::InputError);
  auto other_grid = curves;
  other_grid[3].values[1] = 0.15;
  EXPECT_THROW(aggpack::leave_one_out(other_grid), aggpack::InputError);
  auto repeated = curves;
  for (auto& c : repeated) c.values[2] = c.values[1];
  EXPECT_THROW(aggpack::leave_one_out(repeated), aggpack::InputError);
  EXPECT_THROW(aggpack::density_on_grid(curves[0], 0.5), aggpack::InputError);
}

}  // namespace
