#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <ostream>
#include <span>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "aggpack/core/particle_store.hpp"
#include "aggpack/io/protocol.hpp"
#include "aggpack/io/scenario.hpp"
#include "aggpack/lammps/deck.hpp"
#include "aggpack/run/run.hpp"
#include "aggpack/run/settle_stage.hpp"

namespace aggpack {

// The DEM steps of a run with dynamics.engine = "lammps": the deck written into
// <output>/lammps/<step>_<k>/ (settle_layer_<k>, pour_part_<k>, tap_<k>), `lmp` (or
// `mpirun -np N lmp`) run there with its log kept, the result read back into `particles`
// (velocities set to zero: the bed is quiet), and the step reported as aggpack's own would be.
SettlingRun settle_in_lammps(const Scenario& scenario, ParticleStore& particles, std::uint32_t layer,
                             double time_offset, TimeSeries& series, Progress& progress);
PourRun pour_in_lammps(const Scenario& scenario, ParticleStore& particles, std::span<const double> radii,
                       const SphereMaterials& materials, const PouredShapes& shapes, const PourStep& step,
                       double time_offset, TimeSeries& series, Progress& progress);
TapReport tap_in_lammps(const Scenario& scenario, ParticleStore& particles, std::size_t tapping_index,
                        double time_offset, TimeSeries& series, Progress& progress);

// The spheres of a LAMMPS dump or data file put in place of `particles`' positions, matched by
// id (id k is the k-th sphere): the counts and the radii must agree (InputError naming `file`).
// Velocities are set to zero. Returns the file's format ("LAMMPS dump, timestep 1000", ...).
std::string take_positions_from_lammps(ParticleStore& particles, const std::filesystem::path& file,
                                       std::optional<std::int64_t> timestep, const Scenario& scenario);

// `aggpack export-lammps SCENARIO --out DIR`: runs the scenario's steps before its first DEM
// step and writes that step's deck into DIR. `aggpack export-lammps RUN_DIR --out DIR`: the
// final bed of a finished run (its particles.csv, with its scenario) and a deck that settles
// it, or taps it with `tap`; an interrupted run's bed, as it stood, is marked as not a final
// bed in the message and in the files. Returns the step exported, for messages.
std::string export_lammps(const std::filesystem::path& scenario_or_run, const ScenarioOverrides& overrides,
                          const std::filesystem::path& out, bool tap, std::ostream& log);

// `aggpack import-lammps FILE --scenario S`: the spheres of a LAMMPS dump (the last snapshot
// or `timestep`'s) or data file, analysed in S's container with S's analysis settings, into
// S's output folder (or --out) with aggpack's usual outputs.
RunResult import_lammps(const std::filesystem::path& file, std::optional<std::int64_t> timestep,
                        const std::filesystem::path& scenario_file, const RunOptions& options, std::ostream& log);

}  // namespace aggpack
