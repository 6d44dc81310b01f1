#include <cmath>

#include <gtest/gtest.h>

#include "aggpack/core/error.hpp"
#include "aggpack/studies/campaign.hpp"
#include "aggpack/studies/sweep.hpp"

namespace aggpack {
namespace {

TEST(SeedStatistics, MeanAndSampleStandardDeviation) {
  const SeedStatistics s = seed_statistics({1.0, 2.0, 3.0, 4.0});
  EXPECT_EQ(s.count, 4u);
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  EXPECT_NEAR(s.sd, std::sqrt(5.0 / 3.0), 1e-15);  // sum of squares 5, n - 1 = 3
}

TEST(SeedStatistics, MissingValuesAreLeftOutAndOneValueHasNoSd) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const SeedStatistics s = seed_statistics({nan, 0.6, nan});
  EXPECT_EQ(s.count, 1u);
  EXPECT_DOUBLE_EQ(s.mean, 0.6);
  EXPECT_TRUE(std::isnan(s.sd));
  EXPECT_EQ(seed_statistics({}).count, 0u);
  EXPECT_TRUE(std::isnan(seed_statistics({}).mean));
}

TEST(FaPoints, RangesAndLists) {
  EXPECT_EQ(parse_fa_points("25:45:5"), (std::vector<double>{25, 30, 35, 40, 45}));
  EXPECT_EQ(parse_fa_points("20:50:15"), (std::vector<double>{20, 35, 50}));
  EXPECT_EQ(parse_fa_points("29,35.5,43"), (std::vector<double>{29, 35.5, 43}));
  EXPECT_EQ(parse_fa_points("40"), (std::vector<double>{40}));
  for (const char* bad : {"", "30:x:5", "30:20:5", "0,40", "40,100", "30:40", "30,,40", "35%", "1:99:0.1"})
    EXPECT_THROW(parse_fa_points(bad), InputError) << bad;
}

}  // namespace
}  // namespace aggpack
