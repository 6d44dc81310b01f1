#include "aggpack/io/material_file.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "aggpack/core/error.hpp"
#include "aggpack/grains/named_shapes.hpp"
#include "aggpack/sizes/grading.hpp"

namespace aggpack {
namespace {

namespace fs = std::filesystem;

// Every key of a material file.
constexpr const char* kFull = R"(name = "Crushed limestone, 19 mm"
notes = "quarry A, lot 7"
specific_gravity = 2.70
specific_gravity_basis = "ssd"
absorption_percent = 2.0
[grading]
file = "stone.csv"
d_max = "25 mm"
band = "astm_c33_67"
[shape]
default = "crushed_stone"
templates = 6
[contact]
friction_particle = 0.55
friction_wall = 0.3
rolling_friction = 0.05
restitution = 0.35
youngs_modulus = 30e9
poisson_ratio = 0.2
[lab.c29]
bulk_density = "98.6 lb/ft3"
method = "jigging"
[lab.c1252]
voids_percent = 44.5
method = "B"
[calibration]
rolling_friction = 0.07
runs = [1, 2]
)";

constexpr const char* kMinimal = R"(specific_gravity = 2.65
[grading]
name = "astm_c33_67_mid"
)";

struct BadCase {
  const char* name;
  std::string text;
  std::vector<std::string> expected;  // parts of the message: the file, the key, what is expected
};

class MaterialFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("aggpack_material_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    std::ofstream(dir_ / "stone.csv") << "sieve,opening_mm,percent_passing\n1in,25,100\n3/4in,19,95\n1/2in,12.5,60\n"
                                         "3/8in,9.5,40\n#4,4.75,5\n#8,2.36,0\n";
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path write(const std::string& text, const std::string& name = "m.toml") {
    const fs::path f = dir_ / name;
    std::ofstream(f) << text;
    return f;
  }
  void expect_refused(const std::vector<BadCase>& cases) {
    for (const auto& c : cases) {
      try {
        load_material_file(write(c.text));
        ADD_FAILURE() << c.name << ": accepted";
      } catch (const InputError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("m.toml"), std::string::npos) << c.name << ": " << msg;
        for (const auto& part : c.expected) EXPECT_NE(msg.find(part), std::string::npos) << c.name << ": " << msg;
      }
    }
  }
  fs::path dir_;
};

TEST_F(MaterialFileTest, ReadsEveryKey) {
  const AggregateMaterial m = load_material_file(write(kFull));
  EXPECT_EQ(m.name, "Crushed limestone, 19 mm");
  EXPECT_EQ(m.notes, "quarry A, lot 7");
  EXPECT_DOUBLE_EQ(m.specific_gravity, 2.70);
  EXPECT_EQ(m.basis, SpecificGravityBasis::SaturatedSurfaceDry);
  EXPECT_DOUBLE_EQ(*m.absorption_percent, 2.0);
  // The grading from the CSV beside the file, with its cut-off and band.
  ASSERT_EQ(m.grading.grading.sieves.size(), 6u);
  EXPECT_DOUBLE_EQ(m.grading.grading.largest(), 0.025);
  EXPECT_DOUBLE_EQ(*m.grading.d_max, 0.025);
  EXPECT_EQ(m.grading.band->name, "astm_c33_67");
  // The named shape, refined by the keys beside it.
  ASSERT_TRUE(m.shape);
  EXPECT_EQ(m.shape_name, "crushed_stone");
  EXPECT_EQ(m.shape->family, GrainFamily::Angular);
  EXPECT_EQ(m.shape->templates, 6u);
  EXPECT_DOUBLE_EQ(m.shape->proportions.elongation_mean, named_grain_shape("crushed_stone")->proportions.elongation_mean);
  const ContactParameters& c = m.material.contact;
  EXPECT_DOUBLE_EQ(c.friction_particle, 0.55);
  EXPECT_DOUBLE_EQ(c.friction_wall, 0.3);
  EXPECT_DOUBLE_EQ(c.rolling_friction, 0.05);
  EXPECT_DOUBLE_EQ(c.restitution, 0.35);
  EXPECT_DOUBLE_EQ(c.youngs_modulus, 30e9);
  EXPECT_DOUBLE_EQ(c.poisson_ratio, 0.2);
  ASSERT_TRUE(m.c29 && m.c1252);
  EXPECT_EQ(m.c29->method, C29Method::Jigging);
  EXPECT_DOUBLE_EQ(m.c1252->percent, 44.5);
  EXPECT_EQ(m.c1252->method, C1252Method::B);
  EXPECT_DOUBLE_EQ(m.calibration["rolling_friction"].get<double>(), 0.07);
  EXPECT_EQ(m.calibration["runs"].size(), 2u);
}

TEST_F(MaterialFileTest, DefaultsOfAMinimalFile) {
  const AggregateMaterial m = parse_material_file(kMinimal, dir_ / "limestone.toml");
  EXPECT_EQ(m.name, "limestone");  // the file's stem
  EXPECT_EQ(m.basis, SpecificGravityBasis::OvenDry);
  EXPECT_FALSE(m.shape);
  EXPECT_EQ(m.shape_name, "spheres");
  EXPECT_FALSE(m.c29 || m.c1252);
  EXPECT_TRUE(m.calibration.is_null());
  EXPECT_DOUBLE_EQ(m.material.contact.friction_particle, ContactParameters{}.friction_particle);
}

TEST_F(MaterialFileTest, AShapeByFamilyHasNoName) {
  const AggregateMaterial m = parse_material_file(
      std::string(kMinimal) + "[shape]\nfamily = \"angular\"\nflatness = 0.5\nflakiness_index = 20\n", dir_ / "f.toml");
  ASSERT_TRUE(m.shape);
  EXPECT_EQ(m.shape_name, "");
  EXPECT_EQ(m.shape->family, GrainFamily::Angular);
  EXPECT_DOUBLE_EQ(m.shape->proportions.flatness_mean, 0.5);
  ASSERT_TRUE(m.shape->target);
  EXPECT_EQ(m.shape->target->measure, ShapeMeasure::FlakinessIndex);
  EXPECT_EQ(to_json(m)["shape"]["target"]["percent"], 20.0);
}

TEST_F(MaterialFileTest, OvenDrySpecificGravityAndParticleDensityByHand) {
  // SSD 2.70 with 2 % absorption: OD = 2.70 / 1.02 = 2.647059; x 997.5 kg/m3 (C127 at 23 C).
  const AggregateMaterial m = load_material_file(write(kFull));
  EXPECT_NEAR(oven_dry_specific_gravity(m), 2.6470588235, 1e-9);
  EXPECT_NEAR(oven_dry_particle_density(m), 2640.4411765, 1e-6);
  EXPECT_DOUBLE_EQ(m.material.density, oven_dry_particle_density(m));
  const AggregateMaterial od = parse_material_file(kMinimal, dir_ / "od.toml");
  EXPECT_DOUBLE_EQ(oven_dry_specific_gravity(od), 2.65);
  EXPECT_DOUBLE_EQ(oven_dry_particle_density(od), 2.65 * 997.5);
}

TEST_F(MaterialFileTest, BulkDensityUnitsConvert) {
  // 1 lb/ft3 = 0.45359237 kg / 0.028316846592 m3 = 16.018463374 kg/m3.
  EXPECT_NEAR(kKgPerM3PerLbPerFt3, 16.018463374, 1e-9);
  const AggregateMaterial m = load_material_file(write(kFull));
  EXPECT_NEAR(m.c29->kg_per_m3, 98.6 * 16.018463374, 1e-6);
  const std::string head = std::string(kMinimal) + "[lab.c29]\nmethod = \"rodding\"\nbulk_density = ";
  for (const auto& [given, expected] : std::vector<std::pair<std::string, double>>{{"1580", 1580.0},
                                                                                   {"1580.5", 1580.5},
                                                                                   {"\"1580 kg/m3\"", 1580.0},
                                                                                   {"\"1580kg/m^3\"", 1580.0},
                                                                                   {"\"1.58 t/m3\"", 1580.0},
                                                                                   {"\"1.58 g/cm3\"", 1580.0},
                                                                                   {"\"100 pcf\"", 1601.8463374},
                                                                                   {"\"100 lb/ft^3\"", 1601.8463374}})
    EXPECT_NEAR(parse_material_file(head + given + "\n", dir_ / "u.toml").c29->kg_per_m3, expected, 1e-6) << given;
}

TEST_F(MaterialFileTest, VoidsAgainstAHandCalculation) {
  // C29: voids = 100 [(S W) - B] / (S W), W = 998 kg/m3. S = 2.65, B = 1580:
  // S W = 2644.7; (2644.7 - 1580) / 2644.7 = 0.402579...
  const AggregateMaterial m = parse_material_file(kMinimal, dir_ / "v.toml");
  EXPECT_NEAR(voids_percent(m, 1580.0), 40.2579, 1e-4);
  EXPECT_NEAR(voids_percent(m, 2.65 * 998.0), 0.0, 1e-12);
  // SSD: S is the oven-dry value, 2.70 / 1.02.
  const AggregateMaterial ssd = load_material_file(write(kFull));
  EXPECT_NEAR(voids_percent(ssd, 1580.0), 100.0 * (1.0 - 1580.0 / (2.70 / 1.02 * 998.0)), 1e-10);
}

TEST_F(MaterialFileTest, RefusesWhatNoAggregateIs) {
  const std::string grading = "[grading]\nname = \"astm_c33_67_mid\"\n";
  const std::string c29 = "specific_gravity = 2.65\n" + grading + "[lab.c29]\nmethod = \"rodding\"\nbulk_density = ";
  const std::string c1252 = "specific_gravity = 2.65\n" + grading + "[lab.c1252]\nmethod = \"A\"\nvoids_percent = ";
  expect_refused({
      {"sg 0", "specific_gravity = 0\n" + grading, {"specific_gravity", "expected 1 to 5", "lightweight"}},
      {"sg 10", "specific_gravity = 10\n" + grading, {"specific_gravity", "expected 1 to 5", "heavyweight"}},
      {"sg missing", grading, {"specific_gravity", "missing required key", "the material file"}},
      {"ssd without absorption", "specific_gravity = 2.65\nspecific_gravity_basis = \"ssd\"\n" + grading,
       {"absorption_percent", "ssd"}},
      {"unknown basis", "specific_gravity = 2.65\nspecific_gravity_basis = \"dry\"\n" + grading,
       {"specific_gravity_basis", "oven_dry", "ssd"}},
      {"absorption 31", "specific_gravity = 2.65\nabsorption_percent = 31\n" + grading, {"absorption_percent", "30"}},
      {"absorption -1", "specific_gravity = 2.65\nabsorption_percent = -1\n" + grading, {"absorption_percent"}},
      {"bulk density of the solid", c29 + "2644.7\n", {"lab.c29.bulk_density", "at or above the density of the solid"}},
      {"bulk density above the solid", c29 + "\"170 lb/ft3\"\n", {"lab.c29.bulk_density", "at or above"}},
      {"bulk density too low", c29 + "500\n", {"lab.c29.bulk_density", "below 20 %"}},
      {"bulk density not a density", c29 + "\"1580 kg\"\n", {"lab.c29.bulk_density", "not a density", "lb/ft3"}},
      {"bulk density negative", c29 + "-1\n", {"lab.c29.bulk_density"}},
      {"c29 method", "specific_gravity = 2.65\n" + grading + "[lab.c29]\nbulk_density = 1580\nmethod = \"tamping\"\n",
       {"lab.c29.method", "shovelling", "rodding", "jigging"}},
      {"c29 method missing", "specific_gravity = 2.65\n" + grading + "[lab.c29]\nbulk_density = 1580\n",
       {"method", "missing required key"}},
      {"voids 120", c1252 + "120\n", {"lab.c1252.voids_percent"}},
      {"voids 0", c1252 + "0\n", {"lab.c1252.voids_percent"}},
      {"voids implausible", c1252 + "0.445\n", {"lab.c1252.voids_percent", "expected 25 to 65"}},
      {"voids implausible high", c1252 + "70\n", {"lab.c1252.voids_percent", "expected 25 to 65"}},
      {"c1252 method", "specific_gravity = 2.65\n" + grading + "[lab.c1252]\nvoids_percent = 44\nmethod = \"D\"\n",
       {"lab.c1252.method", "\"A\"", "\"B\"", "\"C\""}},
      {"unknown shape", "specific_gravity = 2.65\n" + grading + "[shape]\ndefault = \"pebbles\"\n",
       {"shape.default", "crushed_stone", "gravel", "natural_sand", "manufactured_sand"}},
      {"shape default and family",
       "specific_gravity = 2.65\n" + grading + "[shape]\ndefault = \"gravel\"\nfamily = \"angular\"\n",
       {"shape.family", "not both"}},
      {"grading missing", "specific_gravity = 2.65\n", {"grading", "missing required key"}},
      {"grading unknown", "specific_gravity = 2.65\n[grading]\nname = \"c33_99\"\n", {"grading.name", "unknown grading"}},
      {"grading file missing", "specific_gravity = 2.65\n[grading]\nfile = \"none.csv\"\n", {"grading.file", "none.csv"}},
      {"grading material", "specific_gravity = 2.65\n" + grading + "material = \"x\"\n", {"grading", "material"}},
      {"density in contact", "specific_gravity = 2.65\n" + grading + "[contact]\ndensity = 2700\n",
       {"contact", "density"}},
      {"rolling model in contact", "specific_gravity = 2.65\n" + grading + "[contact]\nrolling_model = \"spring_dashpot\"\n",
       {"contact", "rolling_model"}},
      {"friction negative", "specific_gravity = 2.65\n" + grading + "[contact]\nfriction_particle = -0.1\n",
       {"contact.friction_particle"}},
      {"unknown key", "specific_gravity = 2.65\nspecific_gravty_basis = \"ssd\"\n" + grading, {"specific_gravty_basis"}},
      {"unknown lab", "specific_gravity = 2.65\n" + grading + "[lab.c127]\nx = 1\n", {"lab", "c127"}},
      {"syntax", "specific_gravity = \n", {"TOML syntax error"}},
  });
}

TEST_F(MaterialFileTest, AGradingCsvErrorIsTheGradingReadersOwn) {
  std::ofstream(dir_ / "bad.csv") << "sieve,opening_mm,percent_passing\n1in,25,90\n#4,4.75,5\n";
  try {
    load_material_file(write("specific_gravity = 2.65\n[grading]\nfile = \"bad.csv\"\n"));
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("passes 100 %"), std::string::npos) << e.what();
  }
}

TEST_F(MaterialFileTest, TheExampleMaterialsLoad) {
  const fs::path dir = fs::path(AGGPACK_EXAMPLES) / "materials";
  for (const char* file : {"crushed_stone_19mm.toml", "gravel_19mm.toml", "natural_sand.toml", "manufactured_sand.toml"}) {
    SCOPED_TRACE(file);
    const AggregateMaterial m = load_material_file(dir / file);
    EXPECT_GE(oven_dry_specific_gravity(m), 2.55);
    EXPECT_LE(oven_dry_specific_gravity(m), 2.70);
    EXPECT_TRUE(m.shape);
    EXPECT_TRUE(m.c29 || m.c1252);
    EXPECT_TRUE(m.grading.band);
    EXPECT_TRUE(check_against_band(m.grading.grading, *m.grading.band).all_inside());
    EXPECT_TRUE(to_json(m).contains("lab"));
  }
  const AggregateMaterial gravel = load_material_file(dir / "gravel_19mm.toml");
  EXPECT_NEAR(oven_dry_specific_gravity(gravel), 2.64 / 1.01, 1e-12);
  EXPECT_NEAR(gravel.c29->kg_per_m3, 106.1 * kKgPerM3PerLbPerFt3, 1e-9);
}

TEST_F(MaterialFileTest, JsonHoldsTheLabResultsBesideTheirVoids) {
  const AggregateMaterial m = load_material_file(write(kFull));
  const nlohmann::json j = to_json(m);
  EXPECT_EQ(j["lab"]["c29"]["method"], "jigging");
  EXPECT_NEAR(j["lab"]["c29"]["bulk_density_lb_ft3"].get<double>(), 98.6, 1e-9);
  const double voids = j["lab"]["c29"]["voids_percent"].get<double>();
  EXPECT_NEAR(voids, voids_percent(m, m.c29->kg_per_m3), 1e-12);
  EXPECT_NEAR(j["lab"]["c29"]["packing_fraction"].get<double>(), 1.0 - voids / 100.0, 1e-12);
  EXPECT_NEAR(j["lab"]["c1252"]["packing_fraction"].get<double>(), 0.555, 1e-12);
  EXPECT_EQ(j["specific_gravity_basis"], "ssd");
  EXPECT_DOUBLE_EQ(j["grading"]["nominal_maximum_size_m"].get<double>(), 0.019);
  EXPECT_DOUBLE_EQ(j["grading"]["maximum_size_m"].get<double>(), 0.025);
  EXPECT_EQ(j["shape"]["name"], "crushed_stone");
  EXPECT_FALSE(j["contact"].contains("density_kg_m3"));
  EXPECT_EQ(j["calibration"]["runs"][1], 2);
}

TEST(NamedShapes, EachNameGivesItsFamily) {
  EXPECT_EQ(named_grain_shape("crushed_stone")->family, GrainFamily::Angular);
  EXPECT_EQ(named_grain_shape("manufactured_sand")->family, GrainFamily::Angular);
  EXPECT_EQ(named_grain_shape("gravel")->family, GrainFamily::Rounded);
  EXPECT_EQ(named_grain_shape("natural_sand")->family, GrainFamily::Rounded);
  EXPECT_FALSE(named_grain_shape("pebbles"));
  EXPECT_EQ(named_grain_shape_names().size(), 4u);
  // Crushed grains are more elongated and flatter than rounded ones of the same origin.
  EXPECT_LT(named_grain_shape("crushed_stone")->proportions.flatness_mean, named_grain_shape("gravel")->proportions.flatness_mean);
  EXPECT_LT(named_grain_shape("manufactured_sand")->proportions.elongation_mean,
            named_grain_shape("natural_sand")->proportions.elongation_mean);
  for (const auto name : named_grain_shape_names()) named_grain_shape(name)->proportions.check();
}

}  // namespace
}  // namespace aggpack
