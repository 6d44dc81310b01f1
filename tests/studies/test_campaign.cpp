#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "aggpack/core/error.hpp"
#include "aggpack/io/scenario.hpp"
#include "aggpack/run/run.hpp"
#include "aggpack/studies/campaign.hpp"
#include "aggpack/studies/sweep.hpp"

namespace aggpack {
namespace {

TEST(SeedStatistics, MeanAndSampleStandardDeviation) {
  const SeedStatistics s = seed_statistics({1.0, 2.0, 3.0, 4.0});
  EXPECT_EQ(s.count, 4u);
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  EXPECT_NEAR(s.sd, std::sqrt(5.0 / 3.0), 1e-15);  // sum of squares 5, n - 1 = 3
}

TEST(SeedStatistics, MissingValuesAreLeftOutAndOneValueHasNoSd) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const SeedStatistics s = seed_statistics({nan, 0.6, nan});
  EXPECT_EQ(s.count, 1u);
  EXPECT_DOUBLE_EQ(s.mean, 0.6);
  EXPECT_TRUE(std::isnan(s.sd));
  EXPECT_EQ(seed_statistics({}).count, 0u);
  EXPECT_TRUE(std::isnan(seed_statistics({}).mean));
}

TEST(FaPoints, RangesAndLists) {
  EXPECT_EQ(parse_fa_points("25:45:5"), (std::vector<double>{25, 30, 35, 40, 45}));
  EXPECT_EQ(parse_fa_points("20:50:15"), (std::vector<double>{20, 35, 50}));
  EXPECT_EQ(parse_fa_points("29,35.5,43"), (std::vector<double>{29, 35.5, 43}));
  EXPECT_EQ(parse_fa_points("40"), (std::vector<double>{40}));
  for (const char* bad : {"", "30:x:5", "30:20:5", "0,40", "40,100", "30:40", "30,,40", "35%", "1:99:0.1"})
    EXPECT_THROW(parse_fa_points(bad), InputError) << bad;
}

// A run in memory (whole-grading, calibrate) is the library's run of that scenario at that
// seed, numbered and logged by the campaign in one line, its own when it gives one.
TEST(Campaign, RunsALoadedScenarioInMemory) {
  const std::filesystem::path file = std::filesystem::temp_directory_path() / "aggpack_campaign_in_memory.toml";
  std::ofstream(file) << "[container]\nside = 0.06\nheight = 0.2\n[particles]\ndiameter = 0.01\ncount = 300\n"
                         "[deposition]\n[analysis]\nbox_sides = [0.03]\n";
  const Scenario scenario = load_scenario(file);
  std::ostringstream log;
  Campaign campaign(1, false, log, 2);
  const CaseRun standard = campaign.run("monosized", scenario, 7);
  const CaseRun own = campaign.run("monosized", scenario, 8, [](const CaseRun& c) {
    return "  own line: " + std::to_string(c.particle_count) + " spheres";
  });
  EXPECT_EQ(campaign.runs_done(), 2u);
  EXPECT_TRUE(standard.result.output_directory.empty());
  EXPECT_EQ(standard.particle_count, 300u);
  EXPECT_EQ(standard.result.report.scenario.seed, 7u);
  EXPECT_EQ(own.result.report.scenario.seed, 8u);
  Scenario at_seed = scenario;
  at_seed.seed = 7;
  Progress silent;
  RunControls controls;
  controls.threads = 1;
  EXPECT_EQ(standard.result.report.final.density.mean, run(at_seed, controls, silent).final.density.mean);
  const std::string text = log.str();
  EXPECT_EQ(text.rfind("monosized seed 7: density ", 0), 0u) << text;
  EXPECT_NE(text.find("\n  own line: 300 spheres\n"), std::string::npos) << text;
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 2) << text;  // one line per run
  std::ostringstream none;
  Campaign quiet(1, true, none, 1);
  quiet.run("monosized", scenario, 7);
  EXPECT_TRUE(none.str().empty());
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace aggpack
