// CPM's calibration read backwards from densities the model itself made.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "aggpack/core/error.hpp"
#include "aggpack/studies/calibration.hpp"

namespace {

TEST(Calibration, RecoversTheKAndBetaThatMadeTheDensities) {
  const aggpack::ModelDistribution mix{{{0.0254, 0.0254, 0.0254, 0.8}, {0.0127, 0.0127, 0.0127, 0.2}}, "test"};
  for (const auto& [k, beta] : std::vector<std::pair<double, double>>{{4.1, 0.72}, {4.75, 0.66}, {9.0, 0.70}}) {
    const double mono = beta / (1.0 + 1.0 / k);
    const double phi = aggpack::cpm(mix, std::vector<double>{beta}, k).density;
    const auto fit = aggpack::solve_calibration(mix, mono, phi);
    EXPECT_NEAR(fit.compaction_index, k, 1e-6 * k) << k << " " << beta;
    EXPECT_NEAR(fit.beta, beta, 1e-8) << k << " " << beta;
  }
}

TEST(Calibration, SaysSoWhenNoKFits) {
  const aggpack::ModelDistribution mix{{{0.0254, 0.0254, 0.0254, 0.8}, {0.0127, 0.0127, 0.0127, 0.2}}, "test"};
  // A mix looser than its monosized bed: CPM always gains from a second size.
  EXPECT_THROW((void)aggpack::solve_calibration(mix, 0.60, 0.55), aggpack::InputError);
  EXPECT_THROW((void)aggpack::solve_calibration(mix, 1.2, 0.55), aggpack::InputError);
}

// What aggpack calibrate writes, with `cpm` in place of its cpm object.
std::string calibration_file(const std::string& cpm) {
  return R"({"aggpack_version": "x", "kind": "aggpack CPM calibration", "scenario_file": "s.toml", "protocol": "deposit",
             "seeds": 3, "cpm": )" + cpm + "}";
}
const std::string kCpm = R"({"compaction_index": 6.5, "compaction_index_range": [6.0, null],
                             "residual_packing_density": 0.7, "residual_packing_density_range": [0.69, 0.71]})";

TEST(Calibration, ReadsWhatCalibrateWrites) {
  const aggpack::ModelParameters p = aggpack::parse_calibration(calibration_file(kCpm), "c.json");
  EXPECT_EQ(p.compaction_index, 6.5);
  EXPECT_EQ(p.beta, 0.7);
  EXPECT_NE(p.compaction_source.find("c.json) from s.toml (deposit; 3 seeds); range 6 to unbounded"), std::string::npos)
      << p.compaction_source;
  EXPECT_NE(p.beta_source.find("range 0.69 to 0.71"), std::string::npos) << p.beta_source;
}

// Every damaged file is an InputError naming the file, the key and what is expected (an empty
// range once crashed, a one-element one was read past its end).
TEST(Calibration, RefusesADamagedFileNamingTheKey) {
  const auto range = [](const std::string& r) {
    return calibration_file(R"({"compaction_index": 6.5, "compaction_index_range": )" + r +
                            R"(, "residual_packing_density": 0.7, "residual_packing_density_range": [0.69, 0.71]})");
  };
  const std::vector<std::pair<std::string, std::vector<std::string>>> cases{
      {range("[]"), {"cpm.compaction_index_range", "an empty array", "[low, high]"}},
      {range("[6.0]"), {"cpm.compaction_index_range", "an array of 1 element", "[low, high]"}},
      {range("[6.0, 7.0, 8.0]"), {"cpm.compaction_index_range", "an array of 3 elements"}},
      {range("{}"), {"cpm.compaction_index_range", "an object"}},
      {range("6.0"), {"cpm.compaction_index_range", "a number"}},
      {range(R"(["6", 7])"), {"cpm.compaction_index_range[0]", "a string", "a number or null"}},
      {range("[6, [7]]"), {"cpm.compaction_index_range[1]", "an array"}},
      {calibration_file(R"({"compaction_index": 6.5, "compaction_index_range": [6, 7], "residual_packing_density": 0.7})"),
       {"cpm.residual_packing_density_range", "missing"}},
      {calibration_file(R"({"compaction_index": "6.5"})"), {"cpm.compaction_index", "a string", "expected a number"}},
      {calibration_file("[1, 2]"), {"cpm", "an array", "expected an object"}},
      {R"({"kind": "aggpack CPM calibration"})", {"cpm", "missing"}},
      {R"({"kind": 3, "cpm": {}})", {"not a calibration written by aggpack calibrate"}},
      {R"([{"kind": "aggpack CPM calibration"}])", {"not a calibration written by aggpack calibrate"}},
      {"7", {"not a calibration written by aggpack calibrate"}},
      {R"({"kind": "aggpack CPM calibration", "cpm": )" + kCpm + R"(, "seeds": 1e30})", {"seeds", "a number"}},
      {R"({"kind": "aggpack CPM calibration", "cpm": )" + kCpm + R"(, "seeds": -3})", {"seeds", "expected a count"}},
      {R"({"kind": "aggpack CPM calibration", "cpm": )" + kCpm + R"(, "protocol": 5})", {"protocol", "expected a string"}},
      {calibration_file(R"({"compaction_index": -1, "compaction_index_range": [6, 7], "residual_packing_density": 0.7,
                            "residual_packing_density_range": [0.69, 0.71]})"),
       {"K = -1", "K > 0"}},
      {"{", {"not JSON"}},
  };
  for (const auto& [text, words] : cases) {
    SCOPED_TRACE(text);
    try {
      (void)aggpack::parse_calibration(text, "dir/c.json");
      ADD_FAILURE() << "accepted";
    } catch (const aggpack::InputError& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind("dir/c.json: ", 0), 0u) << message;
      for (const std::string& word : words) EXPECT_NE(message.find(word), std::string::npos) << word << " in " << message;
    }
  }
}

}  // namespace
