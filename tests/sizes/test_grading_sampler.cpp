#include "aggpack/sizes/grading_sampler.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "aggpack/core/error.hpp"

namespace aggpack {
namespace {

double volume(double d) { return std::numbers::pi / 6 * d * d * d; }

// Mass sampling: the generated percent passing by mass at every sieve matches the
// renormalised target within 5 standard errors of the ratio estimator, computed here from
// the sample itself (delta method).
TEST(GradingSampler, MassModeReproducesTheCurveAtEverySieve) {
  const GradingCut cut = cut_grading(*named_grading("fu2003_table1_coarse"), 0.1 * 0.0254, std::nullopt, "test");
  const GradingSampler sampler(cut, SamplingMode::Mass);
  Rng rng(5, 1);
  const auto d = sample_diameters(sampler, {200000, {}}, rng);
  double total = 0.0;
  for (double x : d) total += volume(x);
  const double mean_v = total / static_cast<double>(d.size());
  for (const Sieve& s : cut.grading.sieves) {
    const double target = cut.renormalised_passing(s.opening);
    double passing = 0.0;
    for (double x : d)
      if (x <= s.opening) passing += volume(x);
    const double p = passing / total;
    double var = 0.0;
    for (double x : d) {
      const double r = (x <= s.opening ? volume(x) : 0.0) - p * volume(x);
      var += r * r;
    }
    const double se = std::sqrt(var / static_cast<double>(d.size())) / mean_v / std::sqrt(static_cast<double>(d.size()));
    EXPECT_NEAR(100 * p, target, 100 * (5 * se) + 1e-9) << s.name;
  }
  // The cut at 0.1 in = 2.54 mm falls between #8 (2.36 mm, 2.7 %) and #4 (4.75 mm, 6.8 %).
  EXPECT_NEAR(cut.cut_below, 0.027 + (0.068 - 0.027) * std::log(2.54 / 2.36) / std::log(4.75 / 2.36), 1e-12);
}

TEST(GradingSampler, NumberModeReproducesTheCurveByCount) {
  const GradingCut cut = cut_grading(*named_grading("astm_c33_fine_mid"), std::nullopt, std::nullopt, "test");
  const GradingSampler sampler(cut, SamplingMode::Number);
  Rng rng(6, 1);
  const std::size_t n = 100000;
  const auto d = sample_diameters(sampler, {n, {}}, rng);
  for (const Sieve& s : cut.grading.sieves) {
    const double p = cut.renormalised_passing(s.opening) / 100;
    const double got =
        static_cast<double>(std::count_if(d.begin(), d.end(), [&](double x) { return x <= s.opening; })) / n;
    EXPECT_NEAR(got, p, 5 * std::sqrt(p * (1 - p) / n) + 1e-12) << s.name;
  }
}

// Three sieves a < b < c, two intervals with number fractions f1, f2. Number mode draws
// uniformly in d within an interval, so interval i holds the volume fraction
// f_i E_i[d^3] / sum_j f_j E_j[d^3] with E[d^3] = (hi^4 - lo^4) / (4 (hi - lo)); mass
// mode holds f_i. The test checks that ratio on a large sample.
TEST(GradingSampler, NumberToMassVolumeRatioMatchesTheAnalyticValue) {
  const Grading g = make_grading("two", {{"a", 1e-3, 0}, {"b", 2e-3, 40}, {"c", 4e-3, 100}}, "test", {});
  const GradingCut cut = cut_grading(g, std::nullopt, std::nullopt, "test");
  const auto e3 = [](double lo, double hi) { return (std::pow(hi, 4) - std::pow(lo, 4)) / (4 * (hi - lo)); };
  const double f1 = 0.4, f2 = 0.6;
  const double number_fraction_1 = f1 * e3(1e-3, 2e-3) / (f1 * e3(1e-3, 2e-3) + f2 * e3(2e-3, 4e-3));
  const double expected_ratio = number_fraction_1 / f1;
  Rng rng(7, 1);
  const auto measure = [&](SamplingMode mode) {
    const auto d = sample_diameters(GradingSampler(cut, mode), {400000, {}}, rng);
    double below = 0.0, total = 0.0;
    for (double x : d) {
      total += volume(x);
      if (x <= 2e-3) below += volume(x);
    }
    return below / total;
  };
  const double mass = measure(SamplingMode::Mass), number = measure(SamplingMode::Number);
  EXPECT_NEAR(mass, f1, 0.005);
  EXPECT_NEAR(number / mass, expected_ratio, 0.02 * expected_ratio);
  EXPECT_LT(expected_ratio, 0.5);  // number mode starves the fine interval of volume
}

TEST(GradingSampler, MeanParticleVolumeMatchesTheSample) {
  for (const SamplingMode mode : {SamplingMode::Mass, SamplingMode::Number}) {
    const GradingSampler sampler(cut_grading(*named_grading("astm_c33_fine_mid"), 0.3e-3, {}, "t"), mode);
    Rng rng(12, 1);
    const auto d = sample_diameters(sampler, {200000, {}}, rng);
    double total = 0.0;
    for (double x : d) total += volume(x);
    EXPECT_NEAR(total / d.size(), sampler.mean_particle_volume(), 0.03 * sampler.mean_particle_volume());
  }
}

TEST(GradingSampler, SolidVolumeStopsAtTheFirstParticleThatReachesIt) {
  const GradingSampler sampler(cut_grading(*named_grading("astm_c33_57_mid"), 0.2 * 0.0254, {}, "test"),
                               SamplingMode::Mass);
  Rng rng(8, 1);
  const double target = 1e-3;
  const auto d = sample_diameters(sampler, {{}, target}, rng);
  double total = 0.0;
  for (double x : d) total += volume(x);
  EXPECT_GE(total, target);
  EXPECT_LT(total - volume(d.back()), target);
}

TEST(GradingSampler, InterleavedMixHoldsTheRatioAtEveryPrefix) {
  const GradingSampler coarse(cut_grading(*named_grading("fu2003_table1_coarse"), 0.2 * 0.0254, {}, "c"),
                              SamplingMode::Mass);
  // The sand is cut at #4 so that sizes tell coarse from fine in the check below.
  const GradingSampler fine(cut_grading(*named_grading("astm_c33_fine_mid"), 0.02 * 0.0254, 4.75e-3, "f"),
                            SamplingMode::Mass);
  const double ratio = 1.52;
  Rng rng(9, 1);
  const auto d = sample_mix(coarse, fine, ratio, {20000, {}}, MixOrder::Interleaved, rng);
  ASSERT_EQ(d.size(), 20000u);
  const double split = 0.2 * 0.0254;  // coarse particles are all larger than this, fines smaller
  const double v_coarse_max = volume(0.0254), v_fine_max = volume(4.75e-3);
  double vc = 0.0, vf = 0.0;
  for (double x : d) {
    (x > split ? vc : vf) += volume(x);
    ASSERT_LE(std::abs(vc - ratio * vf), std::max(v_coarse_max, ratio * v_fine_max) + 1e-18);
  }
  // Only a few dozen coarse particles here: the ratio is as close as one coarse particle allows.
  EXPECT_NEAR(vc / vf, ratio, v_coarse_max / vf);
}

TEST(GradingCut, ACutOffThatRemovesEverythingIsRefused) {
  const Grading g = *named_grading("fu2003_table1_coarse");
  EXPECT_THROW(cut_grading(g, 2 * 0.0254, std::nullopt, "particles.coarse.d_min"), InputError);
  try {
    cut_grading(g, 0.5 * 0.0254, 0.4 * 0.0254, "particles.coarse");
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("leave nothing"), std::string::npos);
  }
}

TEST(GradingReport, ComparesTheGeneratedCurveWithTheTarget) {
  const GradingCut cut = cut_grading(*named_grading("astm_c33_fine_mid"), 0.3e-3, std::nullopt, "test");
  Rng rng(10, 1);
  const auto d = sample_diameters(GradingSampler(cut, SamplingMode::Mass), {50000, {}}, rng);
  const GradingReport r = report_generated(d, cut);
  EXPECT_EQ(r.count, 50000u);
  EXPECT_GE(r.d_min, 0.3e-3);
  EXPECT_LE(r.d_max, 9.5e-3);
  EXPECT_LT(r.d10, r.d50);
  EXPECT_LT(r.d50, r.d90);
  EXPECT_LT(r.largest_deviation, 5.0);  // percentage points: a few heavy 9.5 mm grains carry the top
  EXPECT_EQ(r.rows.size(), cut.grading.sieves.size());
  EXPECT_GT(r.fineness_modulus, 2.0);
  EXPECT_NEAR(cut.cut_below, 0.175, 1e-12);  // #50 (0.300 mm) passes 17.5 % at mid-band
}

}  // namespace
}  // namespace aggpack
