// A lab test's plan: the standard's measure and procedure from a material file, every check
// before any run, and the scenario it writes read back as `aggpack run` reads it.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "aggpack/core/error.hpp"
#include "aggpack/labtests/lab_test.hpp"
#include "aggpack/run/generate_sizes.hpp"
#include "aggpack/run/run_grains.hpp"

namespace aggpack {
namespace {

const std::filesystem::path kMaterials = std::filesystem::path(AGGPACK_EXAMPLES) / "materials";

LabTestOptions options(const std::string& material, LabTestKind test, const std::string& method) {
  LabTestOptions o;
  o.material = kMaterials / material;
  o.test = test;
  o.method = method;
  return o;
}

std::string refusal(const LabTestOptions& o) {
  try {
    plan_lab_test(o);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(LabTest, C29OfA19MmStoneIsRoddedInTheThirdCubicFootMeasure) {
  const LabTestPlan plan = plan_lab_test(options("crushed_stone_19mm.toml", LabTestKind::C29, "rodding"));
  EXPECT_DOUBLE_EQ(plan.nominal_maximum_size_m, 0.019);
  EXPECT_EQ(plan.measure_name, "1/3 ft3 (9.3 L)");
  ASSERT_EQ(plan.parts.size(), 1u);
  const LabTestPart& part = plan.parts[0];
  EXPECT_NEAR(0.25 * 3.141592653589793 * part.measure_diameter_m * part.measure_diameter_m * part.measure_height_m,
              9.3e-3, 1e-9);
  EXPECT_DOUBLE_EQ(part.cut_off_m, 0.019 / 8);
  // The scenario reads as a run's, a cylinder with its rim at the measure's height.
  const Scenario sc = parse_scenario(part.scenario_text, kMaterials / "crushed_stone_19mm.toml");
  EXPECT_TRUE(sc.container.is_cylinder());
  EXPECT_NEAR(sc.container.rim, part.measure_height_m, 1e-9);
  EXPECT_NEAR(sc.container.radius(), 0.5 * part.measure_diameter_m, 1e-9);
  ASSERT_TRUE(sc.protocol.has_value());
  EXPECT_FALSE(plan.modelling.empty());
}

TEST(LabTest, RefusesWhatTheStandardDoesNotDefineBeforeAnyRun) {
  // Jigging is C29's above 37.5 mm only; a sand is not C29's rodding... but C1252's.
  EXPECT_NE(refusal(options("crushed_stone_19mm.toml", LabTestKind::C29, "jigging")).find("rodding"),
            std::string::npos);
  EXPECT_NE(refusal(options("crushed_stone_19mm.toml", LabTestKind::C29, "tamping")).find("shovelling, rodding, jigging"),
            std::string::npos);
  EXPECT_NE(refusal(options("crushed_stone_19mm.toml", LabTestKind::C1252, "A")).find("4.75 mm"), std::string::npos);
  EXPECT_NE(refusal(options("natural_sand.toml", LabTestKind::C1252, "D")).find("A, B, C"), std::string::npos);
  LabTestOptions o = options("crushed_stone_19mm.toml", LabTestKind::C29, "rodding");
  o.seeds = 0;
  EXPECT_NE(refusal(o).find("--seeds"), std::string::npos);
  o = options("crushed_stone_19mm.toml", LabTestKind::C29, "rodding");
  o.max_particles = std::nan("");  // CLI11's range check lets NaN through
  EXPECT_NE(refusal(o).find("--max-particles"), std::string::npos);
  o = options("crushed_stone_19mm.toml", LabTestKind::C29, "rodding");
  o.set = {"container.rim=\"2 m\""};  // a key of the test's scenario, checked as a run checks it
  EXPECT_FALSE(refusal(o).empty());
}

TEST(LabTest, C1252MethodBIsThreeFractionsEachInTheStandardsCylinder) {
  const LabTestPlan plan = plan_lab_test(options("natural_sand.toml", LabTestKind::C1252, "B"));
  ASSERT_EQ(plan.parts.size(), 3u);
  for (const LabTestPart& part : plan.parts) {
    EXPECT_DOUBLE_EQ(part.measure_diameter_m, 0.039);
    EXPECT_DOUBLE_EQ(part.measure_height_m, 0.086);
    const Scenario sc = parse_scenario(part.scenario_text, kMaterials / "natural_sand.toml");
    EXPECT_TRUE(sc.container.is_cylinder());
  }
}

TEST(LabTest, C1252MethodCTakesTheSandAsReceivedAboveItsFinestFraction) {
  LabTestOptions o = options("natural_sand.toml", LabTestKind::C1252, "C");
  o.max_particles = 1e6;
  const LabTestPlan plan = plan_lab_test(o);
  ASSERT_EQ(plan.parts.size(), 1u);
  EXPECT_DOUBLE_EQ(plan.parts[0].cut_off_m, 0.150e-3);  // its 0.075 mm sieve's fines left out, and said
  EXPECT_NEAR(plan.parts[0].cut_off_percent, 4.0, 1e-9);  // natural_sand.csv: 4 % passes 0.150 mm
  const Scenario sc = parse_scenario(plan.parts[0].scenario_text, kMaterials / "natural_sand.toml");
  ASSERT_TRUE(sc.particles.graded.has_value());
  EXPECT_NEAR(*sc.particles.graded->main.d_max, 4.75e-3, 1e-12);
}

// Method A's sample in the 100 mL cylinder is some 10^6 grains: it is simulated in a cylinder of
// the same proportions scaled to hold --max-particles, and says so.
TEST(LabTest, AC1252TooBigToSimulateRunsInARepresentativeCylinderOfTheSameProportions) {
  LabTestOptions o = options("natural_sand.toml", LabTestKind::C1252, "A");
  const LabTestPlan plan = plan_lab_test(o);
  ASSERT_EQ(plan.parts.size(), 1u);
  const LabTestPart& part = plan.parts[0];
  EXPECT_GT(part.full_size_particles, 1e6);
  EXPECT_NEAR(part.scale, std::cbrt(o.max_particles / part.full_size_particles), 1e-12);
  EXPECT_NEAR(part.simulated_diameter_m, 0.039 * part.scale, 1e-15);
  EXPECT_NEAR(part.simulated_height_m, 0.086 * part.scale, 1e-15);
  EXPECT_DOUBLE_EQ(part.measure_diameter_m, 0.039);  // the standard's, reported as the test's
  const Scenario sc = parse_scenario(part.scenario_text, kMaterials / "natural_sand.toml");
  EXPECT_NEAR(sc.container.radius(), 0.5 * part.simulated_diameter_m, 1e-10);
  EXPECT_NEAR(sc.container.rim, part.simulated_height_m, 1e-10);
  // It holds about --max-particles: more by its overfill of two largest grains over the rim, a
  // larger share of a short cylinder than the standard's 10 %.
  const double count = expected_particle_count(sc.particles);
  EXPECT_GT(count, o.max_particles);
  EXPECT_LT(count, 1.25 * o.max_particles);
  bool said = false;
  for (const std::string& note : plan.modelling)
    said = said || note.find("representative measure") != std::string::npos;
  EXPECT_TRUE(said);
  EXPECT_NE(part.scenario_text.find("representative measure"), std::string::npos);  // its comments say it too
  // A cylinder that fits is the standard's.
  o.max_particles = 1e8;
  EXPECT_EQ(plan_lab_test(o).parts[0].scale, 1.0);
  // One narrower than four of its largest grains is refused, naming the option and what it needs.
  o = options("natural_sand.toml", LabTestKind::C1252, "C");
  const std::string why = refusal(o);
  EXPECT_NE(why.find("--max-particles 50000"), std::string::npos) << why;
  EXPECT_NE(why.find("expected --max-particles of at least"), std::string::npos) << why;
}

// Grains fill the measure: what the run generates for the test, each grain's own volume at its
// size summed (the run's sizes and templates, an oracle apart from the plan's arithmetic), is
// the measure filled to its overfill at the expected packing.
TEST(LabTest, GrainsGeneratedForATestFillTheMeasureByTheirOwnVolume) {
  const LabTestPlan plan = plan_lab_test(options("crushed_stone_12mm_single.toml", LabTestKind::C29, "shovelling"));
  const LabTestPart& part = plan.parts[0];
  const Scenario sc = parse_scenario(part.scenario_text, kMaterials / "crushed_stone_12mm_single.toml");
  const GeneratedSizes sizes = generate_sizes(sc.particles, 1);
  const RunGrains grains = make_run_grains(sc.particles, sizes, 1, {});
  double solid = 0.0;
  for (std::size_t i = 0; i < sizes.diameters.size(); ++i) {
    ASSERT_GE(grains.shape_of[i], 0);
    const auto k = static_cast<std::size_t>(grains.shape_of[i]);
    const double reach = grains.shape_grain[k]->reach_for_width(sizes.diameters[i]);
    solid += grains.shapes[k].volume * reach * reach * reach;
  }
  const double rim = part.measure_height_m, overfill = std::max(0.15 * rim, 2.0 * 0.0125);
  const double filled = 0.25 * 3.141592653589793 * part.measure_diameter_m * part.measure_diameter_m * (rim + overfill);
  EXPECT_NEAR(solid / filled, 0.6, 0.03);  // the typical packing: the material file has no C29 value
}

// C29's measure is never scaled: a smaller one would change what 25 strokes of the rod do.
TEST(LabTest, C29RunsInTheStandardsMeasureWhateverItHolds) {
  LabTestOptions o = options("crushed_stone_19mm.toml", LabTestKind::C29, "rodding");
  o.max_particles = 1000;
  const LabTestPlan plan = plan_lab_test(o);
  EXPECT_GT(plan.parts[0].full_size_particles, 1000);
  EXPECT_EQ(plan.parts[0].scale, 1.0);
}

}  // namespace
}  // namespace aggpack
