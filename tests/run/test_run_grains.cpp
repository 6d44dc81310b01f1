// grain_sieve_intervals: each grain's I placed between the sieves of its component's grading.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "aggpack/run/run_grains.hpp"

namespace aggpack {
namespace {

TEST(GrainSieveIntervals, AGrainLiesBetweenTheSieveItPassesAndTheOneItIsRetainedOn) {
  ParticleStore bed;
  const std::vector<Vec3> centres{{-0.001, 0.0, 0.0}, {0.001, 0.0, 0.0}};
  const std::vector<double> radii{0.0015, 0.0015};
  const RigidBodyShape shape{centres, radii, 2e-8, {1e-10, 2e-10, 2e-10}, 1.0, 0};
  for (int k = 0; k < 4; ++k) bed.add_body({0.01 * k, 0.0, 0.0}, {}, shape, 2650.0);
  // Widths: inside an interval, on a sieve (it passes that one), below and above the curve.
  std::vector<GrainMeasure> measures(4);
  measures[0].width = 0.006;
  measures[1].width = 0.0095 * (1.0 + 1e-13);  // the grading's 9.5 mm, to a measure's rounding
  measures[2].width = 0.003;
  measures[3].width = 0.02;
  SizesReport sizes;
  sizes.method = "grading";
  sizes.components.resize(1);
  sizes.components[0].cut.grading.sieves = {{"#4", 0.00475, 0.0}, {"3/8in", 0.0095, 60.0}, {"1/2in", 0.0125, 100.0}};
  const std::vector<SieveInterval> got = grain_sieve_intervals(bed, measures, {0}, sizes);
  ASSERT_EQ(got.size(), 4u);
  EXPECT_EQ(got[0].retained, 0.00475);
  EXPECT_EQ(got[0].passing, 0.0095);
  EXPECT_EQ(got[1].retained, 0.00475);
  EXPECT_EQ(got[1].passing, 0.0095);
  for (int k : {2, 3}) EXPECT_TRUE(std::isnan(got[k].retained) && std::isnan(got[k].passing)) << k;
  sizes.method = "classes";  // size classes have no sieves
  EXPECT_TRUE(std::isnan(grain_sieve_intervals(bed, measures, {0}, sizes)[0].passing));
}

}  // namespace
}  // namespace aggpack
