#pragma once
#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "aggpack/core/input_file.hpp"
#include "aggpack/core/container.hpp"
#include "aggpack/core/particle_store.hpp"
#include "aggpack/deposition/contact_geometry.hpp"
#include "aggpack/grains/shape_measures.hpp"

namespace aggpack {

// Reads a packing made by aggpack or another tool:
// - CSV with a header naming x, y, z and r (or radius, or d, or diameter), any column
//   order, other columns ignored;
// - plain text, whitespace separated: exactly four numbers "x y z r" per row, or a header
//   line naming the columns as for CSV (e.g. "id type x y z radius") and exactly that many
//   fields per row. Anything else is refused with the line number: a row of five or six
//   numbers is never guessed at.
// - a LAMMPS text dump (the last snapshot, or `timestep`'s) or a LAMMPS data file of
//   atom_style sphere (io/lammps_data.hpp), told apart by their first lines.
// Lines starting with '#' and blank lines are skipped. Values are multiplied by
// `length_unit` (metres per file unit). Throws InputError naming the file and line.
// Refuses a file that is not a regular file, or is over `max_bytes`, before reading it.
struct PackingFile {
  ParticleStore particles;
  std::string format;  // "CSV", "whitespace-separated text", "LAMMPS dump, timestep 1000 (the last of 3)", ...
  std::vector<std::string> materials;  // a "material" column's names, per particle; empty without one
  // A "grain" column (particles.csv of a run with grains): each sphere's grain, 1 up, 0 for a
  // sphere of its own; empty without one. The spheres are read as spheres either way.
  std::vector<std::uint32_t> grains;
};
PackingFile read_packing_file(const std::filesystem::path& file, double length_unit, double density,
                              std::uintmax_t max_bytes = kDefaultMaxInputFileBytes,
                              std::optional<std::int64_t> timestep = std::nullopt);
ParticleStore read_particle_file(const std::filesystem::path& file, double length_unit, double density,
                                 std::uintmax_t max_bytes = kDefaultMaxInputFileBytes);

// The same reader on text already in memory; `name` stands for the file in messages.
PackingFile parse_packing_text(std::string_view text, const std::string& name, double length_unit, double density,
                               std::optional<std::int64_t> timestep = std::nullopt);
ParticleStore parse_particle_text(std::string_view text, const std::string& name, double length_unit,
                                  double density);

// "id,x,y,z,r" in metres, one row per particle in store order, full double precision. Ids
// run 1..N in store order: the numbering of particles.vtp and of the LAMMPS files (one
// numbering across the bridge; LAMMPS has no atom 0). Given the names of the run's materials
// (a run of several), a last column "material" names each sphere's.
// With rigid grains, a `grain` column names each sphere's (1-based; 0 for a sphere of its own).
std::string particles_csv(const ParticleStore& particles, std::span<const std::string> material_names = {});

// The sieves between which a grain's intermediate dimension I lies, m: it passes `passing`
// (I <= passing) and is retained on `retained` (NaN for a grain of a size class: no sieves).
struct SieveInterval {
  double retained = std::numeric_limits<double>::quiet_NaN();
  double passing = std::numeric_limits<double>::quiet_NaN();
};

// grains.csv: one row per rigid grain (1-based id, as particles.csv's grain column): its centre
// of mass (m), orientation quaternion (body frame to space; the body frame is the grain's
// principal axes, x the longest), volume-equivalent diameter, L, I, S (m, `measures`, one per
// grain), mass (kg), template (1-based, the run's), its first sphere's id and its sphere count,
// the sieves (m) its I lies between (`sieves`, one per grain, or empty; empty cells without),
// and its coordination (grain_contact_counts: the grains and spheres it touches).
std::string grains_csv(const ParticleStore& particles, std::span<const GrainMeasure> measures,
                       std::span<const SieveInterval> sieves, std::span<const int> coordination);

// "id,support_1_kind,support_1_id,...,support_3_id": what each sphere (id 1..N) came to rest
// on in the deposition stage. A kind is sphere, floor, wall_x_low, wall_x_high, wall_y_low,
// wall_y_high or none; the id is the supporting sphere's, 0 for any other kind. Floor resters
// list only the floor.
std::string supports_csv(std::span<const Supports> supports);

// A bed read from a file: coincident spheres are refused; overlapping pairs deeper than
// `tolerance` x the smaller radius are refused with the worst pair (unless the file comes from
// a soft-contact DEM, `soft_contacts`, which accepts any overlap short of one centre inside the
// other sphere). The spheres of one rigid grain (the same `body`, when the store has the
// array) overlap as they are meant to: not checked against each other. Returns the deepest
// overlap found / smaller radius (0 when none).
struct PairOverlap {
  double depth_over_radius = 0.0;
  std::size_t i = 0, j = 0;  // the worst pair (data rows i + 1 and j + 1)
};
// The neighbour grid it uses is refused (InputError) beyond `max_grid_cells`.
PairOverlap check_particle_overlaps(const ParticleStore& particles, const Container& container, double tolerance,
                                    bool soft_contacts, const std::string& file, double max_grid_cells);

}  // namespace aggpack
