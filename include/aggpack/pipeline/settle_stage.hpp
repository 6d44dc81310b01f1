#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "aggpack/core/particle_store.hpp"
#include "aggpack/io/scenario.hpp"
#include "aggpack/pipeline/progress.hpp"

namespace aggpack {

// One sample of a settling run (a row of timeseries.csv).
struct TimeSample {
  double time;
  std::uint32_t layer;
  double density;  // NaN while the virtual boxes do not fit the bed
  double translational_per_particle_mgd, translational_energy, rotational_energy;
  double mean_overlap, max_overlap, coordination;
};

// timeseries.csv: one row per sample of every settling run of a scenario. Like every CSV
// aggpack writes, its first line is the header (provenance lives in summary.json).
struct TimeSeries {
  std::vector<TimeSample> samples;
  [[nodiscard]] std::string csv() const;
};

// Settles the bed with the scenario's [dynamics] and [material] (particles whose layer is
// below `layer` are frozen), appending samples from `time_offset` on. Returns the stage's
// summary (ended_by, steps, time step, overlaps, ...).
nlohmann::json settle_bed(const Scenario& sc, ParticleStore& particles, std::uint32_t layer, double time_offset,
                          TimeSeries& series, Progress& progress);

// Modelling notes for the dynamics stage: the law, the stiffness, what ended each run.
std::vector<std::string> dynamics_notes(const Scenario& sc, const nlohmann::json& dynamics_summary);

}  // namespace aggpack
