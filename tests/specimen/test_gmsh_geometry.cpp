// The Gmsh route: a small specimen's geometry meshed by Debian's gmsh, its meshed aggregate
// volume (each group's tetrahedra summed) against the exact one, its physical groups present
// (skipped, saying so, without gmsh).
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "aggpack/core/error.hpp"
#include "aggpack/core/stop_request.hpp"
#include "aggpack/io/atomic_file.hpp"
#include "aggpack/specimen/gmsh_geometry.hpp"
#include "aggpack/specimen/specimen_export.hpp"
#include "specimen_beds.hpp"

namespace aggpack {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class GmshSpecimen : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!gmsh_available()) GTEST_SKIP() << "gmsh is not installed (Debian package gmsh; scripts/install-deps.sh)";
    dir_ = fs::temp_directory_path() / ("aggpack_gmsh_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override {  // kept, with Gmsh's log, when a test failed
    std::error_code ec;
    if (!HasFailure()) fs::remove_all(dir_, ec);
  }
  fs::path dir_;
};

TEST_F(GmshSpecimen, MeshesTheAggregateToWithinOnePercentOfItsExactVolume) {
  const Box box{{0.004, 0.004, 0.004}, {0.016, 0.016, 0.016}};
  const Specimen s = cut_specimen(testing::random_spheres(24, 0.02, 0.002, 0.0035, 11), {box, 0.0, 0.0});
  ASSERT_GT(s.kept_particles, 10u);
  write_file_atomically(dir_ / "s.geo", gmsh_geo(s, {0.0008, 0.0015, 0.0, 40}, "test"));
  run_gmsh(dir_ / "s.geo", dir_ / "s.msh", dir_ / "gmsh.log");
  const std::map<std::string, double> volumes = msh_group_volumes(dir_ / "s.msh");
  ASSERT_EQ(volumes.size(), 2u);
  ASSERT_TRUE(volumes.contains("aggregate") && volumes.contains("mortar"));
  EXPECT_NEAR(volumes.at("aggregate"), s.aggregate_volume, 0.01 * s.aggregate_volume);
  EXPECT_NEAR(volumes.at("aggregate") + volumes.at("mortar"), box.volume(), 1e-9 * box.volume());  // flat faces
}

TEST_F(GmshSpecimen, AnItzShellIsItsOwnPhaseBetweenAggregateAndMortar) {
  const VerticalCylinder core{0.01, 0.01, 0.004, 0.016, 0.006};
  const Specimen s = cut_specimen(testing::random_spheres(24, 0.02, 0.002, 0.0035, 11), {core, 0.0, 0.0004});
  write_file_atomically(dir_ / "s.geo", gmsh_geo(s, {0.0008, 0.0015, 0.0004, 40}, "test"));
  run_gmsh(dir_ / "s.geo", dir_ / "s.msh", dir_ / "gmsh.log");
  const std::map<std::string, double> volumes = msh_group_volumes(dir_ / "s.msh");
  ASSERT_EQ(volumes.size(), 3u);
  ASSERT_TRUE(volumes.contains("aggregate") && volumes.contains("mortar") && volumes.contains("itz"));
  EXPECT_NEAR(volumes.at("aggregate"), s.aggregate_volume, 0.01 * s.aggregate_volume);
  EXPECT_NEAR(volumes.at("aggregate") + volumes.at("mortar") + volumes.at("itz"), core.volume(), 0.01 * core.volume());
  EXPECT_GT(volumes.at("itz"), 0.0);
}

// Grains of two and three overlapping spheres, apart from each other: each grain is the union
// of its spheres (meshed as one volume, not as overlapping ones Gmsh cannot mesh), and its
// meshed volume the union's exact one.
TEST_F(GmshSpecimen, MeshesGrainsAsTheUnionOfTheirSpheres) {
  PackedParticles bed;
  std::size_t particle = 0;
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      for (int k = 0; k < 2; ++k, ++particle) {
        const Vec3 c{0.006 + 0.008 * i, 0.006 + 0.008 * j, 0.006 + 0.008 * k};
        const int members = 2 + (i + j + k) % 2;
        for (int m = 0; m < members; ++m) {
          bed.spheres.push_back({{c.x + 0.0012 * (m - 0.5 * (members - 1)), c.y, c.z + 0.0004 * m}, 0.0016});
          bed.particle_of_sphere.push_back(particle);
        }
        bed.particle_size.push_back(0.0032);
      }
  const Box box{{0.002, 0.002, 0.002}, {0.018, 0.018, 0.015}};  // cuts the top grains
  const Specimen s = cut_specimen(bed, {box, 0.0, 0.0});
  ASSERT_EQ(s.kept_particles, 8u);
  write_file_atomically(dir_ / "s.geo", gmsh_geo(s, {0.0006, 0.0015, 0.0, 40}, "test"));
  ASSERT_NE(slurp(dir_ / "s.geo").find("BooleanUnion"), std::string::npos);
  run_gmsh(dir_ / "s.geo", dir_ / "s.msh", dir_ / "gmsh.log");
  const std::map<std::string, double> volumes = msh_group_volumes(dir_ / "s.msh");
  ASSERT_TRUE(volumes.contains("aggregate") && volumes.contains("mortar"));
  EXPECT_NEAR(volumes.at("aggregate"), s.aggregate_volume, 0.02 * s.aggregate_volume);
  EXPECT_NEAR(volumes.at("aggregate") + volumes.at("mortar"), box.volume(), 1e-6 * box.volume());
}

// A geometry Gmsh cannot make: an InputError naming its log, and no mesh file left behind
// (Gmsh writes an empty one).
TEST_F(GmshSpecimen, AFailedMeshLeavesNoMeshFile) {
  std::ofstream(dir_ / "bad.geo") << "SetFactory(\"OpenCASCADE\");\nBox(1) = {0, 0, 0, 1, 1;\n";
  EXPECT_THROW(run_gmsh(dir_ / "bad.geo", dir_ / "bad.msh", dir_ / "gmsh.log"), InputError);
  EXPECT_FALSE(fs::exists(dir_ / "bad.msh"));
}

// Whether a process whose command line names `word` is running (Gmsh's, by its files' folder).
bool process_naming(const std::string& word) {
  for (const auto& entry : fs::directory_iterator("/proc")) {
    std::ifstream cmdline(entry.path() / "cmdline");
    std::string text((std::istreambuf_iterator<char>(cmdline)), std::istreambuf_iterator<char>());
    if (entry.path().filename().string() != std::to_string(::getpid()) && text.find(word) != std::string::npos)
      return true;
  }
  return false;
}

// A stop while Gmsh meshes (what the safe point throws: the CLI's Interrupted, Python's
// KeyboardInterrupt) ends Gmsh's process group at once and removes its partial mesh.
TEST_F(GmshSpecimen, AStopWhileGmshMeshesEndsGmshAndRemovesItsMesh) {
  const Box box{{0.004, 0.004, 0.004}, {0.016, 0.016, 0.016}};
  const Specimen s = cut_specimen(testing::random_spheres(24, 0.02, 0.002, 0.0035, 11), {box, 0.0, 0.0});
  write_file_atomically(dir_ / "s.geo", gmsh_geo(s, {0.0001, 0.0002, 0.0, 40}, "test"));  // minutes of work
  int calls = 0;
  const auto start = std::chrono::steady_clock::now();
  EXPECT_THROW(run_gmsh(dir_ / "s.geo", dir_ / "s.msh", dir_ / "gmsh.log",
                        [&] {
                          if (++calls == 20) throw Interrupted(15, "in the test");  // after a second
                        }),
               Interrupted);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5));
  EXPECT_FALSE(fs::exists(dir_ / "s.msh"));
  EXPECT_FALSE(process_naming((dir_ / "s.geo").string()));
}

}  // namespace
}  // namespace aggpack
