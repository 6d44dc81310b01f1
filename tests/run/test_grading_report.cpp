// `aggpack grading --shape`: the grains a run would make of a grading, and what they measure
// beside the lab's target.
#include "aggpack/run/grading_report.hpp"

#include <gtest/gtest.h>

#include <string>

#include "aggpack/core/error.hpp"
#include "aggpack/io/shape_option.hpp"

namespace aggpack {
namespace {

GradingDescription with_shape(const std::string& grading, const std::string& shape, double d_min = 2.54e-3) {
  GradingQuery q;
  q.grading = grading;
  q.d_min = d_min;
  q.shape = read_shape_option(shape, "--shape");
  return describe_grading(q);
}

// The recipe's crushed stone: the templates, measured at the grading's sizes by mass, have the
// flakiness they were fitted to (within the fit's 1 percentage point).
TEST(GradingShape, TheGeneratedGrainsMeasureTheTargetTheyWereFittedTo) {
  const GradingDescription d = with_shape("fu2003_table1_coarse", "family = \"angular\", spheres = 4, flakiness_index = 18");
  ASSERT_TRUE(d.shape);
  ASSERT_TRUE(d.shape->templates.flakiness_index);
  EXPECT_NEAR(*d.shape->templates.flakiness_index, 18.0, 1.0);
  EXPECT_EQ(d.shape->library.grains.size(), 12u);
  // The sizes measured lie within the cut grading (2.54 to 25 mm).
  for (const double w : d.shape->fit_sizes) {
    EXPECT_GE(w, 2.54e-3);
    EXPECT_LE(w, 25e-3);
  }
  // Another target moves the fitted flatness the way the standard says: flakier, flatter.
  const GradingDescription flakier =
      with_shape("fu2003_table1_coarse", "family = \"angular\", spheres = 4, flakiness_index = 40");
  ASSERT_TRUE(flakier.shape && flakier.shape->templates.flakiness_index);
  EXPECT_LT(flakier.shape->library.distribution.flatness_mean, d.shape->library.distribution.flatness_mean);
  EXPECT_NEAR(*flakier.shape->templates.flakiness_index, 40.0, 1.0);
}

// Given proportions, no target: grains five times as long as wide are all elongated (L/S > 3
// whatever their thickness), and round grains count for no standard.
TEST(GradingShape, GivenProportionsAreMeasuredAsGiven) {
  const GradingDescription needles =
      with_shape("fu2003_table1_coarse", "family = \"rounded\", spheres = 8, elongation = 0.2, spread = 0");
  ASSERT_TRUE(needles.shape && needles.shape->templates.shape_index && needles.shape->templates.flat_elongated_3);
  EXPECT_DOUBLE_EQ(*needles.shape->templates.shape_index, 100.0);
  EXPECT_DOUBLE_EQ(*needles.shape->templates.flat_elongated_3, 100.0);
  EXPECT_FALSE(needles.shape->library.fit);
  const GradingDescription round =
      with_shape("fu2003_table1_coarse", "family = \"rounded\", spheres = 1, elongation = 1, flatness = 1, spread = 0");
  ASSERT_TRUE(round.shape && round.shape->templates.flakiness_index && round.shape->templates.flat_elongated_2);
  EXPECT_DOUBLE_EQ(*round.shape->templates.flakiness_index, 0.0);
  EXPECT_DOUBLE_EQ(*round.shape->templates.flat_elongated_2, 0.0);
  EXPECT_NEAR(round.shape->templates.mean_elongation, 1.0, 1e-9);
}

// A sand has no grain that a flakiness index measures: the error names the option and why.
TEST(GradingShape, AMeasureThatAppliesToNoSizeIsRefusedNamingTheOption) {
  try {
    (void)with_shape("astm_c33_fine_mid", "family = \"angular\", flakiness_index = 18", 0.15e-3);
    FAIL() << "a sand's flakiness was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--shape"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("applies to no grain"), std::string::npos) << e.what();
  }
}

// The option is read by the scenario's own reader: its keys, ranges and messages.
TEST(GradingShape, TheOptionIsReadAsAScenarioShapeTable) {
  EXPECT_EQ(read_shape_option("{family = \"angular\", corners = 20}", "--shape").corners, 20u);
  EXPECT_EQ(read_shape_option("family = \"rounded\"", "--shape").family, GrainFamily::Rounded);
  const auto refused = [](const std::string& text, const std::string& words) {
    try {
      (void)read_shape_option(text, "--shape");
      ADD_FAILURE() << text << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--shape"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  refused("family = \"cubic\"", "family");
  refused("family = \"rounded\", corners = 20", "corners");
  refused("family = \"angular\", spheres = 100", "spheres");
  refused("family = \"angular\", flakines_index = 18", "flakiness_index");  // the typo's nearest key
  refused("family = angular", "not a TOML inline table");
  refused("spheres = 6", "family");
}

}  // namespace
}  // namespace aggpack
