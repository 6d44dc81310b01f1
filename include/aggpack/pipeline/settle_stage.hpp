#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "aggpack/core/particle_store.hpp"
#include "aggpack/io/scenario.hpp"
#include "aggpack/pipeline/progress.hpp"
#include "aggpack/pipeline/reports.hpp"

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
// below `layer` are frozen), appending samples from `time_offset` on, with `threads` OpenMP
// threads (0: OpenMP's default). Returns what the run did (ended_by, steps, time step, ...).
SettlingRun settle_bed(const Scenario& sc, ParticleStore& particles, std::uint32_t layer, double time_offset,
                       int threads, TimeSeries& series, Progress& progress);

// Modelling notes for the dynamics stage: the law, the stiffness, what ended each run.
std::vector<std::string> dynamics_notes(const Scenario& sc, const SettlingReport& report);

}  // namespace aggpack
