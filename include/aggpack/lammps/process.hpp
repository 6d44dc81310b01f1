#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "aggpack/io/lammps_data.hpp"
#include "aggpack/io/scenario.hpp"
#include "aggpack/lammps/deck.hpp"

namespace aggpack {

// Running LAMMPS as a child process on a deck (lammps/deck.hpp) and reading what it left.

// dynamics.engine = "lammps": InputError, before any work, when the LAMMPS binary (or mpirun
// for several ranks) is not on PATH, naming the Debian packages that provide them.
void check_lammps_available(const Scenario& scenario);

// How LAMMPS is started: `lmp`, or `mpirun -np N lmp` for several ranks (shell-quoted).
std::string lammps_command_line(const DynamicsStage& stage);
// The deck written into `folder` and run there by LAMMPS, its output in lammps.log and
// lammps.out; returns its log's text. InputError naming the log when LAMMPS fails or leaves no
// settled.dump.
std::string run_lammps(const Scenario& scenario, const std::filesystem::path& folder, const LammpsDeck& deck);
// The log's lines that begin with `tag` (what the deck printed: "aggpack-batch: ", ...).
std::vector<std::string> tagged_lines(const std::string& log, const std::string& tag);
// The deck's last "aggpack-settled:" line: LAMMPS's time and energy per m g d at the end.
struct SettledLine {
  double time = 0.0, energy = 0.0;
};
SettledLine settled_line(const std::string& log, const std::filesystem::path& folder);
// A dump LAMMPS wrote (its last snapshot, or `timestep`'s), within the scenario's input limit.
LammpsBed read_lammps_dump(const std::filesystem::path& file, const Scenario& scenario,
                           std::optional<std::int64_t> timestep = {});

}  // namespace aggpack
