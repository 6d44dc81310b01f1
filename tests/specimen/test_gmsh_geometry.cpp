// The Gmsh route: a small specimen's geometry meshed by Debian's gmsh, its meshed aggregate
// volume (each group's tetrahedra summed) against the exact one, its physical groups present
// (skipped, saying so, without gmsh).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "aggpack/io/atomic_file.hpp"
#include "aggpack/specimen/gmsh_geometry.hpp"
#include "aggpack/specimen/specimen_export.hpp"
#include "specimen_beds.hpp"

namespace aggpack {
namespace {

namespace fs = std::filesystem;

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

}  // namespace
}  // namespace aggpack
