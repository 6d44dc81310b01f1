#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "aggpack/core/particle_store.hpp"
#include "aggpack/io/scenario.hpp"

namespace aggpack {

// timeseries.csv: one row per sample of every settling run of a scenario.
class TimeSeries {
 public:
  void add(double time, std::uint32_t layer, double density, double translational_per_particle_mgd,
           double translational_energy, double rotational_energy, double mean_overlap, double max_overlap,
           double coordination);
  [[nodiscard]] std::string csv(const std::string& provenance) const;
  [[nodiscard]] std::size_t rows() const { return rows_; }

 private:
  std::string body_;
  std::size_t rows_ = 0;
};

// Settles the bed with the scenario's [dynamics] and [material] (particles whose layer is
// below `layer` are frozen), appending samples from `time_offset` on. Returns the stage's
// summary (ended_by, steps, time step, overlaps, ...).
nlohmann::json settle_bed(const Scenario& sc, ParticleStore& particles, std::uint32_t layer, double time_offset,
                          TimeSeries& series);

// Modelling notes for the dynamics stage: the law, the stiffness, what ended each run.
std::vector<std::string> dynamics_notes(const Scenario& sc, const nlohmann::json& dynamics_summary);

}  // namespace aggpack
