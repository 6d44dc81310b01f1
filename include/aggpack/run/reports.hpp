#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "aggpack/deposition/drop_and_roll.hpp"
#include "aggpack/dynamics/jig.hpp"
#include "aggpack/dynamics/pour.hpp"
#include "aggpack/dynamics/rod.hpp"
#include "aggpack/dynamics/settle.hpp"
#include "aggpack/dynamics/tap.hpp"

namespace aggpack {

// What the steps of a run report, as values: layers and settling runs add up by these
// types, and summary.json is written from them once (to_json), never read back.

// One deposition step (a layer, or the whole bed); `+=` adds a later layer.
struct DepositionReport {
  std::size_t requested = 0;
  DepositionStats stats;        // stats.requested is unused: `requested` counts the step's spheres
  double fill_height = 0.0;     // m
  double wall_clock_s = 0.0;
  std::uint32_t layers = 1;     // the parts the drop sequence is deposited in

  DepositionReport& operator+=(const DepositionReport& layer);
};

// A pour step: what was inserted, where, and how long the insertion took (dynamics/pour.hpp).
nlohmann::json to_json(const PourReport& report);

// A tapping step: the density after every tap (taps.csv) and what it cost (dynamics/tap.hpp).
nlohmann::json to_json(const TapReport& report);
// A rod step: each stroke's position, depth and peak force (rod_strokes.csv), the densities
// before and after (dynamics/rod.hpp); a jig step: the density after every drop (jig_drops.csv).
nlohmann::json to_json(const RoddingReport& report);
nlohmann::json to_json(const JigReport& report);
// Their lines of the console summary and their modelling notes (and a tapping's).
std::string console_line(const TapReport& report);
std::string modelling_note(const TapReport& report);
std::string console_line(const RoddingReport& report);
std::string console_line(const JigReport& report);
std::string modelling_note(const RoddingReport& report);
std::string modelling_note(const JigReport& report);

// One settling run (a layer, or the whole bed).
struct SettlingRun {
  std::uint32_t layer = 0;
  std::size_t particles_settled = 0, particles_frozen = 0;
  SettleEnd ended_by = SettleEnd::MaxTime;
  double simulated_time = 0.0;  // s
  std::size_t steps = 0;
  double time_step = 0.0, rayleigh_time = 0.0;  // s
  bool time_step_from_scenario = false;          // else time_step_safety x Rayleigh time
  double skin = 0.0;                              // m
  std::size_t neighbour_list_builds = 0;
  SettleSample last;                              // the final sample
  double wall_clock_s = 0.0;
  double particle_steps_per_second = 0.0;
  int threads = 1;                          // at most
  std::size_t steps_on_fewer_threads = 0;   // the DEM's choice (ThreadGovernor): faster then
  double memory_bytes_per_particle = 0.0;
  int lammps_ranks = 0;  // 0: aggpack's DEM ran it; else LAMMPS on that many ranks
  bool continues_dem_system = false;  // the DEM system of the step before, contact history and all
};

// Every settling run of a dynamics stage, in order.
struct SettlingReport {
  std::vector<SettlingRun> runs;
  [[nodiscard]] double simulated_time() const;
  [[nodiscard]] std::size_t steps() const;
  [[nodiscard]] std::size_t neighbour_list_builds() const;
  [[nodiscard]] double wall_clock_s() const;
  [[nodiscard]] double particle_steps_per_second() const;  // over all runs, weighted by their wall time
  [[nodiscard]] double memory_bytes_per_particle() const;  // the largest run's
  [[nodiscard]] std::size_t runs_ended_by_max_time() const;
};

// The forms summary.json has always had (the README's stable keys): `stages.deposition`
// and `stages.dynamics` without their density and coordination, which the analysis adds.
nlohmann::json to_json(const DepositionReport& report);
nlohmann::json to_json(const SettlingRun& run);
nlohmann::json to_json(const SettlingReport& report);

}  // namespace aggpack
