#pragma once
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "aggpack/core/particle_store.hpp"
#include "aggpack/io/dem_setup.hpp"
#include "aggpack/io/scenario.hpp"
#include "aggpack/run/progress.hpp"
#include "aggpack/run/safe_point.hpp"
#include "aggpack/run/reports.hpp"

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

// What a DEM step takes beyond the scenario: OpenMP threads (0: OpenMP's default; the results
// do not depend on them); the stop request and the safe point, both met after every sample
// (null: none); the step's state from a checkpoint, to continue from (null: start afresh);
// and what to do with the bed at every sample, after it is recorded (the run's frames; null:
// nothing), given the sample's series time and the bed as it stands.
using SampleObserver = std::function<void(double time, const ParticleStore& bed)>;
class CarriedDem;
struct StageControls {
  int threads = 0;
  const StopRequest* stop = nullptr;
  SafePoint* safe_point = nullptr;
  const std::string* resume_state = nullptr;
  const SampleObserver* at_sample = nullptr;
  CarriedDem* carried = nullptr;  // the run's DEM system, continued from step to step; null: a new one per step
};


// Settles the bed with the scenario's [dynamics] and [material] (particles whose layer is
// below `layer` are frozen), appending samples from `time_offset` on, with `threads` OpenMP
// threads (0: OpenMP's default). Returns what the run did (ended_by, steps, time step, ...).
SettlingRun settle_bed(const Scenario& sc, ParticleStore& particles, std::uint32_t layer, double time_offset,
                       const StageControls& controls, TimeSeries& series, Progress& progress);

// Pours `radii` (part `part` of the drop sequence) onto the bed with the scenario's [pour],
// [dynamics] and [material]: each batch is inserted as a random gas in a slab above the bed's
// top, the next once the last has had the time to fall through its slab's height, then the
// whole bed falls until quiet.
// The DEM grows as the batches come in; the contact history is kept throughout.
struct PourRun {
  PourReport pour;
  SettlingRun settling;
};
PourRun pour_bed(const Scenario& sc, ParticleStore& particles, std::span<const double> radii,
                 const SphereMaterials& materials, const PouredShapes& shapes, std::uint32_t part,
                 double time_offset, const StageControls& controls, TimeSeries& series, Progress& progress);

// Taps the bed with the scenario's [tapping], [dynamics] and [material]: each tap moves the
// container (floor and walls) through half a sine period of peak acceleration Gamma g, then the
// bed rests; the box density is measured after every rest.
TapReport tap_bed(const Scenario& sc, ParticleStore& particles, double time_offset, const StageControls& controls,
                  TimeSeries& series, Progress& progress);

// Rods the bed's top layer with the scenario's [rodding] (into the layer below when the bed has
// layers below its top one, else to the floor: RodDepth::Auto), [dynamics] and [material].
RoddingReport rod_bed(const Scenario& sc, ParticleStore& particles, double time_offset, const StageControls& controls,
                      TimeSeries& series, Progress& progress);
// Jigs the bed with the scenario's [jigging]: each drop lifts the container and drops it on its
// base, then the bed rests; the box density is measured after every rest.
JigReport jig_bed(const Scenario& sc, ParticleStore& particles, double time_offset, const StageControls& controls,
                  TimeSeries& series, Progress& progress);

// Modelling notes for the dynamics stage: the law, the stiffness, what ended each run.
std::vector<std::string> dynamics_notes(const Scenario& sc, const SettlingReport& report);

}  // namespace aggpack
