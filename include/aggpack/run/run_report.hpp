#pragma once
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "aggpack/core/particle_store.hpp"
#include "aggpack/deposition/contact_geometry.hpp"
#include "aggpack/io/scenario.hpp"
#include "aggpack/run/analyze.hpp"
#include "aggpack/run/generate_sizes.hpp"
#include "aggpack/run/predictions.hpp"
#include "aggpack/run/reports.hpp"
#include "aggpack/run/settle_stage.hpp"

namespace aggpack {

// An analysis made by a step during the run (the bed after deposition, say).
struct StageAnalysis {
  PackingReport report;
  double wall_clock_s = 0.0;
};

// A run stopped at a safe point by SIGINT or SIGTERM: what it had done.
struct Interruption {
  int signal_number = 0;
  std::string where;                 // "while settling at 0.1230 s simulated", ...
  std::size_t steps_completed = 0;   // of the protocol's steps, in order
  std::size_t steps_total = 0;
  std::optional<std::string> checkpoint;  // where the last checkpoint was taken; none written
};

// A bed handed to LAMMPS by an export_lammps step, or taken from it by an import_lammps step.
struct LammpsExchange {
  std::string direction;  // "export" or "import"
  std::string path;       // the folder written, or the file read
  std::string what;       // the deck's step ("settle, layer 1"), or the file's format
  std::size_t spheres = 0;
};

// A frame of the DEM written for an animation (output.frame_interval, RunControls::on_frame).
struct FrameRecord {
  std::string file;               // relative to the output folder: "frames/frame_00001.vtp", ...
  double time = 0.0;              // s, the series' time of the sample it was taken at
  std::uint64_t fingerprint = 0;  // of the bed's positions and radii (bed_fingerprint)
  template <class Archive>
  void serialize(Archive& ar) {
    ar(file, time, fingerprint);
  }
};

// Everything a run produced, as values: what the steps reported, the final analysis, the
// beds. summary_json() writes summary.json from it; nothing reads it back from JSON.
struct RunReport {
  Scenario scenario;
  std::optional<GeneratedSizes> sizes;          // when the run generated particles
  double largest_boundary_overlap = 0.0;        // of a particle file's spheres, / r
  double largest_pair_overlap = 0.0;            // of two of a particle file's spheres, / smaller r
  std::string input_format;                     // of a particle file ("CSV", "LAMMPS dump, timestep 1000", ...)
  std::optional<DepositionReport> deposition;   // all deposit steps added up
  std::vector<PourReport> pours;                // every pour step's insertion (its DEM run is in dynamics)
  std::vector<TapReport> tappings;              // every tap step's compaction curve
  std::vector<RoddingReport> roddings;          // every rod step's strokes (dynamics/rod.hpp)
  std::vector<JigReport> jiggings;              // every jig step's compaction curve (dynamics/jig.hpp)
  std::optional<SettlingReport> dynamics;       // every settle and pour step's DEM run
  std::map<std::string, StageAnalysis> analyses;  // by the analyse step's report_as
  PackingReport final;                            // the bed at the end
  bool dynamics_skipped = false;                  // [dynamics] given, but --stop-after ended the run before it
  ParticleStore particles;                        // the final bed
  std::optional<ParticleStore> deposited;         // the bed after a single deposition, when DEM then moved it
  std::map<std::string, ParticleStore> snapshots;  // beds copied by snapshot steps, by name
  std::map<std::string, double> snapshot_times;    // s of simulated time at each snapshot step
  std::vector<FrameRecord> frames;                 // the frames written so far, in order
  std::uint64_t next_frame_multiple = 0;           // the next frame: at or after this x frame_interval
  double simulated_time = 0.0;                     // s, every DEM step's, when the steps ended
  std::vector<LammpsExchange> lammps_exchanges;   // export_lammps and import_lammps steps, in order
  std::vector<Supports> supports;                 // what each sphere rested on after deposition
  TimeSeries series;                              // the settling runs' samples
  std::map<std::string, double> wall_clock_s;     // input, sizes, deposition, dynamics, analysis...
  std::optional<Interruption> interrupted;        // set when a signal stopped the run: no final analysis
  std::optional<std::string> resumed_from;        // the checkpoint's safe point, when resumed
  std::optional<std::string> checkpoint_error;    // why checkpoints stopped, when a write failed
  std::string working_directory;  // the run's, absolute: where a relative scenario.file lies (empty: unknown)
  // Rigid grains (a component's shape): the libraries' report (libraries_json), and each
  // template's component; empty for a run of spheres.
  nlohmann::json grain_libraries;
  std::vector<std::uint32_t> grain_shape_component;

  // The mean virtual-box density after deposition / after dynamics; NaN when not run (after
  // dynamics: or interrupted, before the final analysis).
  [[nodiscard]] double density_after_deposition() const;
  [[nodiscard]] double density_after_dynamics() const;
  // The final analysis's mean virtual-box density; NaN for an interrupted run (none was made).
  [[nodiscard]] double final_density() const;
  // The last DEM stage that moved the bed, in words ("tapping", "pour", "DEM settling"): what
  // density_after_dynamics is after.
  [[nodiscard]] std::string last_dem_stage() const;
  // The analytic models on the run's size distribution (summary.json's predictions).
  [[nodiscard]] Predictions predictions() const;
  // Whether the DEM left the bed at rest: its last sample's translational energy per particle
  // at or below the quiet criterion's (dynamics.kinetic_fraction); none when no DEM moved the
  // bed. A run cut by max_time while the bed still moves reports the density of a moving bed,
  // and says so (summary.json's settled, the console).
  struct RestState {
    bool settled = false;
    double translational_energy_per_particle_mgd = 0.0;
    double quiet_below = 0.0;
  };
  [[nodiscard]] std::optional<RestState> rest_state() const;
  // Every modelling choice the results depend on, in words (summary.json's modelling_notes).
  [[nodiscard]] std::vector<std::string> modelling_notes() const;
  // summary.json (README, "Output files"), `output_seconds` and `total_seconds` included.
  [[nodiscard]] nlohmann::json summary_json(double output_seconds, double total_seconds) const;
  // The terminal's result lines.
  [[nodiscard]] std::string console_summary(const std::filesystem::path& written_to) const;
};

// A fingerprint of a bed's positions and radii, to tell whether two frames show one bed.
[[nodiscard]] std::uint64_t bed_fingerprint(const ParticleStore& bed);
// Frame `number`'s file (from 1), relative to the output folder: "frames/frame_00001.vtp".
[[nodiscard]] std::string frame_file_name(std::size_t number);

}  // namespace aggpack
