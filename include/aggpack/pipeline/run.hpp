#pragma once
#include <filesystem>
#include <optional>
#include <ostream>
#include <string>

#include <nlohmann/json.hpp>

#include "aggpack/io/scenario.hpp"

namespace aggpack {

struct RunOptions {
  ScenarioOverrides overrides;
  int threads = 0;  // 0: OpenMP's default
  std::optional<std::string> stop_after;
  bool quiet = false;
};

struct RunResult {
  std::filesystem::path output_directory;
  nlohmann::json summary;
};

// Loads the scenario, runs its stages, analyses the result and writes particles.csv,
// particles.vtp and summary.json atomically. Nothing is written when the input is bad.
RunResult run_scenario(const std::filesystem::path& scenario_file, const RunOptions& options, std::ostream& log);

// Validates a scenario (and the particle file it names) without running or writing.
Scenario check_scenario(const std::filesystem::path& scenario_file, const ScenarioOverrides& overrides);

}  // namespace aggpack
