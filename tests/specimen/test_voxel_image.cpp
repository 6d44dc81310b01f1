// The voxel image of a specimen against the sphere geometry: its aggregate fraction converges to
// the exact one as the voxel shrinks, each sampled voxel's phase is the one its centre is in, and
// the VTK and Abaqus files hold that image.
#include <gtest/gtest.h>
#include <omp.h>
#include <zlib.h>

#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
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

// The image zlib-compressed as the .vtp is (VTK's layout: a UInt64 header of the blocks, then
// each block a zlib stream), the bytes decompressed the image's; far smaller than a byte a voxel.
TEST(VoxelImage, TheVtiFileHoldsTheImageCompressed) {
  const VoxelImage image = voxelize(bed_specimen(0.0005), 0.001, 1e8);
  std::ostringstream out;
  write_vti(out, image, "test -- provenance");
  const std::string text = out.str();
  EXPECT_NE(text.find("<!-- test -= provenance -->"), std::string::npos);
  EXPECT_NE(text.find("WholeExtent=\"0 30 0 30 0 30\""), std::string::npos);
  EXPECT_NE(text.find("Spacing=\"0.001"), std::string::npos);
  EXPECT_NE(text.find("compressor=\"vtkZLibDataCompressor\""), std::string::npos);
  const std::size_t data = text.find("   _") + 4;
  std::uint64_t header[3] = {};
  std::memcpy(header, text.data() + data, sizeof header);
  const std::uint64_t blocks = header[0], block_size = header[1], last = header[2];
  ASSERT_EQ(block_size, 32768u);
  ASSERT_EQ(blocks, 1u);  // 27 000 bytes
  ASSERT_EQ(last, 27000u);
  std::vector<std::uint64_t> sizes(blocks);
  std::memcpy(sizes.data(), text.data() + data + sizeof header, blocks * sizeof(std::uint64_t));
  const char* packed = text.data() + data + sizeof header + blocks * sizeof(std::uint64_t);
  std::vector<std::uint8_t> phase(27000);
  uLongf length = phase.size();
  ASSERT_EQ(uncompress(phase.data(), &length, reinterpret_cast<const Bytef*>(packed), sizes[0]), Z_OK);
  ASSERT_EQ(length, 27000u);
  EXPECT_EQ(phase, image.phase);
  EXPECT_LT(sizes[0], 27000u / 3);
  EXPECT_EQ(text.substr(static_cast<std::size_t>(packed - text.data()) + sizes[0]), "\n  </AppendedData>\n</VTKFile>\n");
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
  // A file to *INCLUDE: no heading of its own (a deck's second stops CalculiX and Abaqus).
  EXPECT_EQ(out.str().find("*Heading"), std::string::npos);
  // The bottom's and the top's nodes: those at z = z_lo and z_hi, and no other set of faces.
  ASSERT_TRUE(sets.contains("*Nset, nset=ZMIN") && sets.contains("*Nset, nset=ZMAX"));
  for (const auto& [name, z] : {std::pair{"*Nset, nset=ZMIN", 0.01}, std::pair{"*Nset, nset=ZMAX", 0.02}}) {
    EXPECT_GT(sets[name].size(), 100u) << name;
    for (const long n : sets[name]) ASSERT_NEAR(nodes.at(static_cast<std::size_t>(n)).z, z, 1e-12) << name;
    sets.erase(name);
  }
  EXPECT_FALSE(sets.contains("*Nset, nset=XMIN"));  // a cylinder has no x faces
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

// A box's file: the node sets of its six faces, each node on its plane and every node on a
// plane in its set; its header names the element sets it writes and no other (no ITZ here).
TEST(VoxelImage, TheAbaqusFileOfABoxHasItsSixFacesAndNamesOnlyItsSets) {
  const Box box{{0.01, 0.01, 0.01}, {0.02, 0.022, 0.024}};
  const VoxelImage image = voxelize(bed_specimen(0.0, box), 0.001, 1e8);
  std::ostringstream out;
  write_abaqus_inp(out, image, "test");
  const std::string text = out.str();
  EXPECT_EQ(text.find("*Heading"), std::string::npos);
  EXPECT_NE(text.find("** C3D8 voxels; element sets (one per phase): AGGREGATE, MORTAR\n"), std::string::npos) << text.substr(0, 400);
  EXPECT_EQ(text.find("ITZ"), std::string::npos);
  std::istringstream in(text);
  std::string line, section;
  std::vector<Vec3> nodes(1);
  std::map<std::string, std::set<long>> sets;
  while (std::getline(in, line)) {
    if (line.rfind("**", 0) == 0) continue;
    if (line[0] == '*') {
      section = line;
      continue;
    }
    std::vector<double> v;
    std::istringstream fields(line);
    for (std::string f; std::getline(fields, f, ',');) v.push_back(std::stod(f));
    if (section == "*Node") nodes.push_back({v[1], v[2], v[3]});
    else if (section.rfind("*Nset", 0) == 0) for (const double n : v) sets[section].insert(static_cast<long>(n));
  }
  const std::array<std::tuple<const char*, int, double>, 6> faces{
      {{"XMIN", 0, 0.01}, {"XMAX", 0, 0.02}, {"YMIN", 1, 0.01}, {"YMAX", 1, 0.022}, {"ZMIN", 2, 0.01},
       {"ZMAX", 2, 0.024}}};
  for (const auto& [name, axis, at] : faces) {
    const std::set<long>& set = sets["*Nset, nset=" + std::string(name)];
    std::set<long> on_plane;
    for (std::size_t n = 1; n < nodes.size(); ++n) {
      const double c[3] = {nodes[n].x, nodes[n].y, nodes[n].z};
      if (std::abs(c[axis] - at) < 1e-12) on_plane.insert(static_cast<long>(n));
    }
    EXPECT_EQ(set, on_plane) << name;
    EXPECT_GE(set.size(), 100u) << name;
  }
}

}  // namespace
}  // namespace aggpack
