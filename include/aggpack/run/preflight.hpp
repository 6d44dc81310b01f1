#pragma once
#include <filesystem>
#include <optional>
#include <span>

#include "aggpack/core/option_names.hpp"
#include "aggpack/io/scenario.hpp"
#include "aggpack/run/generate_sizes.hpp"
#include "aggpack/run/output_folder.hpp"  // check_output_directory

namespace aggpack {

struct RunGrains;

// The checks of everything a run can know before computing. `aggpack check` and the start of
// `aggpack run` call the same functions, so they refuse the same inputs with the same words;
// each throws InputError naming the file, the key, what is wrong and what is expected.

// The most OpenMP threads a run takes (--threads, RunControls::threads); 0 means OpenMP's
// default (all cores).
inline constexpr int kMaxThreads = 256;
void check_thread_count(int threads, OptionStyle named = OptionStyle::Cli);

// The particle count and memory against [limits], a grain counted as its member spheres: before
// any sizes are drawn, the expected amount (drawn = false); after, the amount drawn.
void check_amount(const Scenario& scenario, const ExpectedAmount& amount, bool drawn);

// output.frame_interval against the DEM: frames are taken at aggpack's own DEM's samples (so
// not more often than dynamics.sample_interval), written as VTP, and at most kMaxFrames of
// them over the protocol's DEM budget (max_time for each settle or pour step, every tap and
// rest of each tap step).
inline constexpr double kMaxFrames = 10000;
void check_frames(const Scenario& scenario);

// Rodding and jigging (run/preflight_compaction.cpp): the rod against the container's section,
// the rod's speed and the drop's impact speed against the time step (each at most a tenth of
// the smallest radius per step), the lift below g. InputError naming the key.
void check_compaction(const Scenario& scenario, double time_step, double smallest_radius);
// A rod or jig step's most samples (one a sample interval `every`) and most simulated time;
// 0 for any other step.
double compaction_samples(const Scenario& scenario, const Step& step, double every);
double compaction_time(const Scenario& scenario, const Step& step);

// Once the radii are known (generated, or read from the particle file): the spheres against
// the container, the fill height and the boxes; the time step against the contact law's
// stability limit; the neighbour grid's cells and the profiles' bins against [limits].
// `solid_volume`: the particles' own, when they are not the spheres of `radii` (grains: their
// reaches are the radii, their unions the volume).
void check_sizes(const Scenario& scenario, std::span<const double> radii,
                 std::optional<double> solid_volume = std::nullopt);

// Particles from a file must lie in the container; periodic sides wrap x and y (moving the
// positions). Overlaps of the floor or a wall up to `tolerance` x r are a settled bed's
// contacts and are kept; a deeper one is refused. Returns the largest overlap / r.
double fit_into_container(ParticleStore& particles, const Container& container, double tolerance,
                          const std::filesystem::path& file);

// A bed taken from a file at a protocol step (import_lammps): in the container and no two
// spheres coincident or overlapping beyond the scenario's tolerances, as particles.from.
void check_imported_bed(const Scenario& scenario, ParticleStore& bed, const std::filesystem::path& file);

// The protocol's steps against the bed each finds: `bed_radii` (a particle file's) to start
// with, then the parts of `to_place` (the generated sizes) each deposit or pour step adds. A
// part with no sphere, a step on an empty bed, or an import_lammps file that is not of the bed
// (format, timestep, count, radii, positions) is refused before any work.
// With `grains` (non-empty), the particles of `to_place` that are grains place their spheres
// (an import's file holds those, a grain's own overlapping as they are meant to).
void check_protocol_beds(const Scenario& scenario, std::span<const double> bed_radii,
                         std::span<const double> to_place, const RunGrains* grains = nullptr);


}  // namespace aggpack
