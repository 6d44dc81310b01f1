// calibrated_by: a DEM calibration's values replace the scenario's own, and every way a
// calibration cannot apply is refused naming the key and the file.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "aggpack/core/error.hpp"
#include "aggpack/io/scenario.hpp"

namespace aggpack {
namespace {

namespace fs = std::filesystem;

constexpr const char* kStoneAndSand =
    "[container]\nside = 0.03\nheight = 0.2\n[particles]\n"
    "classes = [{ diameter = 0.01, count = 30, material = \"stone\" }, { diameter = 0.006, count = 60, material = "
    "\"sand\" }]\n[material]\nrolling_friction = 0.05\n[materials.stone]\nrolling_friction = 0.3\n"
    "[materials.sand]\nfriction_particle = 0.4\n[deposition]\n[dynamics]\n";

class ScenarioCalibration : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("aggpack_scenario_calibration_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // A calibration file as calibrate --dem writes it, with these assignments.
  fs::path calibration(const std::string& name, const std::vector<std::string>& assignments) {
    const nlohmann::json j{{"kind", "aggpack DEM calibration"},
                           {"scenario_file", "cal.toml"},
                           {"protocol", "pour"},
                           {"seeds", 3},
                           {"measured", {{"density", 0.7}, {"of", "the scenario's bed"}}},
                           {"fit", {{"parameter", "rolling_friction"}, {"value", 0.2}, {"band", {0.15, 0.25}}}},
                           {"assignments", assignments}};
    std::ofstream(dir_ / name) << j.dump();
    return dir_ / name;
  }
  Scenario parse(const std::string& extra, const std::vector<std::string>& sets = {}) {
    ScenarioOverrides overrides;
    overrides.set = sets;
    return parse_scenario(extra + kStoneAndSand, dir_ / "s.toml", overrides);
  }
  void expect_refused(const std::string& extra, const std::vector<std::string>& words,
                      const std::vector<std::string>& sets = {}) {
    try {
      (void)parse(extra, sets);
      ADD_FAILURE() << extra << " accepted";
    } catch (const InputError& e) {
      for (const std::string& w : words)
        EXPECT_NE(std::string(e.what()).find(w), std::string::npos) << w << " in " << e.what();
    }
  }
  fs::path dir_;
};

TEST_F(ScenarioCalibration, ItsValuesReplaceTheScenariosAndItIsRecorded) {
  calibration("sand.json", {"materials.sand.rolling_friction=0.2"});
  calibration("all.json", {"material.friction_particle=0.7", "materials.stone.friction_particle=0.6"});
  // A file relative to the scenario's folder; a list of two.
  const Scenario sc = parse("calibrated_by = [\"sand.json\", \"all.json\"]\n");
  ASSERT_EQ(sc.materials.size(), 2u);  // sand, stone: alphabetical
  EXPECT_EQ(sc.materials[0].name, "sand");
  EXPECT_EQ(sc.materials[0].material.contact.rolling_friction, 0.2);
  EXPECT_EQ(sc.materials[0].material.contact.friction_particle, 0.4);  // the scenario's, not calibrated
  EXPECT_EQ(sc.materials[1].material.contact.rolling_friction, 0.3);
  EXPECT_EQ(sc.materials[1].material.contact.friction_particle, 0.6);
  EXPECT_EQ(sc.material.contact.friction_particle, 0.7);
  ASSERT_EQ(sc.calibrations.size(), 2u);
  EXPECT_EQ(sc.calibrations[0].file, dir_ / "sand.json");
  const nlohmann::json echo = to_json(sc);
  EXPECT_EQ(echo["calibrated_by"][1]["assignments"][1], "materials.stone.friction_particle=0.6");
  EXPECT_NE(echo["calibrated_by"][0]["fitted_to"].get<std::string>().find("to the measured density 0.7"),
            std::string::npos);
  // One file as a string; and a scenario without calibrated_by has no such key in its echo.
  EXPECT_EQ(parse("calibrated_by = \"sand.json\"\n").materials[0].material.contact.rolling_friction, 0.2);
  EXPECT_FALSE(to_json(parse("")).contains("calibrated_by"));
}

TEST_F(ScenarioCalibration, ACalibrationThatCannotApplyIsRefused) {
  calibration("sand.json", {"materials.sand.rolling_friction=0.2"});
  calibration("sand_again.json", {"materials.sand.rolling_friction=0.25"});
  calibration("gravel.json", {"materials.gravel.rolling_friction=0.2"});
  std::ofstream(dir_ / "cpm.json") << R"({"kind": "aggpack CPM calibration", "cpm": {}})";
  expect_refused("calibrated_by = [\"sand.json\", \"sand_again.json\"]\n",
                 {"s.toml:1:", "calibrated_by",
                  "sand_again.json sets materials.sand.rolling_friction, which "
                  "calibrated_by " +
                      (dir_ / "sand.json").string() + " sets too"});
  expect_refused("calibrated_by = \"sand.json\"\n", {"--set materials.sand.rolling_friction=0.1 sets too"},
                 {"materials.sand.rolling_friction=0.1"});
  expect_refused("calibrated_by = \"gravel.json\"\n", {"materials.gravel.rolling_friction", "no [materials.gravel]"});
  expect_refused("calibrated_by = \"cpm.json\"\n", {"calibrated_by", "not a DEM calibration", "calibrate --dem"});
  expect_refused("calibrated_by = \"none.json\"\n", {"calibrated_by", "none.json"});
  expect_refused("calibrated_by = 3\n", {"calibrated_by"});
}

}  // namespace
}  // namespace aggpack
