#include "aggpack/core/rng.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace aggpack {
namespace {

TEST(Rng, SameSeedAndPurposeGiveTheSameStream) {
  Rng a = make_rng(42, RngPurpose::Deposition), b = make_rng(42, RngPurpose::Deposition);
  for (int i = 0; i < 1000; ++i) ASSERT_EQ(a.next_u64(), b.next_u64());
}

TEST(Rng, PurposesAndSeedsGiveDifferentStreams) {
  Rng a = make_rng(42, RngPurpose::Deposition), b = make_rng(42, RngPurpose::Sizes), c = make_rng(43, RngPurpose::Deposition);
  int same_ab = 0, same_ac = 0;
  for (int i = 0; i < 100; ++i) {
    const auto x = a.next_u64();
    same_ab += x == b.next_u64();
    same_ac += x == c.next_u64();
  }
  EXPECT_EQ(same_ab, 0);
  EXPECT_EQ(same_ac, 0);
}

TEST(Rng, UniformAndBelowStayInRangeAndLookUniform) {
  Rng r = make_rng(1, RngPurpose::Analysis);
  std::vector<int> bins(10, 0);
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const double u = r.uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    const auto k = r.below(10);
    ASSERT_LT(k, 10u);
    ++bins[k];
  }
  for (int count : bins) EXPECT_NEAR(count, n / 10, 5 * std::sqrt(n * 0.1 * 0.9));  // 5 sigma
}

}  // namespace
}  // namespace aggpack
