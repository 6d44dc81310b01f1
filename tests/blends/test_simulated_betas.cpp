// The simulation route: the beds' scenarios, the cache (warm, stale, damaged) and one small
// material simulated end to end, then read back from its cache without simulating.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "aggpack/blends/simulated_betas.hpp"
#include "aggpack/core/error.hpp"
#include "aggpack/core/version.hpp"
#include "aggpack/labtests/class_bed.hpp"

namespace aggpack {
namespace {

const std::filesystem::path kMaterials = std::filesystem::path(AGGPACK_EXAMPLES) / "materials";

class SimulatedBetas : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("aggpack_betas_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  SimulatedBetaOptions options(const std::string& material) const {
    SimulatedBetaOptions o;
    o.material = kMaterials / material;
    o.cache_folder = dir_;
    o.quiet = true;
    return o;
  }
  std::filesystem::path dir_;
};

MaterialBetas some_betas() {
  MaterialBetas b;
  b.file = "m.toml";
  b.material = "m";
  b.route = BetaRoute::Simulation;
  b.source = "test";
  b.particle_density_kg_m3 = 2500;
  b.classes.push_back({0.0095, 0.0125, 0.0109, 1.0, 0.77, 0.002, {0.62, 0.621}});
  return b;
}

TEST_F(SimulatedBetas, CacheIsReadBackOnlyForItsOwnKey) {
  const AggregateMaterial m = load_material_file(kMaterials / "glass_beads_11mm.toml");
  const SimulatedBetaOptions o = options("glass_beads_11mm.toml");
  const nlohmann::json key = beta_cache_key(m, o);
  EXPECT_EQ(key["aggpack_version"], kVersion);
  const std::filesystem::path file = beta_cache_file(o);
  std::string stale;
  EXPECT_FALSE(read_beta_cache(file, key, stale));
  EXPECT_EQ(stale, "no cache yet");

  write_beta_cache(file, key, some_betas(), 1.0);
  const std::optional<MaterialBetas> warm = read_beta_cache(file, key, stale);
  ASSERT_TRUE(warm);
  EXPECT_DOUBLE_EQ(warm->classes.at(0).beta, 0.77);
  EXPECT_EQ(warm->classes.at(0).packing.size(), 2u);

  nlohmann::json other = key;
  other["aggpack_version"] = "0.0.1+git.0";
  EXPECT_FALSE(read_beta_cache(file, other, stale));
  EXPECT_NE(stale.find("0.0.1+git.0"), std::string::npos) << stale;
  other = key;
  other["material"]["contact"]["friction_particle"] = 0.3;
  EXPECT_FALSE(read_beta_cache(file, other, stale));
  EXPECT_EQ(stale, "its material changed");
  SimulatedBetaOptions more_seeds = o;
  more_seeds.seeds = 4;
  EXPECT_FALSE(read_beta_cache(file, beta_cache_key(m, more_seeds), stale));
  EXPECT_EQ(stale, "its settings changed");
  // Other settings of the same build and material are kept beside it; another build's are not.
  MaterialBetas four = some_betas();
  four.classes[0].beta = 0.78;
  write_beta_cache(file, beta_cache_key(m, more_seeds), four, 1.0);
  EXPECT_DOUBLE_EQ(read_beta_cache(file, key, stale)->classes.at(0).beta, 0.77);
  EXPECT_DOUBLE_EQ(read_beta_cache(file, beta_cache_key(m, more_seeds), stale)->classes.at(0).beta, 0.78);
  nlohmann::json newer = key;
  newer["aggpack_version"] = "9.9.9+git.1";
  write_beta_cache(file, newer, some_betas(), 1.0);
  EXPECT_FALSE(read_beta_cache(file, key, stale));
  EXPECT_TRUE(read_beta_cache(file, newer, stale));
}

TEST_F(SimulatedBetas, DamagedCacheIsRefusedNamingTheFile) {
  const AggregateMaterial m = load_material_file(kMaterials / "glass_beads_11mm.toml");
  const SimulatedBetaOptions o = options("glass_beads_11mm.toml");
  const nlohmann::json key = beta_cache_key(m, o);
  const std::filesystem::path file = beta_cache_file(o);
  write_beta_cache(file, key, some_betas(), 1.0);
  std::stringstream text;
  text << std::ifstream(file).rdbuf();
  const std::string whole = text.str();
  for (const std::string& damaged : {whole.substr(0, whole.size() / 2), std::string("not json"),
                                     // a beta out of range, behind a key that matches
                                     [&] {
                                       nlohmann::json j = nlohmann::json::parse(whole);
                                       j["entries"][0]["betas"]["classes"][0]["beta"] = 1.5;
                                       return j.dump();
                                     }(),
                                     [&] {
                                       nlohmann::json j = nlohmann::json::parse(whole);
                                       j["entries"][0]["betas"]["classes"][0].erase("beta_sd");
                                       return j.dump();
                                     }()}) {
    std::ofstream(file, std::ios::trunc) << damaged;
    std::string stale;
    try {
      read_beta_cache(file, key, stale);
      ADD_FAILURE() << "accepted: " << damaged.substr(0, 80);
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
    }
  }
}

TEST_F(SimulatedBetas, BedsAreRunnableScenarios) {
  const AggregateMaterial stone = load_material_file(kMaterials / "crushed_stone_12mm_single.toml");
  const ClassBed bed = class_bed({&stone, 9.5e-3, 12.5e-3, LabTestKind::C29, "rodding", 3000});
  EXPECT_EQ(bed.procedure, "rodded");
  const Scenario sc = parse_scenario(bed.scenario_text, kMaterials / "bed.toml");
  EXPECT_TRUE(sc.container.periodic);
  // A fine fraction's bed is too narrow for C29's rod: poured instead, and said.
  const ClassBed fine = class_bed({&stone, 1.18e-3, 2.36e-3, LabTestKind::C29, "rodding", 3000});
  EXPECT_EQ(fine.procedure, "poured");
  EXPECT_NE(fine.scenario_text.find("narrower than"), std::string::npos);

  const AggregateMaterial beads = load_material_file(kMaterials / "glass_beads_11mm.toml");
  const AggregateMaterial grit = load_material_file(kMaterials / "glass_grit_3mm.toml");
  const ClassBed blend = blend_bed({&beads, &grit, 0.4, 0.0, LabTestKind::C29, "shovelling", 300});
  const Scenario b = parse_scenario(blend.scenario_text, kMaterials / "blend.toml");
  EXPECT_TRUE(b.container.periodic);
  ASSERT_TRUE(b.particles.graded);
  EXPECT_NEAR(b.particles.graded->ca_fa, 0.6 / 0.4, 1e-12);  // spheres: the volumes as they are
  EXPECT_THROW(class_bed({&stone, 2e-3, 1e-3, LabTestKind::C29, "rodding", 3000}), InputError);
  EXPECT_THROW(class_bed({&stone, 1e-3, 2e-3, LabTestKind::C29, "tamping", 3000}), InputError);
}

TEST_F(SimulatedBetas, SmallSpheresSimulatedOnceThenFromTheCache) {
  SimulatedBetaOptions o = options("glass_beads_11mm.toml");
  o.seeds = 2;
  o.particles = 200;
  o.threads = 1;
  o.quiet = false;
  std::ostringstream first, second;
  const MaterialBetas b = simulated_betas(o, first);
  EXPECT_NE(first.str().find("simulating the betas"), std::string::npos) << first.str();
  ASSERT_EQ(b.classes.size(), 1u);
  ASSERT_EQ(b.classes[0].packing.size(), 2u);
  // Spheres poured from 50 mm in a periodic bed: random loose to close packing.
  for (const double phi : b.classes[0].packing) {
    EXPECT_GT(phi, 0.57);
    EXPECT_LT(phi, 0.65);
  }
  EXPECT_NEAR(b.classes[0].beta, (b.classes[0].packing[0] + b.classes[0].packing[1]) / 2 * (1 + 1 / 4.1), 1e-12);
  const MaterialBetas again = simulated_betas(o, second);
  EXPECT_NE(second.str().find("from the cache"), std::string::npos) << second.str();
  EXPECT_EQ(again.classes[0].beta, b.classes[0].beta);
}

}  // namespace
}  // namespace aggpack
