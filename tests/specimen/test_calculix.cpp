// The exported Abaqus mesh in a real analysis: a CalculiX deck of its own heading that
// *INCLUDEs specimen.inp, gives each phase's element set a material, fixes the bottom face's
// node set and presses the top face's down, solves (skipped, saying so, without ccx: Debian
// package calculix-ccx, scripts/install-deps.sh).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "aggpack/io/atomic_file.hpp"
#include "aggpack/specimen/voxel_image.hpp"
#include "specimen_beds.hpp"

namespace aggpack {
namespace {

namespace fs = std::filesystem;

bool ccx_available() { return std::system("command -v ccx > /dev/null 2>&1") == 0; }

class CalculixDeck : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!ccx_available()) GTEST_SKIP() << "ccx is not installed (Debian package calculix-ccx; scripts/install-deps.sh)";
    dir_ = fs::temp_directory_path() / ("aggpack_ccx_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override {  // kept, with CalculiX's output, when a test failed
    std::error_code ec;
    if (!HasFailure() && !dir_.empty()) fs::remove_all(dir_, ec);
  }
  fs::path dir_;
};

// The top face pressed 1 um down on a 6 mm cube of stones in mortar: CalculiX solves, and the
// top's reaction pushes back (a negative z force), between what all-mortar and all-stone
// cubes would give (E A u / L).
TEST_F(CalculixDeck, SolvesALoadCaseOnTheIncludedSpecimen) {
  const Box box{{0.012, 0.012, 0.012}, {0.018, 0.018, 0.018}};
  const Specimen s = cut_specimen(testing::random_spheres(120, 0.04, 0.002, 0.005, 7), {box, 0.0, 0.0005});
  const VoxelImage image = voxelize(s, 0.001, 1e6);  // 6 x 6 x 6 voxels
  ASSERT_GT(image.aggregate, 0u);
  ASSERT_GT(image.mortar, 0u);
  write_file_atomically(dir_ / "specimen.inp", [&](std::ostream& o) { write_abaqus_inp(o, image, "test"); });
  std::string sections;
  const double e_stone = 50e9, e_mortar = 20e9, e_itz = 10e9;
  for (const auto& [set, e, present] : {std::tuple{"AGGREGATE", e_stone, image.aggregate > 0},
                                        std::tuple{"MORTAR", e_mortar, image.mortar > 0},
                                        std::tuple{"ITZ", e_itz, image.itz > 0}})
    if (present)
      sections += "*Material, name=M" + std::string(set) + "\n*Elastic\n" + std::to_string(e) +
                  ", 0.2\n*Solid Section, elset=" + set + ", material=M" + set + "\n";
  std::ofstream(dir_ / "deck.inp") << "*Heading\naggpack specimen in a deck\n*INCLUDE, INPUT=specimen.inp\n"
                                   << sections
                                   << "*Boundary\nZMIN, 1, 3, 0.0\n*Step\n*Static\n*Boundary\nZMAX, 3, 3, -1e-6\n"
                                      "*Node print, nset=ZMAX, totals=only\nRF\n*End Step\n";
  const int status = std::system(("cd " + dir_.string() + " && ccx -i deck > ccx.out 2>&1").c_str());
  std::ifstream log(dir_ / "ccx.out");
  std::stringstream log_text;
  log_text << log.rdbuf();
  ASSERT_EQ(status, 0) << log_text.str();
  EXPECT_NE(log_text.str().find("Job finished"), std::string::npos) << log_text.str();
  // deck.dat: "total force (fx,fy,fz) for set ZMAX ..." then the three totals.
  std::ifstream dat(dir_ / "deck.dat");
  std::string line;
  double fz = 0.0;
  bool found = false;
  while (std::getline(dat, line))
    if (line.find("total force") != std::string::npos && std::getline(dat, line) && std::getline(dat, line)) {
      std::istringstream totals(line);
      double fx = 0.0, fy = 0.0;
      found = static_cast<bool>(totals >> fx >> fy >> fz);
    }
  ASSERT_TRUE(found) << "no total force in deck.dat";
  const double area = 0.006 * 0.006, strain = 1e-6 / 0.006;
  EXPECT_LT(fz, -e_itz * strain * area);
  EXPECT_GT(fz, -1.3 * e_stone * strain * area);  // a Poisson's ratio's constraint adds a little
}

}  // namespace
}  // namespace aggpack
