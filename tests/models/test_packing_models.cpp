// The analytic packing models against their published limits and closed forms.
#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "aggpack/core/error.hpp"
#include "aggpack/models/packing_models.hpp"

namespace {

using aggpack::ModelClass;
using aggpack::ModelDistribution;

ModelDistribution binary(double d_coarse, double d_fine, double fine_fraction) {
  return {{{d_coarse, d_coarse, d_coarse, 1.0 - fine_fraction}, {d_fine, d_fine, d_fine, fine_fraction}}, "test"};
}

TEST(Cpm, OneClassPacksAtBetaOverOnePlusOneOverK) {
  const ModelDistribution mono{{{0.01, 0.01, 0.01, 1.0}}, "test"};
  for (const double beta : {0.60, 0.64, 0.74})
    for (const double k : {4.1, 4.5, 4.75, 9.0}) {
      const auto r = aggpack::cpm(mono, std::vector<double>{beta}, k);
      EXPECT_NEAR(r.density, beta / (1.0 + 1.0 / k), 1e-14) << beta << " " << k;
      EXPECT_DOUBLE_EQ(r.virtual_density, beta);
      EXPECT_NEAR(aggpack::cpm_compaction_index(mono, std::vector<double>{beta}, r.density), k, 1e-9 * k);
      EXPECT_NEAR(aggpack::cpm_beta_from_monosized(r.density, k), beta, 1e-14);
    }
}

TEST(Cpm, ALargeCompactionIndexGivesTheVirtualPacking) {
  const ModelDistribution mix = binary(0.0254, 0.0127, 0.2);
  const std::vector<double> beta{0.70};
  const auto loose = aggpack::cpm(mix, beta, 4.1), tight = aggpack::cpm(mix, beta, 1e9);
  EXPECT_LT(loose.density, tight.density);
  EXPECT_NEAR(tight.density, tight.virtual_density, 1e-8);
  // The density rises with K: more compaction, a denser packing.
  double last = 0.0;
  for (const double k : {1.0, 2.0, 4.1, 4.75, 9.0, 100.0}) {
    const double phi = aggpack::cpm(mix, beta, k).density;
    EXPECT_GT(phi, last);
    last = phi;
  }
}

TEST(Cpm, TheInteractionFunctionsVanishAndSaturateAtTheirLimits) {
  // No interaction between sizes far apart; full interaction (one class) between equal sizes.
  // Near a zero size ratio x: a ~ sqrt(1.02 x) and b ~ 1.5 x, from their power laws.
  EXPECT_NEAR(aggpack::cpm_loosening(1e-8, 1.0), std::sqrt(1.02e-8), 1e-6 * std::sqrt(1.02e-8));
  EXPECT_NEAR(aggpack::cpm_wall(1e-8, 1.0), 1.5e-8, 1e-6 * 1.5e-8);
  EXPECT_DOUBLE_EQ(aggpack::cpm_loosening(1.0, 1.0), 1.0);
  EXPECT_DOUBLE_EQ(aggpack::cpm_wall(1.0, 1.0), 1.0);
  // Monotone in between.
  double a = 0.0, b = 0.0;
  for (double ratio = 0.05; ratio <= 1.0; ratio += 0.05) {
    EXPECT_GT(aggpack::cpm_loosening(ratio, 1.0), a);
    EXPECT_GT(aggpack::cpm_wall(ratio, 1.0), b);
    a = aggpack::cpm_loosening(ratio, 1.0);
    b = aggpack::cpm_wall(ratio, 1.0);
  }
}

TEST(Cpm, TwoEqualSizesAreOneClass) {
  const auto split = aggpack::cpm(binary(0.01, 0.01, 0.3), std::vector<double>{0.66}, 4.1);
  const auto one = aggpack::cpm({{{0.01, 0.01, 0.01, 1.0}}, "test"}, std::vector<double>{0.66}, 4.1);
  EXPECT_NEAR(split.density, one.density, 1e-14);
}

TEST(Cpm, AtAVanishingSizeRatioTheVirtualPackingIsFurnassLimit) {
  for (const double y : {0.05, 0.2, 0.27, 0.4, 0.7}) {
    const ModelDistribution mix = binary(1.0, 1e-14, y);  // the loosening effect ~ sqrt(ratio): 1e-7
    const auto r = aggpack::cpm(mix, std::vector<double>{0.64, 0.60}, 4.1);
    EXPECT_NEAR(r.virtual_density, aggpack::furnas_binary(0.64, 0.60, y), 1e-6) << y;
  }
  // Furnas's densest mix: phi_c + phi_f - phi_c phi_f, where the two regimes meet.
  const double y_star = aggpack::furnas_densest_fine_fraction(0.64, 0.60);
  EXPECT_NEAR(aggpack::furnas_binary(0.64, 0.60, y_star), aggpack::furnas_densest(0.64, 0.60), 1e-14);
  EXPECT_NEAR(aggpack::furnas_densest(0.64, 0.64), 1.0 - 0.36 * 0.36, 1e-14);
  EXPECT_LT(aggpack::furnas_binary(0.64, 0.60, y_star - 0.01), aggpack::furnas_densest(0.64, 0.60));
  EXPECT_LT(aggpack::furnas_binary(0.64, 0.60, y_star + 0.01), aggpack::furnas_densest(0.64, 0.60));
}

TEST(Cpm, RefusesWhatHasNoMeaning) {
  const ModelDistribution mono{{{0.01, 0.01, 0.01, 1.0}}, "test"};
  EXPECT_THROW(aggpack::cpm(mono, std::vector<double>{1.2}, 4.1), aggpack::InputError);
  EXPECT_THROW(aggpack::cpm(mono, std::vector<double>{0.64}, 0.0), aggpack::InputError);
  EXPECT_THROW(aggpack::cpm(mono, std::vector<double>{0.6, 0.6}, 4.1), aggpack::InputError);
  EXPECT_THROW(aggpack::cpm({{}, "empty"}, std::vector<double>{0.6}, 4.1), aggpack::InputError);
  EXPECT_THROW((void)aggpack::cpm_compaction_index(mono, std::vector<double>{0.6}, 0.61), aggpack::InputError);
}

TEST(CompactionIndex, DeLarrardsTableByProcess) {
  EXPECT_EQ(aggpack::compaction_index_of("poured"), 4.1);
  EXPECT_EQ(aggpack::compaction_index_of("rodded"), 4.5);
  EXPECT_EQ(aggpack::compaction_index_of("vibrated"), 4.75);
  EXPECT_EQ(aggpack::compaction_index_of("vibrated_compressed"), 9.0);
  EXPECT_FALSE(aggpack::compaction_index_of("shaken"));
}

TEST(DesmondWeeks, MonosizedIsRandomClosePackingAndMomentsMatchTheirClosedForms) {
  const std::vector<double> mono(100, 0.01);
  const auto m = aggpack::radius_moments(std::span<const double>(mono));
  EXPECT_EQ(m.polydispersity, 0.0);
  EXPECT_DOUBLE_EQ(aggpack::desmond_weeks_rcp(m), 0.634);
  // Two radii 1 and 3 in equal numbers: mean 2, sd 1, no skew.
  const std::vector<double> two{2.0, 6.0, 2.0, 6.0};
  const auto t = aggpack::radius_moments(std::span<const double>(two));
  EXPECT_NEAR(t.polydispersity, 0.5, 1e-14);
  EXPECT_NEAR(t.skewness, 0.0, 1e-12);
  EXPECT_NEAR(aggpack::desmond_weeks_rcp(t), 0.634 + 0.0658 * 0.5, 1e-14);
  // A binary mix by volume gives the same moments as its spheres listed one by one.
  // Volume 0.9 : 0.1 of diameters 6 and 2: numbers 0.9/216 : 0.1/8, three fine per coarse.
  const ModelDistribution mix = binary(6.0, 2.0, 0.1);
  std::vector<double> spheres(1000, 6.0);
  spheres.resize(4000, 2.0);
  const auto from_classes = aggpack::radius_moments(mix), from_spheres = aggpack::radius_moments(std::span<const double>(spheres));
  EXPECT_NEAR(from_classes.polydispersity, from_spheres.polydispersity, 1e-12);
  EXPECT_NEAR(from_classes.skewness, from_spheres.skewness, 1e-12);
}

TEST(DesmondWeeks, ASieveFractionsMomentsAreThoseOfItsD4NumberDensity) {
  // One fraction [1, 2] with volume uniform in log d: number density ~ d^-4. Its radius
  // moments by quadrature against the closed form.
  const ModelDistribution fraction{{{std::sqrt(2.0), 1.0, 2.0, 1.0}}, "test"};
  double m[4] = {0, 0, 0, 0};
  const int n = 200000;
  for (int k = 0; k < n; ++k) {
    const double d = 1.0 + (k + 0.5) / n, w = std::pow(d, -4.0);
    for (int p = 0; p < 4; ++p) m[p] += w * std::pow(0.5 * d, p);
  }
  const double mean = m[1] / m[0], var = m[2] / m[0] - mean * mean;
  const double third = m[3] / m[0] - 3 * mean * m[2] / m[0] + 2 * mean * mean * mean;
  const auto closed = aggpack::radius_moments(fraction);
  EXPECT_NEAR(closed.polydispersity, std::sqrt(var) / mean, 1e-8);
  EXPECT_NEAR(closed.skewness, third / std::pow(var, 1.5), 1e-6);
}

TEST(GradingClasses, SieveFractionsAtTheGeometricMeanOfTheirSieves) {
  const aggpack::Grading g = aggpack::make_grading(
      "test", {{"", 0.001, 10.0}, {"", 0.002, 40.0}, {"", 0.004, 100.0}}, "test", {"a", "b", "c"});
  const auto whole = aggpack::grading_classes(g);
  ASSERT_EQ(whole.classes.size(), 3u);  // [2, 4], [1, 2] and the pan [0.5, 1] mm
  EXPECT_NEAR(whole.classes[0].diameter, std::sqrt(0.002 * 0.004), 1e-15);
  EXPECT_NEAR(whole.classes[0].volume_fraction, 0.6, 1e-12);
  EXPECT_NEAR(whole.classes[1].volume_fraction, 0.3, 1e-12);
  EXPECT_NEAR(whole.classes[2].volume_fraction, 0.1, 1e-12);
  EXPECT_NEAR(whole.classes[2].diameter, 0.001 / std::numbers::sqrt2, 1e-15);
  // Cut at 2 mm: the coarse fraction alone.
  const auto cut = aggpack::grading_classes(g, 0.002);
  ASSERT_EQ(cut.classes.size(), 1u);
  EXPECT_DOUBLE_EQ(cut.classes[0].volume_fraction, 1.0);
  // A blend at coarse/fine 3: three quarters of the volume coarse.
  const auto mix = aggpack::blend(cut, aggpack::grading_classes(g, 0.001, 0.002), 3.0);
  ASSERT_EQ(mix.classes.size(), 2u);
  EXPECT_NEAR(mix.classes[0].volume_fraction, 0.75, 1e-14);
  // Each class knows its aggregate, for a fine aggregate's own beta.
  EXPECT_FALSE(mix.classes[0].fine);
  EXPECT_TRUE(mix.classes[1].fine);
}

TEST(DiameterClasses, EqualSizesAreOneClassAndManySizesAreBinned) {
  const std::vector<double> d{0.0254, 0.0127, 0.0127, 0.0254, 0.0127};
  const auto c = aggpack::diameter_classes(d);
  ASSERT_EQ(c.classes.size(), 2u);
  EXPECT_NEAR(c.classes[0].volume_fraction, 2 * 8.0 / (2 * 8.0 + 3 * 1.0), 1e-14);
  std::vector<double> many;
  for (int k = 0; k < 1000; ++k) many.push_back(0.001 * (1.0 + k / 1000.0));
  const auto binned = aggpack::diameter_classes(many, 64);
  EXPECT_EQ(binned.classes.size(), 4u);  // 1 to 2 mm in classes of ratio 2^(1/4)
  double total = 0.0;
  for (const auto& cl : binned.classes) total += cl.volume_fraction;
  EXPECT_NEAR(total, 1.0, 1e-14);
}

}  // namespace
