// A lab test's plan: the standard's measure and procedure from a material file, every check
// before any run, and the scenario it writes read back as `aggpack run` reads it.
#include "aggpack/labtests/lab_test.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "aggpack/core/error.hpp"

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
  const LabTestPlan plan = plan_lab_test(options("natural_sand.toml", LabTestKind::C1252, "C"));
  ASSERT_EQ(plan.parts.size(), 1u);
  EXPECT_DOUBLE_EQ(plan.parts[0].cut_off_m, 0.150e-3);  // its 0.075 mm sieve's fines left out, and said
  EXPECT_NEAR(plan.parts[0].cut_off_percent, 4.0, 1e-9);  // natural_sand.csv: 4 % passes 0.150 mm
  const Scenario sc = parse_scenario(plan.parts[0].scenario_text, kMaterials / "natural_sand.toml");
  ASSERT_TRUE(sc.particles.graded.has_value());
  EXPECT_NEAR(*sc.particles.graded->main.d_max, 4.75e-3, 1e-12);
}

}  // namespace
}  // namespace aggpack
