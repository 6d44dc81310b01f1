// fit_rigid_pose against poses made on purpose: a random turn and shift recovered from exact
// positions, a dumbbell's axis (its turn about that axis is free), and a miss reported.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "aggpack/core/quaternion.hpp"
#include "aggpack/core/rigid_fit.hpp"
#include "aggpack/core/rng.hpp"

namespace {

using aggpack::Quaternion;
using aggpack::Vec3;

double rotation_distance(const Quaternion& a, const Quaternion& b) {  // 0 for the same rotation
  const double d = std::abs(a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z);
  return 1.0 - std::min(1.0, d);
}

TEST(RigidFit, RecoversARandomPoseOfManyMembersToRounding) {
  aggpack::Rng rng = aggpack::make_rng(11, aggpack::RngPurpose::Shapes);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<Vec3> offsets, positions;
    const int members = 3 + trial % 6;
    for (int k = 0; k < members; ++k)
      offsets.push_back({rng.uniform(-0.01, 0.01), rng.uniform(-0.01, 0.01), rng.uniform(-0.01, 0.01)});
    const Quaternion q = aggpack::random_orientation(rng);
    const Vec3 centre{rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(0, 1)};
    for (const Vec3& o : offsets) positions.push_back(centre + aggpack::rotate(q, o));
    const aggpack::RigidPose pose = aggpack::fit_rigid_pose(offsets, positions);
    EXPECT_LT(rotation_distance(pose.orientation, q), 1e-13) << trial;
    EXPECT_LT(aggpack::norm(pose.centre - centre), 1e-14) << trial;
    EXPECT_LT(pose.largest_miss, 1e-15) << trial;
  }
}

TEST(RigidFit, ADumbbellsAxisIsFoundWhateverItsTurnAboutIt) {
  const std::vector<Vec3> offsets{{-0.003, 0, 0}, {0.006, 0, 0}};
  const Quaternion q = aggpack::axis_angle(Vec3{1, 2, 3} * (1.0 / std::sqrt(14.0)), 0.7);
  const Vec3 centre{0.1, 0.2, 0.3};
  std::vector<Vec3> positions;
  for (const Vec3& o : offsets) positions.push_back(centre + aggpack::rotate(q, o));
  const aggpack::RigidPose pose = aggpack::fit_rigid_pose(offsets, positions);
  EXPECT_LT(pose.largest_miss, 1e-16);
  const Vec3 axis = aggpack::rotate(pose.orientation, {1, 0, 0}), expected = aggpack::rotate(q, {1, 0, 0});
  EXPECT_LT(aggpack::norm(axis - expected), 1e-14);
  EXPECT_LT(aggpack::norm(pose.centre - centre), 1e-16);
}

TEST(RigidFit, SaysHowFarMembersAreFromARigidBody) {
  const std::vector<Vec3> offsets{{-0.01, 0, 0}, {0.01, 0, 0}, {0, 0.01, 0}};
  std::vector<Vec3> positions{{-0.01, 0, 0}, {0.01, 0, 0}, {0, 0.013, 0}};  // the third moved 3 mm
  const aggpack::RigidPose pose = aggpack::fit_rigid_pose(offsets, positions);
  EXPECT_GT(pose.largest_miss, 1e-3);
  EXPECT_LT(pose.largest_miss, 3e-3);
  EXPECT_THROW((void)aggpack::fit_rigid_pose(offsets, std::span<const Vec3>(positions).first(2)), std::invalid_argument);
}

}  // namespace
