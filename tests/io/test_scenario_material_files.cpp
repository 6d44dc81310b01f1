// A scenario's materials given by material files: [materials.NAME] file = ..., [material] file = ...
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "aggpack/core/error.hpp"
#include "aggpack/io/material_file.hpp"
#include "aggpack/io/scenario.hpp"

namespace aggpack {
namespace {

namespace fs = std::filesystem;

constexpr const char* kStone = R"(name = "stone"
specific_gravity = 2.60
[grading]
file = "stone.csv"
[shape]
default = "gravel"
[contact]
friction_particle = 0.6
rolling_friction = 0.1
)";

constexpr const char* kHead = R"([container]
side = "0.2 m"
height = "0.4 m"
[deposition]
)";

class ScenarioMaterialFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("aggpack_scenario_material_" + std::to_string(::getpid()));
    fs::create_directories(dir_ / "materials");
    // The CSV is beside the material file, not beside the scenario: its path is the material file's.
    std::ofstream(dir_ / "materials/stone.csv") << "sieve,opening_mm,percent_passing\n3/4in,19,100\n1/2in,12.5,50\n"
                                                   "3/8in,9.5,0\n";
    std::ofstream(dir_ / "materials/stone.toml") << kStone;
  }
  void TearDown() override { fs::remove_all(dir_); }
  Scenario load(const std::string& text) {
    const fs::path f = dir_ / "s.toml";
    std::ofstream(f) << text;
    return load_scenario(f);
  }
  std::string refusal(const std::string& text) {
    try {
      load(text);
    } catch (const InputError& e) {
      return e.what();
    }
    ADD_FAILURE() << "accepted";
    return "";
  }
  fs::path dir_;
};

TEST_F(ScenarioMaterialFileTest, ANamedMaterialTakesTheFilesDensityAndContactAndAComponentItsGradingAndShape) {
  const Scenario sc = load(std::string(kHead) + R"([material]
friction_particle = 0.2
[materials.stone]
file = "materials/stone.toml"
restitution = 0.3
[particles]
count = 50
[particles.grading]
material = "stone"
)");
  ASSERT_EQ(sc.materials.size(), 1u);
  const Material& stone = sc.materials[0].material;
  EXPECT_DOUBLE_EQ(stone.density, 2.60 * kWaterDensityAt23C);  // the oven-dry particle density
  EXPECT_DOUBLE_EQ(stone.contact.friction_particle, 0.6);      // the file's, over [material]'s
  EXPECT_DOUBLE_EQ(stone.contact.rolling_friction, 0.1);
  EXPECT_DOUBLE_EQ(stone.contact.restitution, 0.3);            // the table's own key, over the file
  EXPECT_EQ(stone.file, "materials/stone.toml");
  EXPECT_DOUBLE_EQ(sc.material.contact.friction_particle, 0.2);  // [material] keeps its own
  // The component took the material's grading (the CSV beside the material file) and shape.
  const auto& graded = *sc.particles.graded;
  ASSERT_EQ(graded.main.grading.sieves.size(), 3u);
  EXPECT_DOUBLE_EQ(graded.main.grading.largest(), 0.019);
  ASSERT_EQ(sc.particles.component_shape.size(), 1u);
  ASSERT_TRUE(sc.particles.component_shape[0]);
  EXPECT_EQ(sc.particles.component_shape[0]->family, GrainFamily::Rounded);
  EXPECT_EQ(sc.particles.material_of_component(0), 1);
  EXPECT_EQ(to_json(sc)["materials"]["stone"]["file"], "materials/stone.toml");
}

TEST_F(ScenarioMaterialFileTest, AComponentsOwnGradingAndCutOffsStayItsOwn) {
  const Scenario sc = load(std::string(kHead) + R"([materials.stone]
file = "materials/stone.toml"
[particles]
count = 50
ca_fa = 1.5
[particles.coarse]
material = "stone"
d_min = "10 mm"
[particles.fine]
material = "stone"
name = "astm_c33_fine_mid"
)");
  const auto& graded = *sc.particles.graded;
  EXPECT_DOUBLE_EQ(graded.main.grading.largest(), 0.019);  // the material's grading, cut at the component's d_min
  EXPECT_DOUBLE_EQ(*graded.main.d_min, 0.010);
  EXPECT_EQ(graded.fine->grading.name, "astm_c33_fine_mid");  // its own grading: nothing of the file's
  EXPECT_TRUE(sc.particles.component_shape[0]);
  EXPECT_FALSE(sc.particles.component_shape[1]);
  EXPECT_DOUBLE_EQ(sc.materials[0].material.density, 2.60 * kWaterDensityAt23C);
}

TEST_F(ScenarioMaterialFileTest, MaterialZeroByFile) {
  const Scenario sc = load(std::string(kHead) + R"([material]
file = "materials/stone.toml"
wall_youngs_modulus = 1e9
[particles]
diameter = 0.01
count = 10
)");
  EXPECT_DOUBLE_EQ(sc.material.density, 2.60 * kWaterDensityAt23C);
  EXPECT_DOUBLE_EQ(sc.material.contact.friction_particle, 0.6);
  EXPECT_DOUBLE_EQ(sc.material.contact.wall_youngs_modulus, 1e9);
  EXPECT_FALSE(sc.particles.component_shape[0]);  // a monosized bed takes density and contact only
}

TEST_F(ScenarioMaterialFileTest, InlineMaterialsReadAsBefore) {
  const Scenario sc = load(std::string(kHead) + R"([materials.sand]
density = 2500
friction_particle = 0.3
[particles]
diameter = 0.01
count = 10
material = "sand"
)");
  EXPECT_DOUBLE_EQ(sc.materials[0].material.density, 2500.0);
  EXPECT_TRUE(sc.materials[0].material.file.empty());
  EXPECT_FALSE(to_json(sc)["materials"]["sand"].contains("file"));
}

TEST_F(ScenarioMaterialFileTest, RefusalsNameTheScenarioKeyAndTheMaterialFile) {
  const std::string particles = "[particles]\ndiameter = 0.01\ncount = 10\nmaterial = \"stone\"\n";
  std::string msg = refusal(std::string(kHead) + "[materials.stone]\nfile = \"materials/stone.toml\"\ndensity = 2700\n" +
                            particles);
  EXPECT_NE(msg.find("materials.stone.density"), std::string::npos) << msg;
  EXPECT_NE(msg.find("the density is the material file's"), std::string::npos) << msg;
  msg = refusal(std::string(kHead) + "[materials.stone]\nfile = \"materials/none.toml\"\n" + particles);
  EXPECT_NE(msg.find("materials.stone.file"), std::string::npos) << msg;
  EXPECT_NE(msg.find("none.toml"), std::string::npos) << msg;
  std::ofstream(dir_ / "materials/bad.toml") << "specific_gravity = 10\n[grading]\nname = \"astm_c33_67_mid\"\n";
  msg = refusal(std::string(kHead) + "[materials.stone]\nfile = \"materials/bad.toml\"\n" + particles);
  EXPECT_NE(msg.find("s.toml:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("materials.stone.file"), std::string::npos) << msg;
  EXPECT_NE(msg.find("bad.toml:1"), std::string::npos) << msg;
  EXPECT_NE(msg.find("expected 1 to 5"), std::string::npos) << msg;
}

TEST_F(ScenarioMaterialFileTest, ANamedShapeInAComponentsShapeTable) {
  const Scenario sc = load(std::string(kHead) + R"([particles]
count = 50
[particles.grading]
name = "astm_c33_67_mid"
shape = { default = "crushed_stone", spheres = 4 }
)");
  ASSERT_TRUE(sc.particles.component_shape[0]);
  EXPECT_EQ(sc.particles.component_shape[0]->family, GrainFamily::Angular);
  EXPECT_EQ(sc.particles.component_shape[0]->spheres, 4u);
}

}  // namespace
}  // namespace aggpack
