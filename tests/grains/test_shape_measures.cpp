// The lab's shape measures on grains of known dimensions, and proportions fitted to them,
// checked on grains drawn independently from the fitted distribution.
#include "aggpack/grains/shape_measures.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "aggpack/core/error.hpp"

namespace aggpack {
namespace {

const ShapeTarget kFlakiness{ShapeMeasure::FlakinessIndex, 0.0, 0.0};
const ShapeTarget kShapeIndex{ShapeMeasure::ShapeIndex, 0.0, 0.0};

// EN 933-3: a grain of width 9 mm is of class 8/10, whose bar gap is 5 mm.
TEST(ShapeMeasures, AGrainIsFlakyWhenItsThicknessPassesItsClasssBarSieve) {
  EXPECT_TRUE(counts(kFlakiness, {20e-3, 9e-3, 4.9e-3, 1.0}));
  EXPECT_FALSE(counts(kFlakiness, {20e-3, 9e-3, 5.1e-3, 1.0}));
  // Class 10/12.5 (gap 6.3 mm) from 10 mm on.
  EXPECT_TRUE(counts(kFlakiness, {20e-3, 10e-3, 6.2e-3, 1.0}));
  EXPECT_FALSE(counts(kFlakiness, {20e-3, 9.99e-3, 5.5e-3, 1.0}));
  // Outside 4 to 80 mm the standard measures nothing.
  EXPECT_FALSE(measured(ShapeMeasure::FlakinessIndex, {5e-3, 3.9e-3, 1e-3, 1.0}));
  EXPECT_FALSE(measured(ShapeMeasure::FlakinessIndex, {0.2, 80e-3, 10e-3, 1.0}));
  EXPECT_TRUE(measured(ShapeMeasure::FlakinessIndex, {0.2, 79e-3, 10e-3, 1.0}));
}

TEST(ShapeMeasures, ShapeIndexAndFlatAndElongatedCompareLengthWithThickness) {
  EXPECT_TRUE(counts(kShapeIndex, {31e-3, 12e-3, 10e-3, 1.0}));
  EXPECT_FALSE(counts(kShapeIndex, {29e-3, 12e-3, 10e-3, 1.0}));
  const ShapeTarget two_to_one{ShapeMeasure::FlatAndElongated, 0.0, 2.0};
  EXPECT_TRUE(counts(two_to_one, {21e-3, 12e-3, 10e-3, 1.0}));
  EXPECT_FALSE(counts(two_to_one, {19e-3, 12e-3, 10e-3, 1.0}));
  EXPECT_FALSE(measured(ShapeMeasure::FlatAndElongated, {10e-3, 4.7e-3, 2e-3, 1.0}));
  EXPECT_FALSE(measured(ShapeMeasure::ShapeIndex, {100e-3, 63e-3, 20e-3, 1.0}));
}

// By mass, over the grains measured: a flaky grain of mass 1 beside a cubical one of mass 3
// is 25 %; a sand grain beside them does not count either way.
TEST(ShapeMeasures, ThePercentageIsByMassOfTheGrainsMeasured) {
  const std::vector<GrainMeasure> grains{{20e-3, 9e-3, 3e-3, 1.0}, {10e-3, 9e-3, 8e-3, 3.0}, {2e-3, 2e-3, 0.1e-3, 5.0}};
  EXPECT_DOUBLE_EQ(*measured_percent(kFlakiness, grains), 25.0);
  const std::vector<GrainMeasure> sand{{2e-3, 2e-3, 0.1e-3, 5.0}};
  EXPECT_FALSE(measured_percent(kFlakiness, sand).has_value());
}

// Four grains whose every measure is counted by hand: the mean proportions by number, each
// standard's percentage by mass of the grains it applies to.
TEST(ShapeMeasures, StatisticsReportEveryStandardByMassAndTheMeanProportionsByNumber) {
  const std::vector<GrainMeasure> grains{
      {60e-3, 15e-3, 10e-3, 1.0},  // L/S 6, class 12.5/16 (gap 8 mm): not flaky; counted at 2, 3 and 5:1
      {25e-3, 20e-3, 8e-3, 2.0},   // L/S 3.125, class 20/25 (gap 12.5 mm): flaky; 2 and 3:1
      {12e-3, 10e-3, 9e-3, 4.0},   // L/S 1.33, class 10/12.5 (gap 6.3 mm): counted by nothing
      {2e-3, 1e-3, 0.1e-3, 8.0},   // a sand grain: below every standard's range
  };
  const ShapeStatistics s = shape_statistics(grains);
  EXPECT_EQ(s.grains, 4u);
  EXPECT_DOUBLE_EQ(s.mean_elongation, (0.25 + 0.8 + 10.0 / 12.0 + 0.5) / 4.0);
  EXPECT_DOUBLE_EQ(s.mean_flatness, (10.0 / 15.0 + 0.4 + 0.9 + 0.1) / 4.0);
  EXPECT_DOUBLE_EQ(*s.flakiness_index, 100.0 * 2.0 / 7.0);
  EXPECT_DOUBLE_EQ(*s.shape_index, 100.0 * 3.0 / 7.0);
  EXPECT_DOUBLE_EQ(*s.flat_elongated_2, 100.0 * 3.0 / 7.0);
  EXPECT_DOUBLE_EQ(*s.flat_elongated_3, 100.0 * 3.0 / 7.0);
  EXPECT_DOUBLE_EQ(*s.flat_elongated_5, 100.0 * 1.0 / 7.0);
  const std::vector<GrainMeasure> sand{grains.back()};
  const ShapeStatistics only_sand = shape_statistics(sand);
  EXPECT_FALSE(only_sand.flakiness_index || only_sand.shape_index || only_sand.flat_elongated_2 ||
               only_sand.flat_elongated_3 || only_sand.flat_elongated_5);
  EXPECT_EQ(shape_statistics({}).grains, 0u);
}

// Grains drawn from a distribution: their percentage by mass, as a lab would measure it.
double drawn_percent(const ShapeTarget& target, const ProportionDistribution& d, const std::vector<double>& sizes) {
  Rng rng(2026, 12);  // another stream than the fit's
  std::vector<GrainMeasure> grains;
  for (int k = 0; k < 20000; ++k) {
    const double width = sizes[static_cast<std::size_t>(k) % sizes.size()];
    const Proportions p = d.draw(rng);
    const double length = width / p.elongation, thickness = width * p.flatness;
    grains.push_back({length, width, thickness, length * width * thickness});
  }
  return *measured_percent(target, grains);
}

std::vector<double> coarse_sizes() {
  std::vector<double> sizes;
  for (double mm = 4.75; mm < 19.0; mm += 0.35) sizes.push_back(1e-3 * mm);
  return sizes;
}

// "My crushed stone: flakiness 18 %": the fitted flatness, drawn again from another stream,
// gives 18 % within the sampling's scatter; likewise a shape index and D4791 at 3:1.
TEST(ShapeMeasures, FittedProportionsReproduceTheLabsPercentageOnGrainsDrawnAnew) {
  const ProportionDistribution start{0.7, 0.15, 0.7, 0.15};
  const std::vector<double> sizes = coarse_sizes();
  for (const ShapeTarget& target : {ShapeTarget{ShapeMeasure::FlakinessIndex, 18.0, 0.0},
                                    ShapeTarget{ShapeMeasure::ShapeIndex, 25.0, 0.0},
                                    ShapeTarget{ShapeMeasure::FlatAndElongated, 8.0, 3.0}}) {
    const ProportionFit fit = fit_proportions_to(target, start, sizes, 7);
    EXPECT_TRUE(fit.reached) << measure_name(target.measure);
    EXPECT_NEAR(fit.achieved_percent, target.percent, 0.5);
    EXPECT_NEAR(drawn_percent(target, fit.distribution, sizes), target.percent, 1.5) << measure_name(target.measure);
    EXPECT_EQ(fit.distribution.flatness_spread, 0.15);
  }
  // More flakiness asks for flatter grains; the elongation is left alone.
  const ProportionFit few = fit_proportions_to({ShapeMeasure::FlakinessIndex, 5.0, 0.0}, start, sizes, 7);
  const ProportionFit many = fit_proportions_to({ShapeMeasure::FlakinessIndex, 40.0, 0.0}, start, sizes, 7);
  EXPECT_GT(few.distribution.flatness_mean, many.distribution.flatness_mean);
  EXPECT_EQ(few.distribution.elongation_mean, 0.7);
}

// Grains all of one size and shape are all flaky or none: 50 % cannot be had, and the fit says so.
TEST(ShapeMeasures, AnUnreachablePercentageIsReportedNotHidden) {
  const std::vector<double> one_size{9e-3};
  const ProportionFit fit =
      fit_proportions_to({ShapeMeasure::FlakinessIndex, 50.0, 0.0}, ProportionDistribution{}, one_size, 3);
  EXPECT_FALSE(fit.reached);
  EXPECT_TRUE(fit.achieved_percent == 0.0 || fit.achieved_percent == 100.0);
}

TEST(ShapeMeasures, BadTargetsAndDistributionsAreRefused) {
  const std::vector<double> sand{1e-3, 2e-3}, stone{10e-3};
  EXPECT_THROW((void)fit_proportions_to({ShapeMeasure::FlakinessIndex, 10.0, 0.0}, {}, sand, 1), InputError);
  EXPECT_THROW((void)fit_proportions_to({ShapeMeasure::FlakinessIndex, 110.0, 0.0}, {}, stone, 1), InputError);
  EXPECT_THROW((void)fit_proportions_to({ShapeMeasure::FlatAndElongated, 10.0, 0.5}, {}, stone, 1), InputError);
  EXPECT_THROW((ProportionDistribution{1.2, 0.0, 0.5, 0.0}.check()), InputError);
  EXPECT_THROW((ProportionDistribution{0.8, 0.6, 0.5, 0.0}.check()), InputError);
  EXPECT_NO_THROW((ProportionDistribution{0.8, 0.1, 0.5, 0.2}.check()));
}

// The draws: within mean ± spread, clamped to [0.1, 1], their mean the distribution's.
TEST(ShapeMeasures, DrawsAreTriangularAboutTheMean) {
  const ProportionDistribution d{0.6, 0.2, 0.95, 0.2};
  Rng rng(5, 5);
  double sum = 0.0;
  for (int k = 0; k < 10000; ++k) {
    const Proportions p = d.draw(rng);
    EXPECT_GE(p.elongation, 0.4);
    EXPECT_LE(p.elongation, 0.8);
    EXPECT_LE(p.flatness, 1.0);
    sum += p.elongation;
  }
  EXPECT_NEAR(sum / 10000, 0.6, 0.005);
}

}  // namespace
}  // namespace aggpack
