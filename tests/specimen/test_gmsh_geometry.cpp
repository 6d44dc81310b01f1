// The Gmsh route: a small specimen's geometry meshed by Debian's gmsh, its meshed aggregate
// volume against the exact one, its physical groups present (skipped, saying so, without gmsh).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "aggpack/io/atomic_file.hpp"
#include "aggpack/specimen/gmsh_geometry.hpp"
#include "specimen_beds.hpp"

namespace aggpack {
namespace {

namespace fs = std::filesystem;

// The volume of each physical group's tetrahedra (element type 4) in a .msh of format 2.2.
std::map<int, double> tetrahedra_volumes(const fs::path& msh, std::map<int, std::string>& names) {
  std::ifstream in(msh);
  std::string line;
  std::vector<Vec3> nodes;
  std::map<int, double> volumes;
  while (std::getline(in, line)) {
    if (line == "$PhysicalNames") {
      int count = 0;
      in >> count;
      for (int n = 0; n < count; ++n) {
        int dim = 0, tag = 0;
        std::string name;
        in >> dim >> tag >> name;
        names[tag] = name.substr(1, name.size() - 2);
      }
    } else if (line == "$Nodes") {
      std::size_t count = 0;
      in >> count;
      nodes.resize(count + 1);
      for (std::size_t n = 0; n < count; ++n) {
        std::size_t id = 0;
        Vec3 p;
        in >> id >> p.x >> p.y >> p.z;
        nodes.at(id) = p;
      }
    } else if (line == "$Elements") {
      std::size_t count = 0;
      in >> count;
      std::getline(in, line);
      for (std::size_t e = 0; e < count; ++e) {
        std::getline(in, line);
        std::istringstream fields(line);
        int id = 0, type = 0, tags = 0, physical = 0;
        fields >> id >> type >> tags >> physical;
        for (int t = 1; t < tags; ++t) fields >> id;
        if (type != 4) continue;
        std::size_t v[4];
        fields >> v[0] >> v[1] >> v[2] >> v[3];
        const Vec3 a = nodes.at(v[1]) - nodes.at(v[0]), b = nodes.at(v[2]) - nodes.at(v[0]),
                   c = nodes.at(v[3]) - nodes.at(v[0]);
        volumes[physical] += std::abs(dot(cross(a, b), c)) / 6.0;
      }
    }
  }
  return volumes;
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
  std::map<int, std::string> names;
  const std::map<int, double> volumes = tetrahedra_volumes(dir_ / "s.msh", names);
  EXPECT_EQ(names, (std::map<int, std::string>{{1, "aggregate"}, {2, "mortar"}}));
  ASSERT_TRUE(volumes.contains(1) && volumes.contains(2));
  EXPECT_NEAR(volumes.at(1), s.aggregate_volume, 0.01 * s.aggregate_volume);
  EXPECT_NEAR(volumes.at(1) + volumes.at(2), box.volume(), 1e-9 * box.volume());  // the box's faces are flat
}

TEST_F(GmshSpecimen, AnItzShellIsItsOwnPhaseBetweenAggregateAndMortar) {
  const VerticalCylinder core{0.01, 0.01, 0.004, 0.016, 0.006};
  const Specimen s = cut_specimen(testing::random_spheres(24, 0.02, 0.002, 0.0035, 11), {core, 0.0, 0.0004});
  write_file_atomically(dir_ / "s.geo", gmsh_geo(s, {0.0008, 0.0015, 0.0004, 40}, "test"));
  run_gmsh(dir_ / "s.geo", dir_ / "s.msh", dir_ / "gmsh.log");
  std::map<int, std::string> names;
  const std::map<int, double> volumes = tetrahedra_volumes(dir_ / "s.msh", names);
  EXPECT_EQ(names, (std::map<int, std::string>{{1, "aggregate"}, {2, "mortar"}, {3, "itz"}}));
  ASSERT_EQ(volumes.size(), 3u);
  EXPECT_NEAR(volumes.at(1), s.aggregate_volume, 0.01 * s.aggregate_volume);
  EXPECT_NEAR(volumes.at(1) + volumes.at(2) + volumes.at(3), core.volume(), 0.01 * core.volume());
  EXPECT_GT(volumes.at(3), 0.0);
}

}  // namespace
}  // namespace aggpack
