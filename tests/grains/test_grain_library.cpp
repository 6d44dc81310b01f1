// A component's grain library: templates drawn from its proportions (or fitted to a lab's
// flakiness), normalised to reach 1 for the store, measured back as a lab would.
#include "aggpack/grains/grain_library.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "aggpack/core/error.hpp"
#include "aggpack/core/rng.hpp"

namespace aggpack {
namespace {

std::vector<double> coarse_sizes() {
  std::vector<double> sizes;
  for (double mm = 5.0; mm < 19.0; mm += 0.5) sizes.push_back(1e-3 * mm);
  return sizes;
}

TEST(GrainLibrary, TemplatesAreOfReachOneAndMeasureTheirProportions) {
  GrainShapeSpec spec;
  spec.spheres = 6;
  spec.templates = 4;
  spec.proportions = {0.7, 0.1, 0.6, 0.1};
  const GrainLibrary library = make_grain_library(spec, coarse_sizes(), 3);
  ASSERT_EQ(library.grains.size(), 4u);
  for (const LibraryGrain& g : library.grains) {
    EXPECT_NEAR(g.shape().reach(), 1.0, 1e-12);
    EXPECT_EQ(g.unit_radii.size(), 6u);
    EXPECT_NEAR(g.grain.dimensions.length, 1.0, 1e-9);
    EXPECT_NEAR(g.grain.dimensions.width, 0.7, 0.12);
    // Scaled to its width: I is that width, L and S and the mass in proportion.
    const GrainMeasure m = measure_grain(g, 0.01, 2650.0);
    EXPECT_DOUBLE_EQ(m.width, 0.01);
    EXPECT_NEAR(m.length * g.grain.dimensions.width, 0.01, 1e-15);
    EXPECT_NEAR(m.mass, 2650.0 * g.unit_volume * std::pow(g.reach_for_width(0.01), 3), 1e-12 * m.mass);
  }
  EXPECT_FALSE(library.fit.has_value());
}

// "My crushed stone: flakiness 18 %": angular grains fitted to it; a population of grains of
// the component's sizes, each a template at random, measures about that.
TEST(GrainLibrary, AnAngularLibraryFittedToAFlakinessIndexReproducesIt) {
  GrainShapeSpec spec;
  spec.family = GrainFamily::Angular;
  spec.spheres = 6;
  spec.corners = 10;
  spec.templates = 16;
  spec.proportions = {0.7, 0.15, 0.7, 0.15};
  spec.target = ShapeTarget{ShapeMeasure::FlakinessIndex, 18.0, 0.0};
  const std::vector<double> sizes = coarse_sizes();
  const GrainLibrary library = make_grain_library(spec, sizes, 11);
  ASSERT_TRUE(library.fit.has_value());
  EXPECT_LT(library.distribution.flatness_mean, 0.7);
  Rng pick(4, 4);
  std::vector<GrainMeasure> grains;
  for (int k = 0; k < 4000; ++k)
    grains.push_back(measure_grain(library.grains[pick.below(library.grains.size())],
                                   sizes[static_cast<std::size_t>(k) % sizes.size()], 2650.0));
  const double measured = *measured_percent(*spec.target, grains);
  std::printf("flakiness of the generated grains: %.1f %% (target 18 %%, fitted flatness mean %.3f)\n", measured,
              library.distribution.flatness_mean);
  EXPECT_NEAR(library.fit->achieved_percent, 18.0, 1.0);  // every template at every size
  EXPECT_NEAR(measured, 18.0, 3.0);                       // 4000 grains drawn at random: their scatter
}

TEST(GrainLibrary, BadSpecsAreRefused) {
  GrainShapeSpec spec;
  spec.spheres = 0;
  EXPECT_THROW((void)make_grain_library(spec, coarse_sizes(), 1), InputError);
  spec.spheres = 4;
  spec.family = GrainFamily::Angular;
  spec.corners = 3;
  EXPECT_THROW((void)make_grain_library(spec, coarse_sizes(), 1), InputError);
  spec.corners = 12;
  spec.target = ShapeTarget{ShapeMeasure::FlakinessIndex, 18.0, 0.0};
  const std::vector<double> sand{1e-3, 2e-3};
  EXPECT_THROW((void)make_grain_library(spec, sand, 1), InputError);
}

}  // namespace
}  // namespace aggpack
