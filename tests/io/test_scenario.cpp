#include "aggpack/io/scenario.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/io/toml_reader.hpp"

namespace aggpack {
namespace {

namespace fs = std::filesystem;

struct BadCase {
  const char* name;
  std::string text;
  std::vector<std::string> expected;  // substrings of the message: location, key, what
};

class ScenarioTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("aggpack_scenario_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    std::ofstream(dir_ / "p.csv") << "x,y,z,r\n0.5,0.5,0.5,0.1\n";
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path write(const std::string& text) {
    const fs::path f = dir_ / "s.toml";
    std::ofstream(f) << text;
    return f;
  }
  // Each case is refused with an InputError whose message holds its expected parts.
  void expect_refused(const std::vector<BadCase>& cases) {
    for (const auto& c : cases) {
      try {
        load_scenario(write(c.text));
        ADD_FAILURE() << c.name << ": accepted";
      } catch (const InputError& e) {
        const std::string msg = e.what();
        for (const auto& part : c.expected) EXPECT_NE(msg.find(part), std::string::npos) << c.name << ": " << msg;
      }
    }
  }
  fs::path dir_;
};

constexpr const char* kGood = R"(title = "ok"
seed = 7
[container]
side = "12 in"
height = "1 m"
[particles]
from = "p.csv"
[analysis]
box_sides = ["6 in", 0.2]
)";

TEST_F(ScenarioTest, AGoodScenarioIsReadInSIUnits) {
  const Scenario sc = load_scenario(write(kGood));
  EXPECT_EQ(sc.seed, 7u);
  EXPECT_DOUBLE_EQ(sc.container.length_x(), 12 * 0.0254);
  EXPECT_DOUBLE_EQ(sc.container.height(), 1.0);
  EXPECT_FALSE(sc.container.periodic);
  ASSERT_EQ(sc.analysis.box_sides.size(), 2u);
  EXPECT_DOUBLE_EQ(sc.analysis.box_sides[0], 6 * 0.0254);
  EXPECT_EQ(sc.particles.file->filename(), "p.csv");
  EXPECT_EQ(sc.output.directory, "out/s");
  EXPECT_DOUBLE_EQ(to_json(sc)["container"]["side_m"].get<double>(), 12 * 0.0254);
}

TEST_F(ScenarioTest, SetOverridesAnyKeyAndItsErrorsNameTheOption) {
  ScenarioOverrides o;
  o.set = {"container.sides=periodic", "container.side=\"10 in\"", "analysis.contact_tolerance=0.01", "seed=9"};
  const Scenario sc = load_scenario(write(kGood), o);
  EXPECT_TRUE(sc.container.periodic);
  EXPECT_DOUBLE_EQ(sc.container.length_x(), 0.254);
  EXPECT_DOUBLE_EQ(sc.analysis.contact_tolerance, 0.01);
  EXPECT_EQ(sc.seed, 9u);
  o.set = {"container.side=\"-3 in\""};
  try {
    load_scenario(write(kGood), o);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--set container.side="), std::string::npos) << e.what();
  }
  // A seed given beside the file is held to the file's range.
  o.set.clear();
  o.seed = std::uint64_t{1} << 63;
  try {
    load_scenario(write(kGood), o);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("seed 9223372036854775808: expected an integer from 0 to "
                                         "9223372036854775807"),
              std::string::npos)
        << e.what();
  }
}

TEST_F(ScenarioTest, BadFilesAreRefusedWithFileLineKeyAndExpectation) {
  const std::string head = "[container]\nside = \"12 in\"\nheight = \"24 in\"\n";
  const std::string particles = "[particles]\nfrom = \"p.csv\"\n";
  const std::string sized = "[particles]\ndiameter = \"1 in\"\ncount = 10\n";
  const std::vector<BadCase> cases = {
      {"typo in a key", head + particles + "[analysis]\nbox_side = [\"6 in\"]\n",
       {"s.toml:7:", "analysis.box_side", "unknown key", "did you mean 'box_sides'"}},
      {"typo in a section", head + particles + "[materail]\ndensity = 2650\n",
       {"s.toml:6:", "materail", "did you mean 'material'"}},
      {"wrong type", head + particles + "[material]\ndensity = \"heavy\"\n",
       {"s.toml:7:", "material.density", "expected a positive number", "got a string"}},
      {"out of range", head + particles + "[material]\nrestitution = 1.5\n",
       {"s.toml:7:", "material.restitution", "(0, 1]", "1.5"}},
      {"negative length", "[container]\nside = \"-12 in\"\nheight = \"24 in\"\n" + particles,
       {"s.toml:2:", "container.side", "positive"}},
      {"unknown unit", "[container]\nside = \"12 furlongs\"\nheight = \"24 in\"\n" + particles,
       {"s.toml:2:", "container.side", "unknown length unit 'furlongs'"}},
      {"missing required key", "[container]\nside = \"12 in\"\n" + particles,
       {"s.toml:1:", "container.height", "missing required key 'height'"}},
      {"missing section", particles, {"s.toml", "container", "missing required key 'container'"}},
      {"bad choice", "[container]\nside = 1\nheight = 1\nsides = \"wrap\"\n" + particles,
       {"s.toml:4:", "container.sides", "\"walls\", \"periodic\"", "\"wrap\""}},
      {"negative seed", "seed = -1\n" + head + particles, {"s.toml:1:", "seed", "an integer in [0,"}},
      {"float seed", "seed = 1.5\n" + head + particles, {"s.toml:1:", "seed", "got a float"}},
      {"two particle sources", head + "[particles]\nfrom = \"p.csv\"\ndiameter = \"1 in\"\ncount = 3\n",
       {"particles.from", "exactly one of"}},
      {"no particle source", head + "[particles]\ncount = 3\n", {"particles", "exactly one of"}},
      {"class without amount", head + "[particles]\nclasses = [{ diameter = \"1 in\" }]\n",
       {"s.toml:5:", "particles.classes[0]", "exactly one of 'count' and 'volume_fraction'"}},
      {"fractions not adding up",
       head + "[particles]\ncount = 10\nclasses = [{ diameter = \"1 in\", volume_fraction = 0.5 },"
              " { diameter = \"2 in\", volume_fraction = 0.4 }]\n",
       {"particles.classes", "add up to 1", "0.9"}},
      {"unknown output format", head + particles + "[output]\nformats = [\"stl\"]\n",
       {"s.toml:7:", "output.formats", "\"stl\""}},
      {"rolling spring without the spring-dashpot model", head + particles + "[material]\nrolling_friction = 0.1\n"
                                                                          "rolling_stiffness = 100\n",
       {"s.toml:8:", "material.rolling_stiffness", "applies only with rolling_model = \"spring_dashpot\""}},
      {"rolling damping without the spring-dashpot model",
       head + particles + "[material]\nrolling_model = \"constant_torque\"\nrolling_damping = 1\n",
       {"material.rolling_damping", "applies only with rolling_model = \"spring_dashpot\""}},
      {"spring-dashpot without its stiffness",
       head + particles + "[material]\nrolling_friction = 0.1\nrolling_model = \"spring_dashpot\"\n",
       {"material.rolling_stiffness", "is required with rolling_model = \"spring_dashpot\""}},
      {"spring-dashpot without rolling friction",
       head + particles + "[material]\nrolling_model = \"spring_dashpot\"\nrolling_stiffness = 100\n",
       {"material.rolling_friction", "must be > 0"}},
      {"spring-dashpot with a negative damping",
       head + particles + "[material]\nrolling_friction = 0.1\nrolling_model = \"spring_dashpot\"\n"
                          "rolling_stiffness = 100\nrolling_damping = -1\n",
       {"material.rolling_damping", "-1"}},
      {"unknown rolling model", head + particles + "[material]\nrolling_model = \"epsd2\"\n",
       {"material.rolling_model", "\"constant_torque\", \"spring_dashpot\"", "\"epsd2\""}},
            {"sizes but no stage", head + "[particles]\ndiameter = \"1 in\"\ncount = 10\n",
       {"s.toml:5:", "no stage places them", "[deposition]"}},
      {"deposition of a file's particles", head + particles + "[deposition]\n",
       {"s.toml:6:", "deposition", "particles.from gives positions already"}},
      {"deposition key typo", head + sized + "[deposition]\ntolerence = 1e-9\n",
       {"s.toml:8:", "deposition.tolerence", "did you mean 'tolerance'"}},
      {"unknown friction model", head + particles + "[dynamics]\nfriction_model = \"coulomb\"\n",
       {"s.toml:7:", "dynamics.friction_model", "\"mindlin\", \"fu2003\"", "\"coulomb\""}},
      {"layers without deposition", head + particles + "[dynamics]\nlayers = 4\n",
       {"s.toml:7:", "dynamics.layers", "needs a [deposition] table"}},
      {"quiet window shorter than a sample", head + particles + "[dynamics]\nquiet_window = 1e-4\n",
       {"s.toml:7:", "dynamics.quiet_window", "shorter than the sample interval"}},
      {"time step out of range", head + particles + "[dynamics]\ntime_step = 0\n",
       {"s.toml:7:", "dynamics.time_step", "0"}},
      {"poisson ratio out of range", head + particles + "[material]\npoisson_ratio = 0.5\n",
       {"s.toml:7:", "material.poisson_ratio", "0.5"}},
      {"deposition tolerance out of range", head + sized + "[deposition]\ntolerance = 0.5\n",
       {"s.toml:8:", "deposition.tolerance", "0.5"}},
      {"unknown deposition method", head + sized + "[deposition]\nmethod = \"rain\"\n",
       {"s.toml:8:", "deposition.method", "\"drop_and_roll\""}},
      {"fill height above the container", head + sized + "[deposition]\nfill_height = \"30 in\"\n",
       {"s.toml:8:", "deposition.fill_height", "above the container height"}},
      {"unknown named grading", head + "[particles]\ncount = 10\n[particles.grading]\nname = \"c33\"\n[deposition]\n",
       {"s.toml:7:", "particles.grading.name", "unknown grading", "astm_c33_fine_mid"}},
      {"cut-off removes everything",
       head + "[particles]\ncount = 10\n[particles.grading]\nname = \"astm_c33_fine_mid\"\nd_min = \"1 in\"\n",
       {"s.toml:8:", "particles.grading", "leave nothing"}},
      {"decreasing inline sieves",
       head + "[particles]\ncount = 10\n[particles.grading]\nsieves = [{ opening = \"1 mm\", passing = 50 },"
              " { opening = \"2 mm\", passing = 40 }, { opening = \"4 mm\", passing = 100 }]\n",
       {"s.toml:7:", "particles.grading.sieves[1]", "must not decrease"}},
      {"ca_fa without a mix", head + "[particles]\ncount = 10\nca_fa = 1.5\n[particles.grading]\nname = "
                                     "\"astm_c33_fine_mid\"\n",
       {"s.toml:6:", "particles.ca_fa", "only to a coarse/fine mix"}},
      {"mix without fine", head + "[particles]\ncount = 10\nca_fa = 1.5\n[particles.coarse]\nname = "
                                  "\"fu2003_table1_coarse\"\n",
       {"particles.fine", "missing required key"}},
      {"grading without amount", head + "[particles]\n[particles.grading]\nname = \"astm_c33_fine_mid\"\n",
       {"particles.count", "exactly one of 'count', 'solid_volume'"}},
      {"unknown band", head + "[particles]\ncount = 5\n[particles.grading]\nname = \"astm_c33_fine_mid\"\n"
                              "band = \"astm_c33_8\"\n",
       {"s.toml:8:", "particles.grading.band", "unknown band"}},
      {"sampling for classes", head + sized + "sampling = \"mass\"\n[deposition]\n",
       {"particles.sampling", "only to particles sampled from a grading"}},
      {"periodic box too narrow", "[container]\nside = \"3 in\"\nheight = \"24 in\"\nsides = \"periodic\"\n" +
                                      sized + "[deposition]\n",
       {"container.side", "four times the largest diameter"}},
      {"syntax error", "[container\nside = 1\n", {"s.toml:1:", "TOML syntax error"}},
      {"box side list of numbers with bad unit", head + particles + "[analysis]\nbox_sides = [\"6 in\", \"7 inch\"]\n",
       {"s.toml:7:", "analysis.box_sides[1]", "unknown length unit 'inch'"}},
  };
  expect_refused(cases);
}

// The materials' errors name the key and say what is expected.
TEST_F(ScenarioTest, MaterialErrorsNameTheKeyAndWhatIsExpected) {
  const std::string head = "[container]\nside = \"12 in\"\nheight = \"24 in\"\n";
  const std::string particles = "[particles]\nfrom = \"p.csv\"\n";
  const std::string sized = "[particles]\ndiameter = \"1 in\"\ncount = 10\n";
  const std::string mat = "[materials.stone]\ndensity = 2700\n[materials.sand]\ndensity = 2600\n";
  const auto pair = [](const std::string& names, const std::string& coefficient) {
    return "[[material_pairs]]\nmaterials = [" + names + "]\n" + coefficient + "\n";
  };
  const std::vector<BadCase> cases = {
      {"unknown material name", head + mat + sized + "material = \"granite\"\n[deposition]\n",
       {"particles.material", "no material is named \"granite\"", "\"default\"", "\"sand\", \"stone\""}},
      {"a named material with the walls' modulus", head + particles + "[materials.sand]\nwall_youngs_modulus = 1e9\n",
       {"materials.sand.wall_youngs_modulus", "give it in [material]"}},
      {"a named material with the rolling model", head + particles + "[materials.sand]\nrolling_model = "
                                                                     "\"spring_dashpot\"\n",
       {"materials.sand.rolling_model", "one rolling model for the run"}},
      {"a pair of a material with itself", head + particles + mat + pair("\"sand\", \"sand\"", "friction = 0.3"),
       {"material_pairs[0].materials", "\"sand\" against itself"}},
      {"a pair naming an unknown material", head + particles + mat + pair("\"sand\", \"clay\"", "friction = 0.3"),
       {"material_pairs[0].materials", "no material is named \"clay\"", "\"default\", \"sand\", \"stone\""}},
      {"a pair given twice", head + particles + mat + pair("\"sand\", \"stone\"", "friction = 0.3") +
                                 pair("\"stone\", \"sand\"", "restitution = 0.3"),
       {"material_pairs[1].materials", "is given twice"}},
      {"a pair with no coefficient", head + particles + mat + pair("\"sand\", \"default\"", ""),
       {"material_pairs[0].materials", "gives no coefficient", "friction, restitution"}},
      {"a material's name with a hyphen (LAMMPS's fix names refuse it)",
       head + particles + "[materials.fine-sand]\ndensity = 2600\n", {"materials.fine-sand", "letters, digits and '_'"}},
      {"a pair's rolling spring under the constant-torque model",
       head + particles + mat + pair("\"sand\", \"stone\"", "rolling_stiffness = 100"),
       {"material_pairs[0].rolling_stiffness", "applies only with rolling_model = \"spring_dashpot\""}},
      {"two classes of one diameter and two materials",
       head + mat + "[particles]\ncount = 10\nclasses = [{ diameter = \"1 in\", volume_fraction = 0.5, material = "
                    "\"sand\" }, { diameter = \"1 in\", volume_fraction = 0.5, material = \"stone\" }]\n"
                    "[deposition]\n",
       {"particles.classes[1].material", "another size class of the same diameter is of another material"}},
      {"a material at [particles] with a grading",
       head + mat + "[particles]\ncount = 10\nmaterial = \"sand\"\n[particles.grading]\nname = "
                    "\"astm_c33_fine_mid\"\n[deposition]\n",
       {"particles.material", "a grading's material is given in its own table"}},
      {"a material named default", head + particles + "[materials.default]\ndensity = 2000\n",
       {"materials.default", "is not \"default\""}},
  };
  expect_refused(cases);
}

TEST_F(ScenarioTest, ReadsTheDepositionStage) {
  const Scenario sc = load_scenario(write(
      "[container]\nside = \"12 in\"\nheight = \"24 in\"\n[particles]\ndiameter = \"1 in\"\ncount = 10\n"
      "[deposition]\ntolerance = 1e-8\nmax_events = 500\nfill_height = \"10 in\"\n"));
  ASSERT_TRUE(sc.deposition);
  EXPECT_DOUBLE_EQ(sc.deposition->tolerance, 1e-8);
  EXPECT_EQ(sc.deposition->max_events, 500u);
  EXPECT_NEAR(sc.deposition->fill_height, 0.254, 1e-15);
  EXPECT_EQ(to_json(sc)["deposition"]["fill_height_m"].get<double>(), sc.deposition->fill_height);
}

TEST_F(ScenarioTest, ReadsAGradedMix) {
  const Scenario sc = load_scenario(write(
      "[container]\nside = \"5 in\"\nheight = \"8 in\"\n[particles]\nca_fa = 1.52\nfill_height = \"6 in\"\n"
      "[particles.coarse]\nname = \"fu2003_table1_coarse\"\nd_min = \"0.1 in\"\n"
      "[particles.fine]\nname = \"astm_c33_fine_mid\"\nd_min = \"1 mm\"\nband = \"astm_c33_fine\"\n"
      "[deposition]\n"));
  ASSERT_TRUE(sc.particles.graded);
  const GradedParticles& g = *sc.particles.graded;
  ASSERT_TRUE(g.fine);
  EXPECT_EQ(g.main.grading.name, "fu2003_table1_coarse");
  EXPECT_DOUBLE_EQ(g.ca_fa, 1.52);
  EXPECT_EQ(g.sampling, SamplingMode::Mass);
  EXPECT_EQ(g.order, MixOrder::Interleaved);
  EXPECT_NEAR(*g.amount.solid_volume, 0.127 * 0.127 * 0.1524 * 0.6, 1e-12);
  EXPECT_TRUE(g.fine->band);
  EXPECT_EQ(to_json(sc)["particles"]["gradings"].size(), 2u);
}

// A scenario may be 16 MiB, some 3x10^5 steps: each step's name was compared with every
// step before it and each export searched forward for its DEM step, so reading one such file
// took 4 minutes (`check`); now a few seconds. (Speed is measured outside the unit tests; this
// checks what the one-pass reading must still get right: the stages, the decks, the names.)
TEST_F(ScenarioTest, AProtocolOfManyStepsIsReadAndLinked) {
  constexpr int kEach = 4000;
  std::string text = "[container]\nside = 0.1\nheight = 0.1\n[particles]\ndiameter = 0.01\ncount = 10\n"
                     "[deposition]\n[dynamics]\n[[protocol]]\nstep = \"deposit\"\n";
  for (int i = 0; i < kEach; ++i)
    text += fmt::format("[[protocol]]\nstep = \"analyse\"\nname = \"a{0}\"\n[[protocol]]\nstep = \"snapshot\"\n"
                        "name = \"s{0}\"\n[[protocol]]\nstep = \"export_lammps\"\nname = \"e{0}\"\n",
                        i);
  text += "[[protocol]]\nstep = \"settle\"\nlayer = 0\n";
  const Scenario sc = parse_scenario(text, dir_ / "s.toml");
  ASSERT_TRUE(sc.protocol);
  const std::size_t stages = sc.protocol->stage_names().size();
  EXPECT_EQ(sc.protocol->steps.size(), 3u * kEach + 2);
  EXPECT_EQ(stages, kEach + 2u);  // deposition, each analyse step, dynamics
  // Every export's deck is of the settle step at the end.
  std::size_t exports = 0, to_the_settle = 0;
  for (const Step& step : sc.protocol->steps)
    if (const auto* e = std::get_if<ExportLammpsStep>(&step.kind)) {
      ++exports;
      to_the_settle += std::holds_alternative<SettleStep>(e->next) ? 1 : 0;
    }
  EXPECT_EQ(exports, std::size_t{kEach});
  EXPECT_EQ(to_the_settle, exports);
  // Names are still unique per kind.
  EXPECT_THROW(parse_scenario(text + "[[protocol]]\nstep = \"snapshot\"\nname = \"s7\"\n", dir_ / "s.toml"),
               InputError);
}

TEST_F(ScenarioTest, ReadsTheRollingModelAndEchoesItOnlyWhenItIsTheSpringDashpot) {
  const Scenario plain = parse_scenario(std::string(kGood) + "[material]\nrolling_friction = 0.1\n", dir_ / "s.toml");
  EXPECT_EQ(plain.material.contact.rolling_model, RollingModel::ConstantTorque);
  EXPECT_FALSE(to_json(plain).at("material").contains("rolling_model"));
  const Scenario sds = parse_scenario(std::string(kGood) + "[material]\nrolling_friction = 0.1\nrolling_model = "
                                      "\"spring_dashpot\"\nrolling_stiffness = 250\nrolling_damping = 0.5\n",
                                      dir_ / "s.toml");
  const ContactParameters& c = sds.material.contact;
  EXPECT_EQ(c.rolling_model, RollingModel::SpringDashpot);
  EXPECT_EQ(c.rolling_stiffness, 250.0);
  EXPECT_EQ(c.rolling_damping, 0.5);
  const auto echoed = to_json(sds).at("material");
  EXPECT_EQ(echoed.at("rolling_model"), "spring_dashpot");
  EXPECT_EQ(echoed.at("rolling_stiffness_n_m"), 250.0);
  EXPECT_EQ(echoed.at("rolling_damping_n_s_m"), 0.5);
}

// [materials.NAME] starts from [material] and overrides what it gives; the named materials
// follow [material] (index 0, "default") in alphabetical order, whatever the file's order.
TEST_F(ScenarioTest, NamedMaterialsAreReadOverTheBaseMaterial) {
  const Scenario sc = parse_scenario(
      "[container]\nside = \"12 in\"\nheight = \"24 in\"\n[particles]\ndiameter = \"1 in\"\ncount = 10\n"
      "material = \"stone\"\n[deposition]\n"
      "[material]\ndensity = 2500\nfriction_particle = 0.4\nfriction_wall = 0.2\nwall_youngs_modulus = 3e9\n"
      "[materials.stone]\ndensity = 2800\nyoungs_modulus = 5e9\n"
      "[materials.sand]\nfriction_particle = 0.7\nrestitution = 0.3\n"
      "[[material_pairs]]\nmaterials = [\"stone\", \"sand\"]\nfriction = 0.9\n",
      dir_ / "s.toml");
  ASSERT_EQ(material_count(sc), 3u);
  EXPECT_EQ(material_name(sc, 0), "default");
  EXPECT_EQ(material_name(sc, 1), "sand");
  EXPECT_EQ(material_name(sc, 2), "stone");
  const Material &sand = material_of(sc, 1), &stone = material_of(sc, 2);
  EXPECT_EQ(sand.density, 2500.0);  // the base's
  EXPECT_EQ(sand.contact.friction_particle, 0.7);
  EXPECT_EQ(sand.contact.restitution, 0.3);
  EXPECT_EQ(sand.contact.friction_wall, 0.2);
  EXPECT_EQ(sand.contact.wall_youngs_modulus, 3e9);
  EXPECT_EQ(stone.density, 2800.0);
  EXPECT_EQ(stone.contact.youngs_modulus, 5e9);
  EXPECT_EQ(stone.contact.friction_particle, 0.4);
  EXPECT_EQ(stone.contact.restitution, sc.material.contact.restitution);
  EXPECT_EQ(material_densities(sc), (std::vector<double>{2500.0, 2500.0, 2800.0}));
  ASSERT_EQ(sc.material_pairs.size(), 1u);
  EXPECT_EQ(sc.material_pairs[0].first, 1);  // stored low index first
  EXPECT_EQ(sc.material_pairs[0].second, 2);
  EXPECT_EQ(sc.material_pairs[0].friction, 0.9);
  EXPECT_FALSE(sc.material_pairs[0].restitution);
  // The monosized bed is one component, of material "stone".
  EXPECT_EQ(sc.particles.component_material, (std::vector<std::uint8_t>{2}));
  const auto j = to_json(sc);
  EXPECT_EQ(j.at("materials").at("stone").at("density_kg_m3"), 2800.0);
  EXPECT_EQ(j.at("materials").at("stone").at("index"), 2);
  EXPECT_FALSE(j.at("materials").at("sand").contains("wall_youngs_modulus_pa"));
  EXPECT_EQ(j.at("material_pairs").at(0).at("materials"), (nlohmann::json{"sand", "stone"}));
  EXPECT_EQ(j.at("material_pairs").at(0).at("friction"), 0.9);
  EXPECT_EQ(j.at("particles").at("component_materials"), (nlohmann::json{"stone"}));
}

TEST_F(ScenarioTest, EachComponentNamesItsMaterial) {
  const std::string head = "[container]\nside = \"5 in\"\nheight = \"8 in\"\n[materials.stone]\ndensity = 2800\n"
                           "[materials.sand]\ndensity = 2600\n";
  // A mix: coarse, then fine.
  const Scenario mix = parse_scenario(
      head + "[particles]\nca_fa = 1.5\ncount = 20\n[particles.coarse]\nname = \"fu2003_table1_coarse\"\n"
             "material = \"stone\"\n[particles.fine]\nname = \"astm_c33_fine_mid\"\nd_min = \"1 mm\"\n"
             "material = \"sand\"\n[deposition]\n",
      dir_ / "s.toml");
  EXPECT_EQ(mix.particles.component_material, (std::vector<std::uint8_t>{2, 1}));
  EXPECT_EQ(mix.particles.material_of_component(1), 1);
  EXPECT_EQ(to_json(mix).at("particles").at("component_materials"), (nlohmann::json{"stone", "sand"}));
  // Size classes, as listed; a class without `material` is [material]'s.
  const Scenario classes = parse_scenario(
      head + "[particles]\nclasses = [{ diameter = \"1 in\", count = 3, material = \"sand\" }, { diameter = "
             "\"0.5 in\", count = 4 }, { diameter = \"0.7 in\", count = 5, material = \"stone\" }]\n[deposition]\n",
      dir_ / "s.toml");
  EXPECT_EQ(classes.particles.component_material, (std::vector<std::uint8_t>{1, 0, 2}));
  // A single grading.
  const Scenario graded = parse_scenario(
      head + "[particles]\ncount = 10\n[particles.grading]\nname = \"astm_c33_fine_mid\"\nmaterial = \"sand\"\n"
             "[deposition]\n",
      dir_ / "s.toml");
  EXPECT_EQ(graded.particles.component_material, (std::vector<std::uint8_t>{1}));
  // Two classes of one diameter and one material are accepted.
  EXPECT_NO_THROW(parse_scenario(head + "[particles]\nclasses = [{ diameter = \"1 in\", count = 3, material = "
                                        "\"sand\" }, { diameter = \"1 in\", count = 4, material = \"sand\" }]\n"
                                        "[deposition]\n",
                                 dir_ / "s.toml"));
}

TEST_F(ScenarioTest, TheSummaryNamesMaterialsOnlyWhenThereAreNamedOnes) {
  const Scenario one = parse_scenario(std::string(kGood) + "[material]\ndensity = 2000\n", dir_ / "s.toml");
  EXPECT_EQ(material_count(one), 1u);
  const auto j = to_json(one);
  EXPECT_FALSE(j.contains("materials"));
  EXPECT_FALSE(j.contains("material_pairs"));
  EXPECT_FALSE(j.at("particles").contains("component_materials"));
  const Scenario two = parse_scenario(std::string(kGood) + "[materials.sand]\ndensity = 2000\n", dir_ / "s.toml");
  const auto k = to_json(two);
  EXPECT_TRUE(k.contains("materials"));
  EXPECT_FALSE(k.contains("material_pairs"));
  EXPECT_EQ(k.at("particles").at("component_materials"), (nlohmann::json{"default"}));
}

TEST_F(ScenarioTest, AMissingFileIsAnInputError) {
  EXPECT_THROW(load_scenario(dir_ / "nope.toml"), InputError);
}

TEST(EditDistance, CountsSingleEdits) {
  EXPECT_EQ(edit_distance("box_sides", "box_side"), 1u);
  EXPECT_EQ(edit_distance("materail", "material"), 2u);
  EXPECT_EQ(edit_distance("", "abc"), 3u);
}

}  // namespace
}  // namespace aggpack
