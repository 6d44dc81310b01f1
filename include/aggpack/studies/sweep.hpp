#pragma once
#include <filesystem>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace aggpack {

struct SweepOptions {
  std::filesystem::path scenario;      // a coarse/fine mix ([particles] with coarse, fine, ca_fa)
  std::vector<double> fa_percent;      // fine aggregate, % of the aggregate volume, per point
  int seeds = 3;
  std::filesystem::path out = "out/sweep";
  std::vector<std::string> sets;       // --set overrides applied to every run
  std::map<std::string, std::string> typed_as;  // a set -> the option it came from, for messages (--calibration)
  // Three or more d_min of the fine grading: each blend is simulated at each, and CPM carries the
  // series to the blend's whole grading (whole_grading.hpp); none: the scenario's own cut-off.
  std::vector<double> cut_offs;
  std::vector<std::string> cut_off_texts;  // each as the user typed it, for messages (empty: none)
  std::optional<std::filesystem::path> calibration;  // CPM's K and beta for that; none: the scenario's or the defaults
  std::optional<std::string> stop_after;
  int threads = 0;
  bool quiet = false;
  bool resume = false;  // continue the runs an interrupted sweep into `out` left checkpoints of
};

// The densest blend: runs the scenario at each fine fraction (Ca/Fa = (100 - Fa) / Fa) with
// seeds 1..N and writes sweep.csv, sweep.svg (density against Fa % with sd error bars) and
// sweep.json (every point and the best blend). With cut-offs, each blend is run at each cut-off
// and its whole grading estimated; the best blend is then the one of the densest whole grading.
// Returns sweep.json's content.
nlohmann::json sweep(const SweepOptions& options, std::ostream& log);

// Parses "25:45:5" (from:to:step, inclusive) or "28,32,36" into fine-fraction percentages.
std::vector<double> parse_fa_points(const std::string& text);

}  // namespace aggpack
