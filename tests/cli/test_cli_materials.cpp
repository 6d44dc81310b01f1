// A run of several materials as a user meets it: particles.csv's material column, the VTP's
// material array, the summary's materials, and the masses of each material's density.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "run_cli.hpp"

namespace {

namespace fs = std::filesystem;
using aggpack::testing::run_cli;
using aggpack::testing::slurp;

class CliMaterials : public ::testing::Test {
 protected:
  aggpack::testing::ScratchDir scratch_{"aggpack_cli_materials_"};
  const fs::path& dir_ = scratch_.path();
};

// 30 stones of 1 cm (3000 kg/m^3) and 60 sand grains of 6 mm (1500 kg/m^3), deposited and
// settled a little by the DEM with a pair of their own friction.
constexpr const char* kTwoMaterials =
    "title = \"two materials\"\nseed = 4\n[container]\nside = 0.03\nheight = 0.2\n[particles]\n"
    "classes = [{ diameter = 0.01, count = 30, material = \"stone\" }, { diameter = 0.006, count = 60, material = "
    "\"sand\" }]\n[material]\nyoungs_modulus = 1e8\nwall_youngs_modulus = 1e8\n"
    "[materials.stone]\ndensity = 3000\nyoungs_modulus = 2e8\nfriction_particle = 0.6\n"
    "[materials.sand]\ndensity = 1500\n[[material_pairs]]\nmaterials = [\"sand\", \"stone\"]\nfriction = 0.3\n"
    "[deposition]\n[dynamics]\nmax_time = 0.05\n[analysis]\nbox_sides = [0.005]\n";

struct Row {
  double r = 0.0;
  std::string material;
};

// particles.csv's header and its rows' radius and material.
std::vector<Row> csv_rows(const fs::path& file, std::string& header) {
  std::istringstream in(slurp(file));
  std::getline(in, header);
  std::vector<Row> rows;
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::istringstream s(line);
    for (std::string cell; std::getline(s, cell, ',');) cells.push_back(cell);
    EXPECT_EQ(cells.size(), 6u) << line;
    if (cells.size() == 6) rows.push_back({std::stod(cells[4]), cells[5]});
  }
  return rows;
}

TEST_F(CliMaterials, ARunOfTwoMaterialsNamesThemInItsOutputsAndWeighsEachByItsDensity) {
  std::ofstream(dir_ / "two.toml") << kTwoMaterials;
  const auto r = run_cli("run " + (dir_ / "two.toml").string() + " --quiet --threads 1 --out " + (dir_ / "two").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::string header;
  const std::vector<Row> rows = csv_rows(dir_ / "two" / "particles.csv", header);
  EXPECT_EQ(header, "id,x,y,z,r,material");
  ASSERT_EQ(rows.size(), 90u);
  const std::map<std::string, double> density{{"stone", 3000.0}, {"sand", 1500.0}};
  std::map<std::string, std::size_t> count;
  double mass = 0.0, volume = 0.0;
  for (const Row& row : rows) {
    ++count[row.material];
    ASSERT_TRUE(density.count(row.material)) << row.material;
    EXPECT_NEAR(row.r, row.material == "stone" ? 0.005 : 0.003, 1e-12) << row.material;
    const double v = 4.0 / 3.0 * M_PI * row.r * row.r * row.r;
    mass += density.at(row.material) * v;
    volume += v;
  }
  EXPECT_EQ(count["stone"], 30u);
  EXPECT_EQ(count["sand"], 60u);
  // The VTP carries the material of each sphere as an array of its own.
  EXPECT_NE(slurp(dir_ / "two" / "particles.vtp").find("Name=\"material\""), std::string::npos);
  const auto summary = nlohmann::json::parse(std::ifstream(dir_ / "two" / "summary.json"));
  const auto& scenario = summary.at("scenario");
  EXPECT_EQ(scenario.at("materials").at("stone").at("density_kg_m3"), 3000.0);
  EXPECT_EQ(scenario.at("materials").at("sand").at("density_kg_m3"), 1500.0);
  EXPECT_EQ(scenario.at("material_pairs").size(), 1u);
  EXPECT_EQ(scenario.at("particles").at("component_materials"), (nlohmann::json{"stone", "sand"}));
  // The grains' density is the bed's mass over its solid volume, from each sphere's material.
  const double grains = summary.at("bulk_density").at("particle_density_kg_m3").get<double>();
  EXPECT_NEAR(grains, mass / volume, 1e-9 * grains);
  EXPECT_GT(grains, 1500.0);
  EXPECT_LT(grains, 3000.0);
  EXPECT_EQ(summary.at("stages").at("dynamics").at("ended_by").is_string(), true);
}

// The same bed of one material: no material column, array or summary key.
TEST_F(CliMaterials, ARunOfOneMaterialWritesNoMaterialColumn) {
  std::string text = "[container]\nside = 0.03\nheight = 0.2\n[particles]\nclasses = [{ diameter = 0.01, count = 30 },"
                     " { diameter = 0.006, count = 60 }]\n[deposition]\n[analysis]\nbox_sides = [0.005]\n";
  std::ofstream(dir_ / "one.toml") << text;
  const auto r = run_cli("run " + (dir_ / "one.toml").string() + " --quiet --out " + (dir_ / "one").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string csv = slurp(dir_ / "one" / "particles.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "id,x,y,z,r");
  EXPECT_EQ(slurp(dir_ / "one" / "particles.vtp").find("Name=\"material\""), std::string::npos);
  const auto summary = nlohmann::json::parse(std::ifstream(dir_ / "one" / "summary.json"));
  EXPECT_FALSE(summary.at("scenario").contains("materials"));
  EXPECT_EQ(summary.at("bulk_density").at("particle_density_kg_m3"), summary.at("scenario").at("material").at("density_kg_m3"));
}

}  // namespace

namespace {

// A run's particles.csv read back as the bed of another scenario keeps each sphere's material
// (its material column, by name), and one that names a material the scenario lacks is refused.
TEST_F(CliMaterials, AParticleFileNamesItsSpheresMaterials) {
  std::ofstream(dir_ / "two.toml") << kTwoMaterials;
  ASSERT_EQ(run_cli("run " + (dir_ / "two.toml").string() + " --quiet --threads 1 --out " + (dir_ / "two").string())
                .exit_code,
            0);
  const std::string file = (dir_ / "two" / "particles.csv").string();
  const std::string bed = "seed = 1\n[container]\nside = 0.03\nheight = 0.2\n[particles]\nfrom = \"" + file +
                          "\"\n[analysis]\nbox_sides = [0.005]\n";
  std::ofstream(dir_ / "again.toml") << bed << "[materials.stone]\ndensity = 3000\n[materials.sand]\ndensity = 1500\n";
  const auto again = run_cli("run " + (dir_ / "again.toml").string() + " --quiet --out " + (dir_ / "again").string());
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_EQ(slurp(dir_ / "again" / "particles.csv"), slurp(dir_ / "two" / "particles.csv"));
  const auto first = nlohmann::json::parse(slurp(dir_ / "two" / "summary.json"));
  const auto second = nlohmann::json::parse(slurp(dir_ / "again" / "summary.json"));
  EXPECT_DOUBLE_EQ(second.at("bulk_density").at("particle_density_kg_m3").get<double>(),
                   first.at("bulk_density").at("particle_density_kg_m3").get<double>());
  std::ofstream(dir_ / "lacking.toml") << bed << "[materials.stone]\ndensity = 3000\n";
  const auto lacking = run_cli("run " + (dir_ / "lacking.toml").string() + " --quiet --out " + (dir_ / "lacking").string());
  EXPECT_EQ(lacking.exit_code, 2) << lacking.output;
  EXPECT_NE(lacking.output.find("is of material \"sand\", which the scenario does not name"), std::string::npos)
      << lacking.output;
  EXPECT_FALSE(fs::exists(dir_ / "lacking" / "particles.csv"));
}

}  // namespace
