// `aggpack test` and `aggpack calibrate MATERIAL --test`, as a user meets them: the answer in the
// lab's units, the scenario it wrote giving the same packing when run again, bad input refused
// before any run, and a calibration whose file reads back.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "run_cli.hpp"

namespace {

namespace fs = std::filesystem;
using aggpack::testing::run_cli;
using aggpack::testing::slurp;

class CliLabTests : public ::testing::Test {
 protected:
  aggpack::testing::ScratchDir scratch_{"aggpack_cli_lab_tests_"};
  const fs::path& dir_ = scratch_.path();
};

const fs::path kBeads = fs::path(AGGPACK_EXAMPLES) / "materials" / "glass_beads_11mm.toml";

TEST_F(CliLabTests, AShovelledC29GivesTheLabsUnitsAndItsScenarioRunsToTheSamePacking) {
  const fs::path out = dir_ / "c29";
  const auto r = run_cli("test c29 " + kBeads.string() + " --method shovelling --seeds 1 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("bulk density"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("1/10 ft3 (2.8 L)"), std::string::npos) << r.output;
  const nlohmann::json s = nlohmann::json::parse(slurp(out / "summary.json"));
  EXPECT_EQ(s["test"], "c29");
  EXPECT_EQ(s["method"], "shovelling");
  const double packing = s["packing_density"]["mean"];
  // Loose equal spheres: 0.55 (random loose) to 0.61 in a measure 14 diameters wide.
  EXPECT_GT(packing, 0.55);
  EXPECT_LT(packing, 0.62);
  // C29's arithmetic: bulk density = packing x S x 998 kg/m3; voids = 100 (1 - packing).
  EXPECT_NEAR(s["bulk_density_kg_m3"].get<double>(), packing * 2.5 * 998.0, 1e-6);
  EXPECT_NEAR(s["voids_percent"].get<double>(), 100.0 * (1.0 - packing), 1e-9);
  ASSERT_EQ(s["parts"].size(), 1u);
  ASSERT_EQ(s["parts"][0]["packing_density"].size(), 1u);
  EXPECT_FALSE(s["modelling"].empty());
  // Where the time went: the pour's DEM, over steps of the bed's spheres (beads: one a particle).
  const nlohmann::json& time = s["parts"][0]["time"];
  EXPECT_GT(time["dem_steps"].get<double>(), 1000);
  EXPECT_GT(time["pour_s"].get<double>(), 0.0);
  EXPECT_LE(time["pour_s"].get<double>(), s["parts"][0]["wall_clock_s"].get<double>());
  EXPECT_EQ(time["rodding_s"].get<double>(), 0.0);
  EXPECT_GE(time["spheres"].get<std::size_t>(), s["parts"][0]["particles"][0].get<std::size_t>());
  // The scenario it wrote is the test: run again with seed 1, its measure holds the same packing.
  const auto again = run_cli("run " + (out / "scenario_1.toml").string() + " --seed 1 --out " + (dir_ / "run").string());
  ASSERT_EQ(again.exit_code, 0) << again.output;
  const nlohmann::json run = nlohmann::json::parse(slurp(dir_ / "run" / "summary.json"));
  EXPECT_DOUBLE_EQ(run["measure"]["packing_density"].get<double>(), s["parts"][0]["packing_density"][0].get<double>());
}

TEST_F(CliLabTests, WhatTheStandardDoesNotDefineIsRefusedBeforeAnyRunOrFolder) {
  const fs::path out = dir_ / "refused";
  for (const std::string& args :
       {"test c29 " + kBeads.string() + " --method jigging",              // jigging is above 37.5 mm
        "test c29 " + kBeads.string() + " --method tamping",              // no such method
        "test c1252 " + kBeads.string() + " --method A",                  // a coarse aggregate
        "test c29 " + kBeads.string() + " --method rodding --finest 2in"}) {  // a cut-off above every size
    const auto r = run_cli(args + " --out " + out.string());
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
    EXPECT_NE(r.output.find("error"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out)) << args;
  }
  const auto jig = run_cli("test c29 " + kBeads.string() + " --method jigging --out " + out.string());
  EXPECT_NE(jig.output.find("37.5 mm"), std::string::npos) << jig.output;
  // A material named by a relative path finds its grading file beside it (the scenario is
  // read through), and method C of a sand to 4.75 mm with its fines is more than a
  // representative cylinder of --max-particles can hold: the option is named with what it needs.
  const auto sand =
      aggpack::testing::run_command("cd " + kBeads.parent_path().parent_path().string() + " && " + AGGPACK_EXE +
                                    " test c1252 materials/natural_sand.toml --method C "
                                    "--out " +
                                    out.string());
  EXPECT_EQ(sand.exit_code, 2) << sand.output;
  EXPECT_NE(sand.output.find("--max-particles 50000"), std::string::npos) << sand.output;
  EXPECT_NE(sand.output.find("expected --max-particles of at least"), std::string::npos) << sand.output;
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(CliLabTests, ACalibrationOnTheTestWritesAMaterialFileThatReadsBackWithItsValue) {
  // The beads with a loose bulk density between what they give rolling freely (0.596) and with a
  // rolling friction of 0.3 (0.588).
  const fs::path material = dir_ / "beads.toml";
  std::ofstream(material) << slurp(kBeads) << "\n[lab.c29]\nbulk_density = \"1475 kg/m3\"\nmethod = \"shovelling\"\n";
  const auto r = run_cli("calibrate " + material.string() +
                         " --test c29 --method shovelling --fit rolling_friction --range 0,0.3 --max-runs 2 --seeds 2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const fs::path calibrated = dir_ / "beads_calibrated.toml";
  ASSERT_TRUE(fs::exists(calibrated)) << r.output;
  const nlohmann::json c = nlohmann::json::parse(slurp(fs::path(calibrated.string() + ".json")));
  EXPECT_EQ(c["kind"], "aggpack material calibration");
  EXPECT_EQ(c["key"], "contact.rolling_friction");
  EXPECT_NEAR(c["target_packing_density"].get<double>(), 1475.0 / (2.5 * 998.0), 1e-12);
  const double value = c["value"];
  EXPECT_GE(value, 0.0);
  EXPECT_LE(value, 0.3);
  // The calibrated file reads back, its rolling friction the fitted one, its lab value kept.
  const auto m = run_cli("material " + calibrated.string() + " --json");
  ASSERT_EQ(m.exit_code, 0) << m.output;
  const nlohmann::json j = nlohmann::json::parse(m.output);
  EXPECT_NEAR(j["contact"]["rolling_friction"].get<double>(), value, 1e-5) << m.output;
}

}  // namespace
