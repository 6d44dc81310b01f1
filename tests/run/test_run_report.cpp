// What a run's report says of itself: an interrupted run made no final analysis, and claims no
// density (NaN in the API, "not measured" on the console, no density in summary.json).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "aggpack/io/particle_file.hpp"
#include "aggpack/io/scenario.hpp"
#include "aggpack/run/run_report.hpp"

namespace aggpack {
namespace {

const std::filesystem::path kLattice = std::filesystem::path(AGGPACK_EXAMPLES) / "cubic_lattice.csv";

// The shipped lattice settled by a DEM that a signal stopped: what run() hands back then.
RunReport interrupted_report() {
  RunReport r;
  r.scenario = parse_scenario("seed = 1\n[container]\nside = \"10 in\"\nheight = \"10 in\"\n[particles]\nfrom = \"" +
                                  kLattice.string() + "\"\n[dynamics]\n[analysis]\nbox_sides = [\"4 in\"]\n",
                              "lattice.toml");
  r.particles = read_particle_file(kLattice, 1.0, 1.0);
  r.dynamics = SettlingReport{{SettlingRun{}}};
  r.interrupted = Interruption{2, "while settling at 0.0100 s simulated", 0, 1, std::nullopt};
  return r;
}

TEST(RunReport, AnInterruptedRunClaimsNoDensity) {
  const RunReport r = interrupted_report();
  EXPECT_TRUE(std::isnan(r.final_density()));
  EXPECT_TRUE(std::isnan(r.density_after_dynamics()));
  const std::string console = r.console_summary("out/lattice");
  EXPECT_EQ(console.find("density 0.0000"), std::string::npos) << console;
  EXPECT_NE(console.find("mean density not measured: interrupted by signal 2 while settling"), std::string::npos)
      << console;
  EXPECT_EQ(console.find("voids"), std::string::npos) << console;  // no bulk density of a density not measured
  const nlohmann::json summary = r.summary_json(0.0, 1.0);
  EXPECT_TRUE(summary["interrupted"].get<bool>());
  EXPECT_FALSE(summary.contains("density"));
  EXPECT_FALSE(summary.contains("bulk_density"));
  EXPECT_FALSE(summary["stages"]["dynamics"].contains("density"));
}

TEST(RunReport, AFinishedRunReportsItsFinalAnalysis) {
  RunReport r = interrupted_report();
  r.interrupted.reset();
  r.final.density.mean = 0.5;
  EXPECT_EQ(r.final_density(), 0.5);
  EXPECT_EQ(r.density_after_dynamics(), 0.5);
  EXPECT_NE(r.console_summary("out/lattice").find("mean density 0.5000"), std::string::npos);
  EXPECT_EQ(r.summary_json(0.0, 1.0)["density"]["mean"], 0.5);
}

}  // namespace
}  // namespace aggpack
