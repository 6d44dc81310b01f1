#pragma once
#include <filesystem>
#include <optional>
#include <ostream>
#include <string>

#include <nlohmann/json.hpp>

#include "aggpack/core/particle_store.hpp"
#include "aggpack/io/scenario.hpp"
#include "aggpack/pipeline/progress.hpp"
#include "aggpack/pipeline/settle_stage.hpp"

namespace aggpack {

struct RunOptions {
  ScenarioOverrides overrides;
  int threads = 0;  // 0: OpenMP's default
  std::optional<std::string> stop_after;
  bool quiet = false;
  Progress* progress = nullptr;  // live progress on a terminal; none when null
};

struct RunResult {
  std::filesystem::path output_directory;
  nlohmann::json summary;
  ParticleStore particles;                   // the final bed
  std::optional<ParticleStore> deposited;    // the bed after deposition, when DEM then moved it
  TimeSeries series;                         // the settling runs' samples (empty without dynamics)
};

// Loads the scenario, runs its stages, analyses the result and writes particles.csv,
// particles.vtp and summary.json atomically. Nothing is written when the input is bad.
RunResult run_scenario(const std::filesystem::path& scenario_file, const RunOptions& options, std::ostream& log);

// Validates a scenario (and the particle file it names) without running or writing.
Scenario check_scenario(const std::filesystem::path& scenario_file, const ScenarioOverrides& overrides);

}  // namespace aggpack
