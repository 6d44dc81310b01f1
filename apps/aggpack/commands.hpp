#pragma once
// The subcommands of the aggpack command line, in groups. Each group's function adds its
// subcommands and their options to the app, in the order `aggpack --help` lists them, and
// returns for each what runs when it is the one given.
#include <functional>
#include <vector>

#include <CLI/CLI.hpp>

#include "aggpack/core/stop_request.hpp"

// A subcommand, and what runs when the command line gives it (after parsing): the exit code.
// It may throw aggpack::InputError (exit code 2) or another exception (1).
struct Subcommand {
  CLI::App* app;
  std::function<int()> run;
};

// --threads of the subcommands that simulate: the most OpenMP threads, 0 (all cores) or 1 to
// kMaxThreads (the DEM takes fewer when fewer are faster).
CLI::Option* add_threads_option(CLI::App* cmd, int& threads);

// run, resume and check (run_commands.cpp).
std::vector<Subcommand> add_run_commands(CLI::App& app);
// analyze, grading, predict and material: one bed, grading or material file, no simulation (bed_commands.cpp).
std::vector<Subcommand> add_bed_commands(CLI::App& app);
// calibrate, whole-grading, reproduce and sweep: series of runs (study_commands.cpp). reproduce
// finds the shipped scenarios from argv[0] and records the command line.
std::vector<Subcommand> add_study_commands(CLI::App& app, int argc, char** argv);
// export-lammps and import-lammps (run_commands.cpp).
std::vector<Subcommand> add_lammps_commands(CLI::App& app);
// test c29 and test c1252: a standard's test of one aggregate, simulated (lab_commands.cpp).
std::vector<Subcommand> add_lab_commands(CLI::App& app);
// blend: blends of materials by CPM at their betas (blend_command.cpp).
Subcommand add_blend_command(CLI::App& app);
// specimen: a concrete specimen for meso-model codes (specimen_command.cpp).
Subcommand add_specimen_command(CLI::App& app);

// SIGINT and SIGTERM from now on ask the work to stop at its next safe point (a second one ends
// the process at once): the request they set, for the library's `stop` (run_commands.cpp).
const aggpack::StopRequest& stop_on_signals();
