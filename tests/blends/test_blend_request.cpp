// The blends asked of material files: which route each material's betas take, and a prediction
// that simulates nothing (predict): a warm cache's simulated betas, else the lab number's, said.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "aggpack/blends/blend_request.hpp"
#include "aggpack/blends/material_sweep.hpp"
#include "aggpack/core/error.hpp"

namespace aggpack {
namespace {

namespace fs = std::filesystem;
const fs::path kMaterials = fs::path(AGGPACK_EXAMPLES) / "materials";

class BlendRequests : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("aggpack_request_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  // The shipped stone as `aggpack calibrate --test` would leave it: calibrated, its lab number kept.
  fs::path calibrated_stone() const {
    const fs::path file = dir_ / "stone_calibrated.toml";
    fs::copy_file(kMaterials / "crushed_stone_19mm.csv", dir_ / "crushed_stone_19mm.csv");  // its sieve file
    std::ifstream in(kMaterials / "crushed_stone_19mm.toml");
    std::stringstream text;
    text << in.rdbuf();
    std::ofstream(file) << text.str()
                        << "\n[calibration]\ntest = \"c29\"\nmethod = \"rodding\"\n"
                           "[calibration.contact]\nfriction_particle = 0.62\n";
    return file;
  }
  BlendRequest request(const fs::path& stone) const {
    BlendRequest r;
    r.materials = {stone, kMaterials / "natural_sand.toml"};
    r.fractions = {{0.6, 0.4}};
    r.beds.cache_folder = dir_;
    r.beds.quiet = true;
    r.may_simulate = false;
    return r;
  }
  fs::path dir_;
};

TEST_F(BlendRequests, WithoutSimulationACalibratedMaterialWithAColdCacheTakesItsLabNumberAndSaysSo) {
  std::ostringstream log;
  const BlendResult b = predict_blends(request(calibrated_stone()), log);
  ASSERT_EQ(b.curves.size(), 1u);
  EXPECT_EQ(b.curves[0].route, "lab_test");
  bool said = false;
  for (const std::string& m : b.modelling) said = said || m.find("not in the cache") != std::string::npos;
  EXPECT_TRUE(said);
  // The same blend as the lab route asked for outright.
  BlendRequest lab = request(kMaterials / "crushed_stone_19mm.toml");
  lab.route = "lab";
  EXPECT_DOUBLE_EQ(predict_blends(lab, log).curves[0].points[0].packing, b.curves[0].points[0].packing);
}

TEST_F(BlendRequests, WithoutSimulationAWarmCacheGivesTheSimulatedBetasAndTheLabRouteBesideThem) {
  const fs::path stone = calibrated_stone();
  BlendRequest r = request(stone);
  // A cache as the beds would leave it, with betas unlike the lab route's: 0.60 for every class.
  MaterialBetas simulated = lab_route_betas(load_material_file(stone));
  simulated.route = BetaRoute::Simulation;
  for (ClassBeta& c : simulated.classes) c.beta = 0.60, c.beta_sd = 0.004;
  SimulatedBetaOptions o = r.beds;
  o.material = stone;
  write_beta_cache(beta_cache_file(o), beta_cache_key(load_material_file(stone), o), simulated, 1.0);
  std::ostringstream log;
  const BlendResult b = predict_blends(r, log);
  ASSERT_EQ(b.curves.size(), 2u);         // the answer, then the lab route beside it
  EXPECT_EQ(b.curves[0].route, "mixed");  // the stone simulated, the uncalibrated sand by its lab number
  EXPECT_EQ(b.curves[0].materials[0].route, BetaRoute::Simulation);
  EXPECT_DOUBLE_EQ(b.curves[0].materials[0].classes[0].beta, 0.60);
  EXPECT_EQ(b.curves[1].route, "lab_test");
  // Lower betas of the stone, a looser blend; the band is the betas' sd.
  EXPECT_LT(b.curves[0].points[0].packing, b.curves[1].points[0].packing);
  EXPECT_LT(b.curves[0].points[0].packing_low, b.curves[0].points[0].packing);
}

TEST_F(BlendRequests, WithoutSimulationNoBetasIsAnErrorSayingHowToGetThem) {
  BlendRequest r = request(calibrated_stone());
  r.route = "simulation";
  std::ostringstream log;
  try {
    predict_blends(r, log);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("stone_calibrated.betas.json"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("aggpack blend"), std::string::npos) << e.what();
  }
  BlendRequest beads = request(kMaterials / "glass_beads_11mm.toml");  // no lab number, not calibrated
  EXPECT_THROW(predict_blends(beads, log), InputError);
}

TEST_F(BlendRequests, BadRequestsAreRefusedBeforeAnyBed) {
  BlendRequest r = request(kMaterials / "crushed_stone_19mm.toml");
  r.fractions = {{0.6, 0.3}};
  EXPECT_THROW(check_blend_request(r), InputError);
  r.fractions = {{0.6, 0.2, 0.2}};
  EXPECT_THROW(check_blend_request(r), InputError);
  r.fractions.clear();
  r.sweep_percents = {20.0, 120.0};
  EXPECT_THROW(check_blend_request(r), InputError);
  r.sweep_percents = {20.0};
  r.route = "guess";
  EXPECT_THROW(check_blend_request(r), InputError);
  EXPECT_THROW(blend_process("tamped", "--process"), InputError);
  EXPECT_DOUBLE_EQ(blend_process("loose", "--process").compaction_index, 4.1);
}

TEST_F(BlendRequests, ASweepOfMaterialsMarksEveryDensityPredictedAndNamesTheCalibrations) {
  MaterialSweepOptions o;
  o.blend = request(calibrated_stone());
  o.blend.fractions.clear();
  o.blend.sweep_percents = {20, 30, 40, 50};
  o.check_percents = {150};
  std::ostringstream log;
  EXPECT_THROW(sweep_materials(o, log), InputError);  // a check percent refused before the curve
  o.check_percents.clear();
  const MaterialSweep s = sweep_materials(o, log);
  const nlohmann::json j = to_json(s);
  ASSERT_EQ(j["points"].size(), 4u);
  double best = 0.0;
  for (const nlohmann::json& p : j["points"]) {
    EXPECT_EQ(p["source"], "predicted");
    best = std::max(best, p["density"].get<double>());
  }
  EXPECT_DOUBLE_EQ(j["best"]["density"].get<double>(), best);
  EXPECT_TRUE(j["checked_points"].empty());
  EXPECT_EQ(j["materials"][0]["calibration"]["test"], "c29");
  EXPECT_TRUE(j["materials"][1]["calibration"].is_null());
  const std::string csv = sweep_csv(s);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 5);
  EXPECT_NE(csv.find("40,predicted,"), std::string::npos) << csv;
}

}  // namespace
}  // namespace aggpack
