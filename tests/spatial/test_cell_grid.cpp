#include "aggpack/spatial/cell_grid.hpp"

#include <gtest/gtest.h>

#include <random>
#include <set>

namespace aggpack {
namespace {

// The grid's candidates must include every neighbour the brute force finds, each once.
void check_against_brute_force(bool periodic, std::uint64_t seed) {
  std::mt19937_64 gen(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Container c = Container::square(3.0, 2.0, periodic);
  std::vector<Vec3> points;
  std::vector<double> radii;
  for (int i = 0; i < 1500; ++i) {
    points.push_back({3.0 * u(gen), 3.0 * u(gen), 2.0 * u(gen)});
    radii.push_back(0.01 + 0.09 * u(gen) * u(gen));  // 1:10 polydisperse
  }
  const double reach = 2 * 0.1;
  const CellGrid grid(points, c, reach);
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::multiset<std::uint32_t> candidates;
    grid.for_each_candidate(points[i], [&](std::uint32_t j) { candidates.insert(j); });
    for (std::uint32_t j : candidates) ASSERT_EQ(candidates.count(j), 1u) << "candidate visited twice";
    for (std::size_t j = 0; j < points.size(); ++j) {
      const double contact = radii[i] + radii[j];
      if (norm2(grid.separation(points[i], points[j])) <= contact * contact) {
        ASSERT_TRUE(candidates.count(static_cast<std::uint32_t>(j))) << i << " misses " << j;
      }
    }
  }
}

TEST(CellGrid, FindsEveryBruteForceNeighbourWithWalls) { check_against_brute_force(false, 1); }
TEST(CellGrid, FindsEveryBruteForceNeighbourWhenPeriodic) { check_against_brute_force(true, 2); }

TEST(CellGrid, PeriodicSeparationIsTheMinimumImage) {
  const std::vector<Vec3> pts{{0.1, 0.1, 0.0}, {2.9, 2.95, 0.0}};
  const CellGrid grid(pts, Container::square(3.0, 1.0, true), 0.5);
  const Vec3 d = grid.separation(pts[0], pts[1]);
  EXPECT_NEAR(d.x, -0.2, 1e-12);
  EXPECT_NEAR(d.y, -0.15, 1e-12);
}

}  // namespace
}  // namespace aggpack
