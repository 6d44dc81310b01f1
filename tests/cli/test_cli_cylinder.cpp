// A cylindrical measure (ASTM C29, C1252) as a user runs one: a pour into it, end to end, with
// the content struck off at the rim in summary.json; the keys it refuses, by name.
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "run_cli.hpp"

namespace {

namespace fs = std::filesystem;
using aggpack::testing::run_cli;

// 500 spheres of 6 mm poured into a 60 mm measure struck off at 25 mm (the bed about 33 mm
// deep), soft so that it runs in seconds.
constexpr const char* kMeasure =
    "seed = 2\n[container]\nshape = \"cylinder\"\ndiameter = \"60 mm\"\nheight = \"100 mm\"\nrim = \"25 mm\"\n"
    "[particles]\ndiameter = \"6 mm\"\ncount = 500\n"
    "[material]\nyoungs_modulus = 1e8\nwall_youngs_modulus = 1e8\nfriction_particle = 0.3\n[dynamics]\nmax_time = 0.6\n"
    "[analysis]\nbox_sides = [\"15 mm\"]\n[pour]\nbatches = 2\n";

class CliCylinder : public ::testing::Test {
 protected:
  aggpack::testing::ScratchDir scratch_{"aggpack_cli_cylinder_"};
  const fs::path& dir_ = scratch_.path();

  fs::path write_scenario(const std::string& name, const std::string& text) {
    const fs::path path = dir_ / (name + ".toml");
    std::ofstream(path) << text;
    return path;
  }
  // `aggpack check` on kMeasure with `from` replaced by `to`: exit code 2 and `message` named.
  void expect_refused(const std::string& from, const std::string& to, const std::string& message) {
    std::string text = kMeasure;
    const std::size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
    const auto r = run_cli("check " + write_scenario("bad", text).string());
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << r.output;
  }
};

TEST_F(CliCylinder, APourIntoAMeasureStaysInItsCircleAndReportsItsContent) {
  const fs::path out = dir_ / "measure";
  const auto r = run_cli("run " + write_scenario("measure", kMeasure).string() + " --threads 1 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("measure 0.06 m (60 mm) across, struck off at 0.025 m (25 mm): packing density"), std::string::npos)
      << r.output;
  const auto s = nlohmann::json::parse(std::ifstream(out / "summary.json"));
  EXPECT_EQ(s["container"]["shape"], "cylinder");
  EXPECT_NEAR(s["container"]["diameter_m"].get<double>(), 0.06, 1e-15);
  EXPECT_EQ(s["scenario"]["container"]["shape"], "cylinder");
  EXPECT_NEAR(s["scenario"]["container"]["rim_m"].get<double>(), 0.025, 1e-15);
  const auto& m = s.at("measure");
  EXPECT_NEAR(m["volume_m3"].get<double>(), std::numbers::pi * 0.03 * 0.03 * 0.025, 1e-15);
  EXPECT_EQ(m["strike_off"], "exact cut at the rim");
  // A loose pour of equal spheres in a narrow measure (10 diameters): the wall loosens it.
  const double exact = m["packing_density"].get<double>(), whole = m["packing_density_whole_particles"].get<double>();
  EXPECT_GT(exact, 0.50);
  EXPECT_LT(exact, 0.64);
  EXPECT_NEAR(whole, exact, 0.05);
  EXPECT_GT(m["particles"].get<int>(), 250);
  EXPECT_LT(m["particles"].get<int>(), 500);
  // Every sphere inside the circle (to a contact's overlap), none lost.
  std::ifstream csv(out / "particles.csv");
  std::string line;
  std::getline(csv, line);
  std::size_t rows = 0;
  double farthest = 0.0;
  while (std::getline(csv, line)) {
    std::istringstream row(line);
    double id, x, y, z, radius;
    char comma;
    row >> id >> comma >> x >> comma >> y >> comma >> z >> comma >> radius;
    ++rows;
    farthest = std::max(farthest, std::hypot(x - 0.03, y - 0.03) + radius - 0.03);
    EXPECT_GT(z, 0.0);
  }
  EXPECT_EQ(rows, 500u);
  EXPECT_LT(farthest, 0.01 * 0.003);  // at most a Hertz overlap of the wall
  // The wall profile is radial: the first ring (at the wall) looser than the core.
  const auto& rings = s["profiles"]["wall_distance"]["solid_fraction"];
  ASSERT_GT(rings.size(), 8u);
  EXPECT_GT(s["density"]["mean"].get<double>(), 0.5);
  // A specimen cut from it must lie inside the wall: a box in the container's corner is refused.
  const auto corner = run_cli("specimen " + out.string() + " --box 0,0,0.005,0.012,0.012,0.015 --formats vti --out " +
                              (dir_ / "corner").string());
  EXPECT_EQ(corner.exit_code, 2) << corner.output;
  EXPECT_NE(corner.output.find("reaches 0.0424264 m from the axis of the cylindrical container"), std::string::npos)
      << corner.output;
  const auto core = run_cli("specimen " + out.string() + " --cylinder 0.03,0.03,0.005,0.015,0.01 --formats vti --out " +
                            (dir_ / "core").string());
  EXPECT_EQ(core.exit_code, 0) << core.output;
}

TEST_F(CliCylinder, RefusesWhatAMeasureCannotBeByItsKey) {
  expect_refused("diameter = \"60 mm\"", "diameter = \"60 mm\"\nside = \"60 mm\"", "container.side: a cylinder");
  expect_refused("diameter = \"60 mm\"", "diameter = \"60 mm\"\nsides = \"periodic\"",
                 "container.sides: a cylinder has a wall all round");
  expect_refused("rim = \"25 mm\"", "rim = \"120 mm\"", "container.rim: 0.12 m is above the container's height");
  expect_refused("shape = \"cylinder\"\n", "", "container.diameter: only a cylinder");
  expect_refused("shape = \"cylinder\"", "shape = \"cone\"", "container.shape");
  expect_refused("[pour]\nbatches = 2\n", "[deposition]\n",
                 "container.shape = \"cylinder\": drop-and-roll deposition needs a box");
  expect_refused("[analysis]\nbox_sides = [\"15 mm\"]", "[analysis]\nbox_sides = [\"40 mm\"]", "analysis.box_sides");
  // A file's sphere in the container's corner, inside its box but beyond its wall, is refused;
  // one pressed into the wall by a contact's overlap (1e-9 m) is taken.
  std::ofstream(dir_ / "bed.csv") << "x,y,z,r\n0.03,0.03,0.003,0.003\n0.005,0.005,0.003,0.003\n";
  const std::string from_file =
      "[container]\nshape = \"cylinder\"\ndiameter = 0.06\nheight = 0.1\n[particles]\nfrom = \"bed.csv\"\n";
  const auto corner = run_cli("check " + write_scenario("corner", from_file).string());
  EXPECT_EQ(corner.exit_code, 2) << corner.output;
  EXPECT_NE(corner.output.find("particle 1 (data row 2)"), std::string::npos) << corner.output;
  EXPECT_NE(corner.output.find("beyond the cylinder's wall"), std::string::npos) << corner.output;
  std::ofstream(dir_ / "bed.csv") << "x,y,z,r\n0.03,0.03,0.003,0.003\n0.057000001,0.03,0.003,0.003\n";
  // (Two spheres are too few a bed for a virtual cube: the check after the file's fails instead.)
  const auto touching = run_cli("check " + write_scenario("touching", from_file).string());
  EXPECT_EQ(touching.output.find("particle 1"), std::string::npos) << touching.output;
  EXPECT_NE(touching.output.find("analysis.box_sides: the bed is too small"), std::string::npos) << touching.output;
}

}  // namespace
