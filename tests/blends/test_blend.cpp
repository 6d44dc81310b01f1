// Blends by CPM at each material's betas: the lab route against its closed form for one class,
// the blend against CPM's own invariances, the densest blend and the sweep's parsing.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>

#include "aggpack/blends/blend.hpp"
#include "aggpack/blends/blend_check.hpp"
#include "aggpack/core/error.hpp"
#include "aggpack/labtests/standards.hpp"

namespace aggpack {
namespace {

// A material of one sieve fraction [lo, hi] mm with a C29 or C1252 number.
AggregateMaterial material(const std::string& lab, double lo_mm = 9.5, double hi_mm = 12.5) {
  const std::string text = fmt::format(R"(name = "m"
specific_gravity = 2.5
[grading]
sieves = [{{ opening = "{} mm", passing = 0 }}, {{ opening = "{} mm", passing = 100 }}]
{}
)",
                                       lo_mm, hi_mm, lab);
  return parse_material_file(text, "m.toml");
}

MaterialBetas one_class(const std::string& name, double d, double beta, double sd = 0.0, double density = 2500) {
  MaterialBetas b;
  b.material = name;
  b.particle_density_kg_m3 = density;
  b.classes.push_back({d / 1.1, d * 1.1, d, 1.0, beta, sd, {}});
  return b;
}

TEST(LabRoute, OneClassInvertsInClosedForm) {
  // One class: phi = beta (1 - (1 - k_w) Vp/V) / (1 + 1/K), so beta is known exactly.
  const AggregateMaterial m = material("[lab.c29]\nbulk_density = \"1500 kg/m3\"\nmethod = \"rodding\"");
  const MaterialBetas b = lab_route_betas(m);
  ASSERT_EQ(b.classes.size(), 1u);
  const double phi = 1.0 - voids_percent(m, 1500) / 100.0;
  const Measure measure = c29_measure(0.0125, "m.toml");
  const double d = std::sqrt(9.5e-3 * 12.5e-3);
  const double wall =
      1.0 - (1.0 - kContainerWallFactor) * container_perturbed_fraction(d, measure.diameter_m, measure.height_m);
  EXPECT_NEAR(b.classes[0].beta, phi * (1.0 + 1.0 / 4.5) / wall, 1e-9);
  EXPECT_EQ(b.route, BetaRoute::LabTest);
  EXPECT_NE(b.source.find("C29 rodding"), std::string::npos);
}

TEST(LabRoute, C1252MethodAInvertsOnTheStandardsSampleAndGivesTheSandsOwnClasses) {
  const AggregateMaterial m =
      material("[lab.c1252]\nvoids_percent = 42.0\nmethod = \"A\"", 0.075, 4.75);  // a sand, all in one fraction
  const MaterialBetas b = lab_route_betas(m);
  ASSERT_EQ(b.classes.size(), 1u);  // the material's own class, at the beta of method A's sample
  // Method A's sample at that beta, in the cylinder, at K 4.1, gives the lab's packing back.
  const Grading sample = grading_of_fractions(c1252_method_a_fractions(), "A");
  const ModelDistribution dist = grading_classes(sample, sample.smallest());
  std::vector<double> in_measure;
  for (const ModelClass& c : dist.classes)
    in_measure.push_back(
        b.classes[0].beta *
        (1.0 - (1.0 - kContainerWallFactor) * container_perturbed_fraction(c.diameter, kC1252Diameter, kC1252Height)));
  EXPECT_NEAR(cpm(dist, in_measure, 4.1).density, 0.58, 1e-9);
}

TEST(LabRoute, RefusesAMaterialWithoutALabNumberAndOneOutOfReach) {
  EXPECT_THROW(lab_route_betas(material("")), InputError);
  EXPECT_THROW(lab_route_betas(material("[lab.c29]\nbulk_density = \"2400 kg/m3\"\nmethod = \"rodding\"")), InputError);
}

TEST(ContainerWall, PerturbedFractionOfALayerHalfADiameterDeep) {
  EXPECT_DOUBLE_EQ(container_perturbed_fraction(0.0, 0.1, 0.1), 0.0);
  EXPECT_DOUBLE_EQ(container_perturbed_fraction(0.1, 0.1, 0.1), 1.0);
  // A layer d/2 at the side of a cylinder of radius R and at its floor: by the volumes.
  const double d = 0.01, D = 0.15, H = 0.16, R = D / 2;
  const double inner = std::numbers::pi * (R - d / 2) * (R - d / 2) * (H - d / 2);
  EXPECT_NEAR(container_perturbed_fraction(d, D, H), 1.0 - inner / (std::numbers::pi * R * R * H), 1e-12);
}

TEST(Blend, OneMaterialAloneIsCpmOfItsClasses) {
  MaterialBetas b = one_class("a", 0.01, 0.7);
  b.classes.push_back({0.002, 0.004, std::sqrt(0.002 * 0.004), 0.0, 0.65, 0.0, {}});
  b.classes[0].volume_fraction = 0.7;
  b.classes[1].volume_fraction = 0.3;
  const MaterialBetas one[] = {b};
  const double whole[] = {1.0};
  const BlendPoint p = predict_blend(one, whole, 4.5);
  const double betas[] = {0.7, 0.65};
  EXPECT_NEAR(p.packing, cpm(model_distribution(b), betas, 4.5).density, 1e-12);
}

TEST(Blend, TwoCopiesOfAMaterialPackAsTheMaterial) {
  const MaterialBetas a = one_class("a", 0.01, 0.72, 0.01);
  const MaterialBetas pair[] = {a, a};
  const double alone[] = {1.0, 0.0}, halves[] = {0.5, 0.5}, thirds[] = {1.0 / 3, 2.0 / 3};
  const double phi = predict_blend(pair, alone, 4.1).packing;
  EXPECT_NEAR(phi, 0.72 / (1 + 1 / 4.1), 1e-12);  // one class: beta / (1 + 1/K)
  EXPECT_NEAR(predict_blend(pair, halves, 4.1).packing, phi, 1e-12);
  EXPECT_NEAR(predict_blend(pair, thirds, 4.1).packing, phi, 1e-12);
  const BlendPoint p = predict_blend(pair, halves, 4.1);
  EXPECT_NEAR(p.packing_low, 0.71 / (1 + 1 / 4.1), 1e-12);
  EXPECT_NEAR(p.packing_high, 0.73 / (1 + 1 / 4.1), 1e-12);
}

TEST(Blend, LabUnitsFromTheParticleDensities) {
  const MaterialBetas pair[] = {one_class("stone", 0.01, 0.7, 0, 2700), one_class("sand", 0.001, 0.7, 0, 2500)};
  const double f[] = {0.6, 0.4};
  const BlendPoint p = predict_blend(pair, f, 4.5);
  EXPECT_NEAR(p.particle_density_kg_m3, 0.6 * 2700 + 0.4 * 2500, 1e-9);
  EXPECT_NEAR(p.bulk_density_kg_m3, p.packing * p.particle_density_kg_m3, 1e-9);
  EXPECT_NEAR(p.voids_percent, 100 * (1 - p.packing), 1e-12);
  EXPECT_NEAR(p.mass_fractions[0], 0.6 * 2700 / 2620, 1e-12);
  EXPECT_NEAR(p.mass_fractions[0] + p.mass_fractions[1], 1.0, 1e-12);
  // A fine material filling a coarse one's voids packs denser than either alone.
  const double alone[] = {1.0, 0.0};
  EXPECT_GT(p.packing, predict_blend(pair, alone, 4.5).packing + 0.05);
}

TEST(Blend, RefusesFractionsThatAreNotOneAMaterialSummingToOne) {
  const MaterialBetas pair[] = {one_class("a", 0.01, 0.7), one_class("b", 0.001, 0.7)};
  const double three[] = {0.3, 0.3, 0.4}, short_sum[] = {0.5, 0.4}, negative[] = {1.2, -0.2};
  EXPECT_THROW(predict_blend(pair, std::span<const double>(three, 3), 4.5), InputError);
  EXPECT_THROW(predict_blend(pair, short_sum, 4.5), InputError);
  EXPECT_THROW(predict_blend(pair, negative, 4.5), InputError);
  const double pc[] = {20.0};
  const MaterialBetas triple[] = {pair[0], pair[1], pair[1]};
  EXPECT_THROW(sweep_binary(triple, pc, 4.5), InputError);
  const double over[] = {120.0};
  EXPECT_THROW(sweep_binary(pair, over, 4.5), InputError);
}

TEST(Blend, DensestAndItsBands) {
  std::vector<BlendPoint> curve(5);
  const double packing[] = {0.70, 0.718, 0.72, 0.716, 0.70};
  for (std::size_t i = 0; i < 5; ++i) {
    curve[i].packing = packing[i];
    curve[i].packing_low = packing[i] - 0.003;
    curve[i].packing_high = packing[i] + 0.003;
  }
  const DensestBlend d = densest(curve);
  EXPECT_EQ(d.index, 2u);
  EXPECT_EQ(d.spread_first, 1u);  // 0.721 reaches 0.717; 0.703 does not
  EXPECT_EQ(d.spread_last, 3u);   // 0.719 reaches it
  EXPECT_EQ(d.plateau_first, 1u);
  EXPECT_EQ(d.plateau_last, 3u);
}

TEST(Blend, ParsesASweep) {
  EXPECT_EQ(parse_sweep("20:60:1", "--sweep").size(), 41u);
  const std::vector<double> s = parse_sweep("10:30:7.5", "--sweep");
  ASSERT_EQ(s.size(), 3u);
  EXPECT_DOUBLE_EQ(s[2], 25.0);
  for (const char* bad : {"20:60", "a:60:1", "20:60:0", "60:20:1", "0:100:0.001", "20:60:nan"})
    EXPECT_THROW(parse_sweep(bad, "--sweep"), InputError) << bad;
}

TEST(Blend, CutBelowKeepsTheLogShareAboveTheCut) {
  MaterialBetas sand = one_class("sand", 0.001, 0.7);
  sand.classes = {{0.00236, 0.00475, std::sqrt(0.00236 * 0.00475), 0.2, 0.7, 0.0, {}},
                  {0.00118, 0.00236, std::sqrt(0.00118 * 0.00236), 0.3, 0.68, 0.0, {}},
                  {0.0006, 0.00118, std::sqrt(0.0006 * 0.00118), 0.5, 0.66, 0.0, {}}};
  const MaterialBetas cut = cut_below(sand, 0.00166);  // within the second class
  ASSERT_EQ(cut.classes.size(), 2u);
  const double kept = 0.3 * std::log(0.00236 / 0.00166) / std::log(2.0);
  EXPECT_NEAR(cut.classes[0].volume_fraction, 0.2 / (0.2 + kept), 1e-12);
  EXPECT_DOUBLE_EQ(cut.classes[1].d_lo, 0.00166);
  EXPECT_DOUBLE_EQ(cut.classes[1].beta, 0.68);
  EXPECT_THROW(cut_below(sand, 0.005), InputError);
}

TEST(Blend, InteractionExponentsAreFittedBackFromBlendsTheyMade) {
  // Blends "simulated" by CPM itself at exponents (0.5, 2.5): the fit finds exponents that give
  // them back, where de Larrard's miss them.
  BlendCheck check;
  check.coarse = one_class("coarse", 0.011, 0.78, 0.001);
  check.fine = one_class("fine", 0.0034, 0.79, 0.001);
  check.process = {"poured", 4.1};
  const MaterialBetas pair[] = {check.coarse, check.fine};
  const CpmInteraction truth{0.5, 2.5};
  for (const double pc : {20.0, 30.0, 40.0, 50.0, 60.0}) {
    BlendCheckPoint p;
    p.percent = pc;
    const double f[] = {1 - pc / 100, pc / 100};
    p.simulated.mean = predict_blend(pair, f, 4.1, truth).packing;
    check.points.push_back(p);
  }
  const BlendCheck checks[] = {check};
  EXPECT_GT(largest_difference(checks, CpmInteraction{}), 0.005);
  const CpmInteraction fitted = fit_interaction(checks);
  EXPECT_LT(largest_difference(checks, fitted), 2e-4);
  EXPECT_THROW(fit_interaction(std::span<const BlendCheck>{}), InputError);
  // The default exponents are de Larrard's.
  EXPECT_DOUBLE_EQ(cpm_loosening(0.3, 1.0), std::sqrt(1 - std::pow(0.7, 1.02)));
  EXPECT_DOUBLE_EQ(cpm_wall(0.3, 1.0), 1 - std::pow(0.7, 1.5));
}

}  // namespace
}  // namespace aggpack
