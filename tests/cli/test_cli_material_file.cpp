// `aggpack material FILE`, and a run whose material is a material file, as a user meets them.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "run_cli.hpp"

namespace {

namespace fs = std::filesystem;
using aggpack::testing::run_cli;
using aggpack::testing::slurp;

class CliMaterialFile : public ::testing::Test {
 protected:
  aggpack::testing::ScratchDir scratch_{"aggpack_cli_material_file_"};
  const fs::path& dir_ = scratch_.path();
};

const fs::path kMaterials = fs::path(AGGPACK_EXAMPLES) / "materials";

TEST_F(CliMaterialFile, PrintsEachShippedMaterialWithItsLabResults) {
  for (const char* file : {"crushed_stone_19mm.toml", "gravel_19mm.toml", "natural_sand.toml", "manufactured_sand.toml"}) {
    const auto r = run_cli("material " + (kMaterials / file).string());
    EXPECT_EQ(r.exit_code, 0) << file << ": " << r.output;
    for (const char* part : {"bulk specific gravity", "particle density", "nominal maximum size", "fineness modulus",
                             "shape: ", "contact: friction", "voids", "packing fraction"})
      EXPECT_NE(r.output.find(part), std::string::npos) << file << ": " << part << "\n" << r.output;
  }
  // The crushed stone's C29 result: 1580 kg/m3 rodded at SG 2.65: voids 100 (1 - 1580 / 2644.7) = 40.26 %.
  const auto stone = run_cli("material " + (kMaterials / "crushed_stone_19mm.toml").string());
  EXPECT_NE(stone.output.find("ASTM C29 bulk density (rodding): 1580.0 kg/m3 (98.64 lb/ft3): voids 40.26 %, packing "
                              "fraction 0.5974"),
            std::string::npos)
      << stone.output;
  const auto sand = run_cli("material " + (kMaterials / "natural_sand.toml").string());
  EXPECT_NE(sand.output.find("ASTM C1252 uncompacted voids (method A): 39.00 %, packing fraction 0.6100"),
            std::string::npos)
      << sand.output;
}

TEST_F(CliMaterialFile, JsonGivesTheSameValues) {
  const auto r = run_cli("material " + (kMaterials / "gravel_19mm.toml").string() + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = nlohmann::json::parse(r.output);
  EXPECT_EQ(j["name"], "River gravel, 19 mm (C33 No. 67)");
  EXPECT_EQ(j["specific_gravity_basis"], "ssd");
  EXPECT_NEAR(j["specific_gravity_oven_dry"].get<double>(), 2.64 / 1.01, 1e-12);
  EXPECT_NEAR(j["particle_density_kg_m3"].get<double>(), 2.64 / 1.01 * 997.5, 1e-9);
  EXPECT_NEAR(j["lab"]["c29"]["bulk_density_lb_ft3"].get<double>(), 106.1, 1e-9);
  EXPECT_EQ(j["lab"]["c29"]["method"], "rodding");
  EXPECT_NEAR(j["lab"]["c29"]["voids_percent"].get<double>(), 34.85, 0.01);
  EXPECT_DOUBLE_EQ(j["grading"]["nominal_maximum_size_m"].get<double>(), 0.019);
  EXPECT_EQ(j["shape"]["family"], "rounded");
}

TEST_F(CliMaterialFile, BadInputExitsTwoNamingTheFileAndKey) {
  std::ofstream(dir_ / "bad.toml") << "specific_gravity = 2.65\n[grading]\nname = \"astm_c33_fine_mid\"\n"
                                      "[lab.c1252]\nvoids_percent = 120\nmethod = \"A\"\n";
  auto r = run_cli("material " + (dir_ / "bad.toml").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("bad.toml:5"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("lab.c1252.voids_percent"), std::string::npos) << r.output;
  r = run_cli("material " + (dir_ / "none.toml").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("none.toml"), std::string::npos) << r.output;
  r = run_cli("material");
  EXPECT_EQ(r.exit_code, 2) << r.output;
}

TEST_F(CliMaterialFile, ARunTakesAMaterialFilesDensityContactAndGrading) {
  fs::create_directories(dir_ / "materials");
  std::ofstream(dir_ / "materials/pea.csv") << "sieve,opening_mm,percent_passing\n1/2in,12.5,100\n3/8in,9.5,60\n"
                                               "#4,4.75,0\n";
  std::ofstream(dir_ / "materials/pea.toml") << "name = \"pea gravel\"\nspecific_gravity = 2.50\n[grading]\n"
                                                "file = \"pea.csv\"\n[contact]\nfriction_particle = 0.45\n";
  std::ofstream(dir_ / "run.toml") << "seed = 3\n[container]\nside = \"6 cm\"\nheight = \"15 cm\"\n"
                                      "[materials.pea]\nfile = \"materials/pea.toml\"\n[particles]\n"
                                      "fill_height = \"6 cm\"\n"
                                      "[particles.grading]\nmaterial = \"pea\"\n[deposition]\n[analysis]\n"
                                      "box_sides = [0.02]\n";
  const auto r = run_cli("run " + (dir_ / "run.toml").string() + " --quiet --threads 1 --out " + (dir_ / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json summary = nlohmann::json::parse(slurp(dir_ / "out/summary.json"));
  const nlohmann::json& pea = summary["scenario"]["materials"]["pea"];
  EXPECT_NEAR(pea["density_kg_m3"].get<double>(), 2.50 * 997.5, 1e-9) << pea.dump();
  EXPECT_DOUBLE_EQ(pea["friction_particle"].get<double>(), 0.45);
  EXPECT_EQ(pea["file"], "materials/pea.toml");
  EXPECT_EQ(summary["scenario"]["particles"]["gradings"][0]["sieves"].size(), 3u);
  EXPECT_EQ(summary["scenario"]["particles"]["component_materials"][0], "pea");
}

}  // namespace
