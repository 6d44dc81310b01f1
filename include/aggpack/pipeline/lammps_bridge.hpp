#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <ostream>
#include <string>

#include "aggpack/core/particle_store.hpp"
#include "aggpack/io/scenario.hpp"
#include "aggpack/pipeline/run.hpp"
#include "aggpack/pipeline/settle_stage.hpp"

namespace aggpack {

// A settle step handed to LAMMPS: the bed as a data file and an input deck that settles it as
// the step would in aggpack (README, "Running larger beds on many cores or a cluster").
struct LammpsDeck {
  std::string data;  // bed.data: atom_style sphere, the spheres below `layer` of type 2 (held still)
  std::string deck;  // settle.in: runs unchanged with `lmp -in settle.in` and under mpirun
  static constexpr const char* kDataFile = "bed.data";
  static constexpr const char* kDeckFile = "settle.in";
  static constexpr const char* kDumpFile = "settled.dump";  // written by the deck at the end
};

// The deck for the settle step of `layer` on `bed`: the scenario's contact law with its
// LAMMPS keywords (contact_law_registry), walls or periodic sides, gravity, the same time
// step and skin, and the quiet criterion's energy condition or max_time as the stopping rule.
LammpsDeck lammps_settle_deck(const Scenario& scenario, const ParticleStore& bed, std::uint32_t layer);

// dynamics.engine = "lammps": InputError, before any work, when the LAMMPS binary (or mpirun
// for several ranks) is not on PATH, naming the Debian packages that provide them.
void check_lammps_available(const Scenario& scenario);

// A settle step run by LAMMPS: the deck and the bed written into
// <output>/lammps/settle_layer_<k>/, `lmp` (or `mpirun -np N lmp`) run there with its log
// kept, the settled positions read back into `particles` (velocities set to zero: the bed is
// quiet), one sample appended to `series`, and the run reported as aggpack's own would be.
SettlingRun settle_in_lammps(const Scenario& scenario, ParticleStore& particles, std::uint32_t layer,
                             double time_offset, TimeSeries& series, Progress& progress);

// `aggpack export-lammps SCENARIO --out DIR`: runs the scenario's steps before its first DEM
// step (which must be a settle step) and writes bed.data and settle.in into DIR. Returns the
// step exported ("dynamics, layer 1 of 1").
std::string export_lammps(const std::filesystem::path& scenario_file, const ScenarioOverrides& overrides,
                          const std::filesystem::path& out, std::ostream& log);

// `aggpack import-lammps FILE --scenario S`: the spheres of a LAMMPS dump (the last snapshot
// or `timestep`'s) or data file, analysed in S's container with S's analysis settings, into
// S's output folder (or --out) with aggpack's usual outputs.
RunResult import_lammps(const std::filesystem::path& file, std::optional<std::int64_t> timestep,
                        const std::filesystem::path& scenario_file, const RunOptions& options, std::ostream& log);

}  // namespace aggpack
