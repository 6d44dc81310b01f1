// calibrate --dem's search on densities with closed forms (no DEM), and its file read back.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "aggpack/core/error.hpp"
#include "aggpack/io/dem_calibration_file.hpp"
#include "aggpack/studies/dem_calibration.hpp"

namespace {

using aggpack::SimulatedDensities;

// A density curve with a fixed standard error, as a search sees a series of seeds.
auto curve(double (*phi)(double), double standard_error) {
  return [phi, standard_error](double x) {
    SimulatedDensities d;
    d.what = "x";
    d.mean = phi(x);
    d.standard_error = standard_error;
    d.density = {d.mean};
    return d;
  };
}

double linear(double x) {
  return 0.64 - 0.2 * x;
}
double saturating(double x) {
  return 0.58 + 0.06 * std::exp(-8.0 * x);
}

// On a straight line the first interpolation is the root: three values, and the band is the
// standard error over the slope.
TEST(DemCalibration, FindsTheCrossingOfALineAtTheThirdValue) {
  const auto search = aggpack::find_crossing(curve(linear, 0.002), 0.0, 0.5, 0.60, 6, "rolling_friction");
  ASSERT_EQ(search.evaluations.size(), 3u);
  EXPECT_NEAR(search.value, 0.2, 1e-12);
  EXPECT_NEAR(search.band_low, 0.2 - 0.002 / 0.2, 1e-12);
  EXPECT_NEAR(search.band_high, 0.2 + 0.002 / 0.2, 1e-12);
  EXPECT_TRUE(search.converged);
  EXPECT_FALSE(search.band_clipped);
}

// On a curve the bracket closes from both sides (Illinois): without noise to stop it early,
// eight values bring the crossing to the closed form's within 1e-3.
TEST(DemCalibration, ClosesOnTheCrossingOfACurve) {
  const double target = 0.60;
  const double exact = -std::log((target - 0.58) / 0.06) / 8.0;  // 0.1373
  const auto search = aggpack::find_crossing(curve(saturating, 0.0), 0.0, 0.5, target, 8, "rolling_friction");
  EXPECT_EQ(search.evaluations.size(), 8u);
  EXPECT_NEAR(search.value, exact, 1e-3);
  for (const auto& e : search.evaluations) {
    EXPECT_GE(e.value, 0.0);
    EXPECT_LE(e.value, 0.5);
  }
  // Fewer values, a coarser answer, but still inside the range and on the right side of the ends.
  const auto short_search = aggpack::find_crossing(curve(saturating, 0.0), 0.0, 0.5, target, 3, "rolling_friction");
  EXPECT_EQ(short_search.evaluations.size(), 3u);
  EXPECT_GT(short_search.value, 0.0);
  EXPECT_LT(short_search.value, 0.5);
}

// A measurement within one standard error beyond an end is taken at that end, its band cut
// there; beyond it, no value of the range reaches it, and the message says which way to go.
TEST(DemCalibration, SaysWhenTheRangeCannotReachTheMeasurement) {
  const auto at_end = aggpack::find_crossing(curve(linear, 0.005), 0.0, 0.5, 0.643, 6, "rolling_friction");
  EXPECT_NEAR(at_end.value, 0.0, 1e-12);
  EXPECT_TRUE(at_end.band_clipped);
  for (const auto& [target, words] : std::vector<std::pair<double, std::vector<std::string>>>{
           {0.66, {"0.6600 is above the simulated 0.6400", "rolling_friction = 0", "densest end"}},
           {0.50, {"0.5000 is below the simulated 0.5400", "rolling_friction = 0.5", "--range"}}}) {
    try {
      (void)aggpack::find_crossing(curve(linear, 0.005), 0.0, 0.5, target, 6, "rolling_friction");
      ADD_FAILURE() << target << " accepted";
    } catch (const aggpack::InputError& e) {
      for (const std::string& w : words) EXPECT_NE(std::string(e.what()).find(w), std::string::npos) << e.what();
    }
  }
}

aggpack::DemCalibration a_calibration() {
  aggpack::DemCalibration c;
  c.scenario = "stone_sand.toml";
  c.protocol = "pour";
  c.parameter = "rolling_friction";
  c.materials = {"sand", "stone"};
  c.measured = 0.703;
  c.seeds = 3;
  c.range_low = 0.0, c.range_high = 0.5;
  c.search.value = 0.231, c.search.band_low = 0.2, c.search.band_high = 0.26;
  c.assignments = {"materials.sand.rolling_friction=0.231", "materials.stone.rolling_friction=0.231"};
  return c;
}

TEST(DemCalibration, ItsFileReadsBackWithWhatItWasFittedTo) {
  const std::string text = aggpack::to_json(a_calibration()).dump(1);
  ASSERT_TRUE(aggpack::is_dem_calibration_text(text));
  const aggpack::DemCalibrationFile f = aggpack::parse_dem_calibration(text, "dir/c.json");
  EXPECT_EQ(f.assignments, a_calibration().assignments);
  EXPECT_EQ(f.fitted_to,
            "rolling_friction = 0.231 (band 0.2 to 0.26) fitted by aggpack calibrate --dem to the measured density "
            "0.703 of the scenario's bed (stone_sand.toml; pour; 3 seeds) [dir/c.json]");
}

// A calibration file is user input: an edited one that sets another key, or a value that is no
// number, is refused naming the file and the element.
TEST(DemCalibration, RefusesADamagedFileNamingTheKey) {
  const auto with = [](const char* key, const nlohmann::json& value) {
    nlohmann::json j = aggpack::to_json(a_calibration());
    if (value.is_null())
      j.erase(key);
    else
      j[key] = value;
    return j.dump();
  };
  const std::vector<std::pair<std::string, std::vector<std::string>>> cases{
      {with("assignments", {"dynamics.time_step=1"}),
       {"assignments[0]", "\"dynamics.time_step=1\"", "rolling_friction"}},
      {with("assignments", {"materials.sand.rolling_friction=-0.1"}), {"assignments[0]", "a number >= 0"}},
      {with("assignments", {"materials.sand.rolling_friction=0.1x"}), {"assignments[0]"}},
      {with("assignments", {"materials.sand.rolling_friction=nan"}), {"assignments[0]"}},
      {with("assignments", {3}), {"assignments[0]", "a number", "\"key=value\" string"}},
      {with("assignments", nlohmann::json::array()), {"assignments", "an array"}},
      {with("assignments", nullptr), {"assignments", "missing"}},
      {with("measured", {{"density", "0.7"}, {"of", "x"}}), {"measured.density", "a string", "a number"}},
      {with("fit", nullptr), {"fit", "missing"}},
      {with("seeds", -2), {"seeds", "a count of seeds"}},
      {with("kind", "aggpack CPM calibration"), {"not a DEM calibration", "calibrate --dem"}},
      {"{", {"not JSON"}},
  };
  for (const auto& [text, words] : cases) {
    SCOPED_TRACE(text);
    try {
      (void)aggpack::parse_dem_calibration(text, "dir/c.json");
      ADD_FAILURE() << "accepted";
    } catch (const aggpack::InputError& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind("dir/c.json: ", 0), 0u) << message;
      for (const std::string& w : words) EXPECT_NE(message.find(w), std::string::npos) << w << " in " << message;
    }
  }
}

}  // namespace
