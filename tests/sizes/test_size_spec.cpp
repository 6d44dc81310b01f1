#include "aggpack/sizes/size_spec.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <numbers>

#include "aggpack/core/error.hpp"

namespace aggpack {
namespace {

double volume(double d) { return std::numbers::pi / 6 * d * d * d; }

TEST(SizeSpec, ClassesByCountAreGeneratedAndShuffledAsAPermutation) {
  SizeSpec spec;
  spec.classes = {{0.5, 2000, {}}, {1.0, 1000, {}}};
  Rng rng = make_rng(3, RngPurpose::Sizes);
  auto d = generate_diameters(spec, rng);
  ASSERT_EQ(d.size(), 3000u);
  EXPECT_EQ(std::count(d.begin(), d.end(), 0.5), 2000);
  EXPECT_FALSE(std::is_sorted(d.begin(), d.end()));
  spec.order = SizeOrder::AsListed;
  d = generate_diameters(spec, rng);
  EXPECT_TRUE(std::is_sorted(d.begin(), d.end()));
}

TEST(SizeSpec, VolumeFractionsAreMetWithinOneParticle) {
  SizeSpec spec;
  spec.classes = {{0.5, {}, 0.3}, {1.0, {}, 0.7}};
  spec.total_count = 5000;
  const auto counts = class_counts(spec);
  EXPECT_EQ(counts[0] + counts[1], 5000u);
  const double v0 = counts[0] * volume(0.5), v1 = counts[1] * volume(1.0);
  EXPECT_NEAR(v0 / (v0 + v1), 0.3, volume(1.0) / (v0 + v1));
  spec.total_count.reset();
  spec.solid_volume = 100.0;
  const auto by_volume = class_counts(spec);
  EXPECT_NEAR(by_volume[1] * volume(1.0), 70.0, volume(1.0));
  EXPECT_NEAR(by_volume[0] * volume(0.5), 30.0, volume(0.5));
}

TEST(SizeSpec, InconsistentSpecsAreRefused) {
  SizeSpec spec;
  spec.classes = {{0.5, {}, 0.3}, {1.0, {}, 0.6}};
  spec.total_count = 10;
  EXPECT_THROW(class_counts(spec), InputError);  // fractions add to 0.9
  spec.classes[1].volume_fraction = 0.7;
  spec.total_count.reset();
  EXPECT_THROW(class_counts(spec), InputError);  // no amount
}

}  // namespace
}  // namespace aggpack
