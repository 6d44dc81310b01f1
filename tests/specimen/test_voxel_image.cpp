// The voxel image of a specimen against the sphere geometry: its aggregate fraction converges to
// the exact one as the voxel shrinks, each sampled voxel's phase is the one its centre is in, and
// the VTK and Abaqus files hold that image.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstring>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "aggpack/core/error.hpp"
#include "aggpack/specimen/voxel_image.hpp"
#include "specimen_beds.hpp"

namespace aggpack {
namespace {

const Box kBox{{0.005, 0.005, 0.005}, {0.035, 0.035, 0.035}};

Specimen bed_specimen(double itz = 0.0, SpecimenRegion region = kBox) {
  return cut_specimen(testing::random_spheres(120, 0.04, 0.002, 0.005, 7), {region, 0.0, itz});
}

TEST(VoxelImage, TheAggregateFractionConvergesToTheExactOneAsTheVoxelShrinks) {
  const Specimen s = bed_specimen();
  const double exact = s.aggregate_fraction();
  ASSERT_GT(exact, 0.15);
  std::vector<double> errors;
  for (const double h : {0.0016, 0.0008, 0.0004, 0.0002}) {
    const VoxelImage image = voxelize(s, h, 1e8);
    EXPECT_EQ(image.inside(), image.phase.size());
    errors.push_back(std::abs(image.fraction(image.aggregate) - exact));
  }
  // Roughly linear in the voxel size: each halving at least takes the error below the coarsest's
  // scaled by the size (with room for the sampling's scatter), and the finest is within 0.2 %.
  for (std::size_t n = 1; n < errors.size(); ++n)
    EXPECT_LE(errors[n], 1.5 * errors[0] / std::pow(2.0, static_cast<double>(n)) + 1e-4) << n;
  EXPECT_LT(errors.back(), 0.002 * exact);
  EXPECT_LT(errors.back(), errors.front());
}

TEST(VoxelImage, EachVoxelIsThePhaseItsCentreIsIn) {
  const Specimen s = bed_specimen(0.0005, VerticalCylinder{0.02, 0.02, 0.005, 0.035, 0.013});
  const VoxelImage image = voxelize(s, 0.0004, 1e8);
  const VoxelGrid& g = image.grid;
  std::mt19937_64 rng(3);
  std::set<std::uint8_t> seen;
  for (int n = 0; n < 20000; ++n) {
    const std::size_t i = rng() % g.count[0], j = rng() % g.count[1], k = rng() % g.count[2];
    const Vec3 p = g.centre(i, j, k);
    std::uint8_t expected = 0;
    if (!region_contains(s.region, p)) {
      expected = 255;
    } else {
      for (const MemberSphere& sphere : s.spheres) {
        const Vec3 d = p - sphere.centre;
        const double distance = std::sqrt(dot(d, d));
        if (distance <= sphere.radius) expected = 1;
        else if (expected == 0 && distance <= sphere.radius + s.itz_thickness) expected = 2;
      }
    }
    ASSERT_EQ(image.phase[i + g.count[0] * (j + g.count[1] * k)], expected) << i << " " << j << " " << k;
    seen.insert(expected);
  }
  EXPECT_EQ(seen, (std::set<std::uint8_t>{0, 1, 2, 255}));
  // The cylinder's share of its bounding box, pi/4, to the voxels' resolution.
  EXPECT_NEAR(static_cast<double>(image.inside()) / static_cast<double>(image.phase.size()), std::numbers::pi / 4.0,
              0.01);
}

TEST(VoxelImage, IsTheSameBytesForAnyThreadCount) {
  const Specimen s = bed_specimen(0.0005, VerticalCylinder{0.02, 0.02, 0.005, 0.035, 0.013});
  omp_set_num_threads(1);
  const VoxelImage one = voxelize(s, 0.0003, 1e8);
  omp_set_num_threads(2);
  const VoxelImage two = voxelize(s, 0.0003, 1e8);
  EXPECT_EQ(one.phase, two.phase);
}

TEST(VoxelImage, TooManyVoxelsOrNoSizeAreRefused) {
  const Specimen s = bed_specimen();
  EXPECT_THROW((void)voxelize(s, 1e-5, 1e8), InputError);  // 2.7e10 voxels
  EXPECT_THROW((void)voxelize(s, 0.0, 1e8), InputError);
  EXPECT_THROW((void)voxelize(s, -1.0, 1e8), InputError);
  EXPECT_THROW((void)voxelize(s, 0.001, std::nan("")), InputError);  // a limit that is no number refuses
}

TEST(VoxelImage, TheVtiFileHoldsTheImage) {
  const VoxelImage image = voxelize(bed_specimen(0.0005), 0.001, 1e8);
  std::ostringstream out;
  write_vti(out, image, "test -- provenance");
  const std::string text = out.str();
  EXPECT_NE(text.find("<!-- test -= provenance -->"), std::string::npos);
  EXPECT_NE(text.find("WholeExtent=\"0 30 0 30 0 30\""), std::string::npos);
  EXPECT_NE(text.find("Spacing=\"0.001"), std::string::npos);
  const std::size_t data = text.find("   _") + 4;
  std::uint64_t bytes = 0;
  std::memcpy(&bytes, text.data() + data, sizeof bytes);
  ASSERT_EQ(bytes, 27000u);
  EXPECT_EQ(std::memcmp(text.data() + data + 8, image.phase.data(), bytes), 0);
  EXPECT_EQ(text.substr(data + 8 + bytes), "\n  </AppendedData>\n</VTKFile>\n");
}

// The Abaqus file: its nodes and elements counted, each element's volume positive and one
// voxel's, the element sets partitioning the elements, one per phase, the aggregate's the image's.
TEST(VoxelImage, TheAbaqusFileIsAVoxelMeshWithOneSetPerPhase) {
  const VoxelImage image = voxelize(bed_specimen(0.0005, VerticalCylinder{0.02, 0.02, 0.01, 0.02, 0.01}), 0.001, 1e8);
  std::ostringstream out;
  write_abaqus_inp(out, image, "test");
  std::istringstream in(out.str());
  std::string line, section;
  std::vector<Vec3> nodes(1);
  std::size_t elements = 0;
  std::map<std::string, std::vector<long>> sets;
  while (std::getline(in, line)) {
    if (line.rfind("**", 0) == 0) continue;
    if (line[0] == '*') {
      section = line;
      continue;
    }
    std::vector<double> v;
    std::istringstream fields(line);
    for (std::string f; std::getline(fields, f, ',');) v.push_back(std::stod(f));
    if (section == "*Node") {
      ASSERT_EQ(v[0], static_cast<double>(nodes.size()));
      nodes.push_back({v[1], v[2], v[3]});
    } else if (section == "*Element, type=C3D8") {
      ASSERT_EQ(v.size(), 9u);
      ASSERT_EQ(v[0], static_cast<double>(++elements));
      const auto at = [&](int c) { return nodes.at(static_cast<std::size_t>(v[static_cast<std::size_t>(c)])); };
      const Vec3 e1 = at(2) - at(1), e2 = at(4) - at(1), e3 = at(5) - at(1);
      EXPECT_NEAR(dot(cross(e1, e2), e3), image.grid.voxel_volume(), 1e-12 * image.grid.voxel_volume());
    } else {
      for (const double e : v) sets[section].push_back(static_cast<long>(e));
    }
  }
  EXPECT_EQ(elements, image.inside());
  EXPECT_LT(elements, image.phase.size());  // the cylinder's corners are left out
  ASSERT_EQ(sets.size(), 3u);
  EXPECT_EQ(sets["*Elset, elset=AGGREGATE"].size(), image.aggregate);
  EXPECT_EQ(sets["*Elset, elset=MORTAR"].size(), image.mortar);
  EXPECT_EQ(sets["*Elset, elset=ITZ"].size(), image.itz);
  std::set<long> all;
  for (const auto& [name, members] : sets) all.insert(members.begin(), members.end());
  EXPECT_EQ(all.size(), elements);
  EXPECT_EQ(*all.begin(), 1);
  EXPECT_EQ(*all.rbegin(), static_cast<long>(elements));
}

}  // namespace
}  // namespace aggpack
