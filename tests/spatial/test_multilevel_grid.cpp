#include "aggpack/spatial/multilevel_grid.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <set>

namespace aggpack {
namespace {

struct Spheres {
  std::vector<Vec3> centres;
  std::vector<double> radii;
};

// Random spheres with radii spread over `size_ratio` (log-uniform), some slightly outside
// the container (a file's packing may be), in a container of side `side`.
Spheres random_spheres(std::size_t n, double side, double size_ratio, std::uint64_t seed) {
  std::mt19937_64 gen(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Spheres s;
  const double r_max = 0.1;
  for (std::size_t i = 0; i < n; ++i) {
    s.centres.push_back({side * (1.04 * u(gen) - 0.02), side * (1.04 * u(gen) - 0.02), 2.0 * u(gen)});
    s.radii.push_back(r_max * std::pow(size_ratio, -u(gen)));
  }
  return s;
}

MultilevelGrid filled_grid(const Spheres& s, const Container& c) {
  MultilevelGrid grid(c, s.radii, c.bounds.volume());
  for (std::size_t i = 0; i < s.radii.size(); ++i) grid.insert(static_cast<std::uint32_t>(i), s.centres[i], s.radii[i]);
  return grid;
}

// After the exact distance test, the grid's neighbours are exactly the brute-force set,
// and no candidate is visited twice.
void check_near_against_brute_force(bool periodic, double side, double size_ratio, std::uint64_t seed) {
  const Container c = Container::square(side, 2.0, periodic);
  Spheres s = random_spheres(1500, side, size_ratio, seed);
  if (periodic) {
    for (Vec3& p : s.centres) p.x = std::fmod(p.x + side, side), p.y = std::fmod(p.y + side, side);
  }
  const MultilevelGrid grid = filled_grid(s, c);
  if (size_ratio > 4) {
    EXPECT_GT(grid.level_count(), 2u);
  }
  std::mt19937_64 gen(seed + 100);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int q = 0; q < 400; ++q) {
    const Vec3 p{side * u(gen), side * u(gen), 2.0 * u(gen)};
    const double reach = 0.25 * u(gen);
    std::multiset<std::uint32_t> found;
    grid.for_each_near(p, reach, [&](std::uint32_t k) {
      if (norm(grid.separation(p, s.centres[k])) <= reach + s.radii[k]) found.insert(k);
    });
    std::multiset<std::uint32_t> expected;
    for (std::size_t k = 0; k < s.radii.size(); ++k)
      if (norm(grid.separation(p, s.centres[k])) <= reach + s.radii[k]) expected.insert(static_cast<std::uint32_t>(k));
    ASSERT_EQ(found, expected) << "query " << q;
  }
}

TEST(MultilevelGrid, NeighboursMatchBruteForceWithWalls) { check_near_against_brute_force(false, 3.0, 10.0, 1); }
TEST(MultilevelGrid, NeighboursMatchBruteForceWithWideSizeRange) {
  check_near_against_brute_force(false, 3.0, 30.0, 2);
}
TEST(MultilevelGrid, NeighboursMatchBruteForceWhenPeriodic) { check_near_against_brute_force(true, 3.0, 10.0, 3); }
TEST(MultilevelGrid, NeighboursMatchBruteForceInANarrowPeriodicBox) {
  check_near_against_brute_force(true, 0.45, 4.0, 4);  // fewer than three cells across
}

// Every pair of spheres within `skin` of touching, found by querying from each sphere the
// levels of its size and larger only (keeping a same-level pair from its lower id): each pair
// exactly once, and exactly the brute-force set.
void check_pairs_from_the_smaller_sphere(bool periodic, double size_ratio, std::uint64_t seed) {
  const double side = 3.0, skin = 0.01;
  const Container c = Container::square(side, 2.0, periodic);
  Spheres s = random_spheres(1500, side, size_ratio, seed);
  if (periodic)
    for (Vec3& p : s.centres) p.x = std::fmod(p.x + side, side), p.y = std::fmod(p.y + side, side);
  const MultilevelGrid grid = filled_grid(s, c);
  const auto near = [&](std::size_t i, std::size_t j) {
    return norm(grid.separation(s.centres[i], s.centres[j])) < s.radii[i] + s.radii[j] + skin;
  };
  std::multiset<std::pair<std::uint32_t, std::uint32_t>> found, expected;
  std::size_t cross_level = 0;
  for (std::uint32_t i = 0; i < s.radii.size(); ++i)
    grid.for_each_near_larger(s.centres[i], s.radii[i], s.radii[i] + skin, [&](std::uint32_t j, bool same_level) {
      if (j == i || (same_level && j < i) || !near(i, j)) return;
      cross_level += same_level ? 0 : 1;
      EXPECT_TRUE(same_level || s.radii[j] > 0.5 * s.radii[i]) << "a smaller sphere's level was searched";
      found.emplace(std::min(i, j), std::max(i, j));
    });
  for (std::uint32_t i = 0; i < s.radii.size(); ++i)
    for (std::uint32_t j = i + 1; j < s.radii.size(); ++j)
      if (near(i, j)) expected.emplace(i, j);
  EXPECT_GT(cross_level, 50u);  // the test sees pairs across levels, not only within one
  EXPECT_EQ(found, expected);
}

TEST(MultilevelGrid, PairsFromTheSmallerSphereMatchBruteForce) { check_pairs_from_the_smaller_sphere(false, 30.0, 6); }
TEST(MultilevelGrid, PairsFromTheSmallerSphereMatchBruteForceWhenPeriodic) {
  check_pairs_from_the_smaller_sphere(true, 10.0, 7);
}

// A falling sphere must see every sphere under its disc whose centre is below it.
TEST(MultilevelGrid, ColumnScanSeesEverySphereBelow) {
  for (bool periodic : {false, true}) {
    const double side = 3.0;
    const Container c = Container::square(side, 2.0, periodic);
    Spheres s = random_spheres(2000, side, 20.0, 5);
    if (periodic) {
      for (Vec3& p : s.centres) p.x = std::fmod(p.x + side, side), p.y = std::fmod(p.y + side, side);
    }
    const MultilevelGrid grid = filled_grid(s, c);
    std::mt19937_64 gen(6);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int q = 0; q < 300; ++q) {
      const Vec3 p{side * u(gen), side * u(gen), 2.5 * u(gen)};
      const double r = 0.1 * u(gen) + 0.005;
      std::set<std::uint32_t> found;
      grid.for_each_below(p, r, [&](std::uint32_t k) { found.insert(k); },
                          [] { return -std::numeric_limits<double>::infinity(); });
      for (std::size_t k = 0; k < s.radii.size(); ++k) {
        Vec3 d = grid.separation(p, s.centres[k]);
        if (std::hypot(d.x, d.y) < r + s.radii[k] && s.centres[k].z <= p.z) {
          ASSERT_TRUE(found.count(static_cast<std::uint32_t>(k))) << "query " << q << " misses " << k;
        }
      }
    }
  }
}

TEST(MultilevelGrid, ColumnScanStopsBelowTheStopHeight) {
  const Container c = Container::square(1.0, 10.0, false);
  const std::vector<double> radii(100, 0.05);
  MultilevelGrid grid(c, radii, c.bounds.volume());
  for (std::uint32_t i = 0; i < 100; ++i) grid.insert(i, {0.5, 0.5, 0.05 + 0.1 * i}, 0.05);  // a column
  std::size_t visited = 0;
  grid.for_each_below({0.5, 0.5, 20.0}, 0.05, [&](std::uint32_t) { ++visited; }, [] { return 9.9; });
  EXPECT_LT(visited, 8u);  // only the top of the column can reach 9.9
  EXPECT_GT(visited, 0u);
}

TEST(MultilevelGrid, PeriodicSeparationIsTheMinimumImage) {
  const std::vector<double> radii{0.1};
  const MultilevelGrid grid(Container::square(3.0, 1.0, true), radii, 9.0);
  const Vec3 d = grid.separation({0.1, 0.1, 0.0}, {2.9, 2.95, 0.0});
  EXPECT_NEAR(d.x, -0.2, 1e-12);
  EXPECT_NEAR(d.y, -0.15, 1e-12);
}

TEST(MultilevelGrid, SparseLevelsGetCoarseCells) {
  // A few tiny spheres in a large bed must not allocate a fine grid over the whole bed.
  const Container c = Container::square(10.0, 10.0, false);
  std::vector<double> radii(1000, 0.5);
  radii.push_back(0.001);
  MultilevelGrid grid(c, radii, 1000.0);
  grid.insert(0, {5, 5, 9.5}, 0.5);
  grid.insert(1, {5, 5, 9.5}, 0.001);
  EXPECT_LT(grid.memory_bytes(), 100'000u);
}

}  // namespace
}  // namespace aggpack
