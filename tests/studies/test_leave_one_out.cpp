// "Calibrate on one blend, predict the rest" on a grid, against curves with closed forms.
#include <gtest/gtest.h>

#include <cmath>
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
  EXPECT_LE(study.choices[1].fitted->band_low, 0.35);
  EXPECT_DOUBLE_EQ(study.choices[1].fitted->band_high, 0.35);  // clipped at the grid's end
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
  curves[3].values[1] = 0.15;
  EXPECT_THROW(aggpack::leave_one_out(curves), aggpack::InputError);
  EXPECT_THROW(aggpack::density_on_grid(curves[0], 0.5), aggpack::InputError);
}

}  // namespace
