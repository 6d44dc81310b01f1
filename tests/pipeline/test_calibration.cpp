// CPM's calibration read backwards from densities the model itself made.
#include <vector>

#include <gtest/gtest.h>

#include "aggpack/core/error.hpp"
#include "aggpack/pipeline/calibration.hpp"

namespace {

TEST(Calibration, RecoversTheKAndBetaThatMadeTheDensities) {
  const aggpack::ModelDistribution mix{{{0.0254, 0.0254, 0.0254, 0.8}, {0.0127, 0.0127, 0.0127, 0.2}}, "test"};
  for (const auto& [k, beta] : std::vector<std::pair<double, double>>{{4.1, 0.72}, {4.75, 0.66}, {9.0, 0.70}}) {
    const double mono = beta / (1.0 + 1.0 / k);
    const double phi = aggpack::cpm(mix, std::vector<double>{beta}, k).density;
    const auto fit = aggpack::solve_calibration(mix, mono, phi);
    EXPECT_NEAR(fit.compaction_index, k, 1e-6 * k) << k << " " << beta;
    EXPECT_NEAR(fit.beta, beta, 1e-8) << k << " " << beta;
  }
}

TEST(Calibration, SaysSoWhenNoKFits) {
  const aggpack::ModelDistribution mix{{{0.0254, 0.0254, 0.0254, 0.8}, {0.0127, 0.0127, 0.0127, 0.2}}, "test"};
  // A mix looser than its monosized bed: CPM always gains from a second size.
  EXPECT_THROW((void)aggpack::solve_calibration(mix, 0.60, 0.55), aggpack::InputError);
  EXPECT_THROW((void)aggpack::solve_calibration(mix, 1.2, 0.55), aggpack::InputError);
}

}  // namespace
