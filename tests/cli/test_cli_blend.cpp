// `aggpack blend`, as a user meets it: a stone and a sand by their lab numbers give a curve in
// the lab's units, its table, JSON and plot; bad input is refused before any work, and a
// damaged cache of betas is an error naming it, never a different curve.
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

class CliBlend : public ::testing::Test {
 protected:
  aggpack::testing::ScratchDir scratch_{"aggpack_cli_blend_"};
  const fs::path& dir_ = scratch_.path();
};

const fs::path kMaterials = fs::path(AGGPACK_EXAMPLES) / "materials";
const std::string kStoneAndSand =
    (kMaterials / "crushed_stone_19mm.toml").string() + " " + (kMaterials / "natural_sand.toml").string();

TEST_F(CliBlend, AStoneAndASandByTheirLabNumbersGiveACurveWithItsDensestBlend) {
  const fs::path out = dir_ / "blend";
  const auto r = run_cli("blend " + kStoneAndSand + " --sweep 20:60:1 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("densest:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("predicted, not simulated"), std::string::npos) << r.output;
  const nlohmann::json s = nlohmann::json::parse(slurp(out / "blend.json"));
  EXPECT_EQ(s["kind"], "aggpack blend");
  EXPECT_EQ(s["process"], "rodded");
  EXPECT_DOUBLE_EQ(s["compaction_index"].get<double>(), 4.5);
  ASSERT_EQ(s["curves"].size(), 1u);  // no simulated betas: the lab route alone
  const nlohmann::json& curve = s["curves"][0];
  EXPECT_EQ(curve["route"], "lab_test");
  ASSERT_EQ(curve["points"].size(), 41u);
  double best = 0.0;
  for (const nlohmann::json& p : curve["points"]) {
    best = std::max(best, p["packing_density"].get<double>());
    EXPECT_NEAR(p["bulk_density_kg_m3"].get<double>(),
                p["packing_density"].get<double>() * p["particle_density_kg_m3"].get<double>(), 1e-6);
  }
  EXPECT_DOUBLE_EQ(curve["densest"]["point"]["packing_density"].get<double>(), best);
  const double at = curve["densest"]["second_volume_percent"];
  EXPECT_GE(at, curve["densest"]["plateau_percent"][0].get<double>());
  EXPECT_LE(at, curve["densest"]["plateau_percent"][1].get<double>());
  // A stone and a sand pack denser together than the stone alone at its lab packing.
  EXPECT_GT(best, 0.65);
  EXPECT_NE(slurp(out / "blend.svg").find("<svg"), std::string::npos);
  for (const nlohmann::json& m : curve["materials"]) EXPECT_FALSE(m["modelling"].empty());
}

TEST_F(CliBlend, FractionsGiveThoseBlendsAlone) {
  const auto r = run_cli("blend " + kStoneAndSand + " --fractions 0.6,0.4 --fractions 0.5,0.5 --process loose --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json s = nlohmann::json::parse(r.output.substr(r.output.find('{')));
  EXPECT_EQ(s["process"], "poured");
  ASSERT_EQ(s["curves"][0]["points"].size(), 2u);
  EXPECT_FALSE(s["curves"][0].contains("densest"));
}

TEST_F(CliBlend, BadInputIsRefusedBeforeAnyWork) {
  const fs::path out = dir_ / "never";
  struct Case {
    std::string args, expected;
  };
  const Case cases[] = {
      {kStoneAndSand + " --sweep 20:60", "FROM:TO:STEP"},
      {kStoneAndSand + " --fractions 0.6,0.3", "sum to"},
      {kStoneAndSand + " --fractions 0.6,x", "'x' is not a number"},
      {kStoneAndSand, "--sweep FROM:TO:STEP"},
      {kStoneAndSand + " --sweep 20:60:1 --process tamped", "--process tamped"},
      {kStoneAndSand + " --sweep 20:60:1 --route magic", "--route magic"},
      {(kMaterials / "gravel_12mm_single.toml").string() + " " + (kMaterials / "natural_sand.toml").string() +
           " --sweep 20:60:1 --route lab",
       "gravel_12mm_single.toml: the material has no lab number"},
      {kStoneAndSand + " --sweep 20:60:1 --route simulation --beds c29:tamping", "--beds c29:tamping"},
      {kStoneAndSand + " --sweep 20:60:1 --check 40 --check-cut wide", "--check-cut wide"},
      {kStoneAndSand + " --check 40,x", "--check 40,x: 'x' is not a number"},
      {(kMaterials / "glass_beads_11mm.toml").string() + " " + (kMaterials / "glass_grit_3mm.toml").string() +
           " --route simulation --sweep 20:60:1 --check 0 --betas-cache " + (dir_ / "none").string(),
       "--check 0: 0 is not a percent"},
      {kStoneAndSand + " --sweep 20:60:1 --interaction 1.02", "--interaction 1.02"},
      {kStoneAndSand + " --sweep 20:60:1 --fit-interaction", "--fit-interaction"},
  };
  for (const Case& c : cases) {
    const auto r = run_cli("blend " + c.args + " --out " + out.string());
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << c.args << "\n" << r.output;
    EXPECT_FALSE(fs::exists(out / "blend.json")) << c.args;
  }
}

TEST_F(CliBlend, ADamagedCacheOfBetasIsAnErrorNamingIt) {
  fs::create_directories(dir_ / "cache");
  std::ofstream(dir_ / "cache" / "glass_beads_11mm.betas.json") << "{\"kind\": \"aggpack betas\", \"key\": 3";
  const auto r = run_cli("blend " + (kMaterials / "glass_beads_11mm.toml").string() + " " +
                         (kMaterials / "glass_grit_3mm.toml").string() +
                         " --sweep 20:60:1 --route simulation --betas-cache " + (dir_ / "cache").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("glass_beads_11mm.betas.json: a damaged betas cache"), std::string::npos) << r.output;
}

TEST_F(CliBlend, ASweepOfTwoMaterialsIsTheBlendsCurveEveryPointPredicted) {
  const fs::path out = dir_ / "sweep";
  const auto r = run_cli("sweep " + kStoneAndSand + " --fa 20:60:10 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json s = nlohmann::json::parse(slurp(out / "sweep.json"));
  const auto b = run_cli("blend " + kStoneAndSand + " --sweep 20:60:10 --json");
  ASSERT_EQ(b.exit_code, 0) << b.output;
  const nlohmann::json blend = nlohmann::json::parse(b.output.substr(b.output.find('{')));
  ASSERT_EQ(s["points"].size(), 5u);
  for (std::size_t i = 0; i < 5; ++i) {  // the same prediction as `aggpack blend`'s
    EXPECT_EQ(s["points"][i]["source"], "predicted");
    EXPECT_DOUBLE_EQ(s["points"][i]["fa_percent"].get<double>(), 20.0 + 10.0 * i);
    EXPECT_DOUBLE_EQ(s["points"][i]["density"].get<double>(),
                     blend["curves"][0]["points"][i]["packing_density"].get<double>());
  }
  EXPECT_TRUE(s["checked_points"].empty());  // no --check: no DEM
  EXPECT_NE(slurp(out / "sweep.csv").find("40,predicted,"), std::string::npos);
  EXPECT_NE(slurp(out / "sweep.svg").find("<svg"), std::string::npos);
  // predict of the same two materials at 40 % sand (Ca/Fa 1.5): the same number again.
  const auto p = run_cli("predict " + (kMaterials / "crushed_stone_19mm.toml").string() + " --mix " +
                         (kMaterials / "natural_sand.toml").string() + " --ca-fa 1.5 --json");
  ASSERT_EQ(p.exit_code, 0) << p.output;
  const nlohmann::json predicted = nlohmann::json::parse(p.output.substr(p.output.find('{')));
  EXPECT_NEAR(predicted["curves"][0]["points"][0]["packing_density"].get<double>(),
              s["points"][2]["density"].get<double>(), 1e-12);
}

TEST_F(CliBlend, SweepAndPredictOfMaterialsRefuseAScenarioOptionsAndBadChecks) {
  const fs::path out = dir_ / "never";
  const std::string stone = (kMaterials / "crushed_stone_19mm.toml").string();
  struct Case {
    std::string args, expected;
  };
  const Case cases[] = {
      {"sweep " + kStoneAndSand + " --fa 20:60:10 --set seed=3", "--set is a scenario's option"},
      {"sweep " + kStoneAndSand + " --fa 20:60:10 --check 150", "150 is not a percent"},
      {"sweep " + kStoneAndSand + " --fa 20:60:10 --process tamped", "--process tamped"},
      {"sweep " + (fs::path(AGGPACK_EXAMPLES) / "example1.toml").string() + " --fa 20:60:10 --check 30",
       "--check is a sweep of two materials' option"},
      {"predict " + stone + " --beta 0.7", "--beta is for a scenario or a grading"},
      {"predict " + kStoneAndSand.substr(0, kStoneAndSand.find(' ')) + " --mix " +
           (kMaterials / "natural_sand.toml").string(),
       "--ca-fa is missing"},
      {"predict " + stone + " --mix astm_c33_fine_mid --ca-fa 1.5", "expected a material file"},
  };
  for (const Case& c : cases) {
    const auto r = run_cli(c.args + (c.args.starts_with("sweep") ? " --out " + out.string() : ""));
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << c.args << "\n" << r.output;
    EXPECT_FALSE(fs::exists(out / "sweep.json")) << c.args;
  }
}

// A small case of the validation's check (docs/validation.md, "Blends: predicted against
// simulated"): glass beads with beads half their size (few enough fines for the CI), 40 % fines,
// two seeds of small beds. The numbers
// it checks are the physics' (a binary blend packs denser than either size alone) and the
// bookkeeping's (the prediction is CPM of the betas written beside it, read back the same).
class CliBlendCheck : public CliBlend {};

TEST_F(CliBlendCheck, ASmallBinaryBlendOfSpheresAgainstItsPrediction) {
  const fs::path out = dir_ / "check", fine = dir_ / "glass_beads_5mm.toml";
  std::ofstream(fine) << "name = \"Glass beads, 4.75-6.3 mm\"\nspecific_gravity = 2.50\n[grading]\n"
                         "sieves = [{ opening = \"4.75 mm\", passing = 0 }, { opening = \"6.3 mm\", passing = 100 }]\n"
                         "[contact]\nfriction_particle = 0.15\nfriction_wall = 0.15\nrestitution = 0.6\n";
  const auto r = run_cli("blend " + (kMaterials / "glass_beads_11mm.toml").string() + " " + fine.string() +
                         " --route simulation --fractions 0.6,0.4 --check 40 --seeds 2 --bed-particles 300"
                         " --check-particles 40 --threads 2 --betas-cache " +
                         (dir_ / "cache").string() + " --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json s = nlohmann::json::parse(slurp(out / "blend.json"));
  const nlohmann::json& check = s["check"];
  ASSERT_EQ(check["points"].size(), 1u);
  const nlohmann::json& point = check["points"][0];
  ASSERT_EQ(point["simulated"].size(), 2u);
  // Each size alone packs at 0.60-0.64 poured; together they pack denser.
  for (const nlohmann::json& m : {check["coarse"], check["fine"]})
    for (const nlohmann::json& phi : m["classes"][0]["packing"]) EXPECT_LT(phi.get<double>(), 0.645);
  EXPECT_GT(point["simulated_mean"].get<double>(), 0.645);
  // The prediction at the curve's 40 % and the check's agree when the process is the beds'.
  EXPECT_NEAR(point["predicted"].get<double>(), point["predicted_published_interaction"].get<double>(), 1e-15);
  EXPECT_NEAR(check["largest_difference"].get<double>(),
              std::abs(point["predicted"].get<double>() - point["simulated_mean"].get<double>()), 1e-15);
  // CPM with de Larrard's exponents is within a few hundredths of the DEM here (the validation's
  // seven points: 0.005 to 0.033, docs/validation.md).
  EXPECT_LT(check["largest_difference"].get<double>(), 0.05);
  // Read back, the check predicts the same; the betas are now cached (no bed simulated again).
  const auto again = run_cli("blend " + (kMaterials / "glass_beads_11mm.toml").string() + " " + fine.string() +
                             " --checked " + (out / "blend.json").string() + " --json");
  ASSERT_EQ(again.exit_code, 0) << again.output;
  const nlohmann::json back = nlohmann::json::parse(again.output.substr(again.output.find('{')));
  EXPECT_DOUBLE_EQ(back["checked"][0]["points"][0]["predicted"].get<double>(), point["predicted"].get<double>());
}

}  // namespace
