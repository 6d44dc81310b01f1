#pragma once
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "aggpack/core/container.hpp"
#include "aggpack/core/particle_store.hpp"

namespace aggpack {

// A LAMMPS data file of the bed for `atom_style sphere` (columns id type diameter density x
// y z; SI units), every number with the 17 digits that keep contacts exact, and a Velocities
// section (v and omega) when a sphere moves. The box is the container's footprint, from its
// floor to `z_top` (m), which must clear the highest sphere. Ids count from 1 in store order.
// Atom type m + 1 for a sphere of material m (of `densities`, kg/m^3, one per material); M + m + 1
// for the spheres flagged in `frozen` (a deck holds them still), 2M types in all (one material
// and nothing frozen: type 1 alone).
// A bed with rigid bodies (grains) is written for `atom_style hybrid sphere bond` instead
// (columns id type x y z diameter density molecule): a grain's spheres carry its index + 1 as
// their molecule id, a sphere of its own 0; lammps_rigid_bodies gives the grains' mass
// properties.
std::string lammps_data(const ParticleStore& particles, const Container& container, std::span<const double> densities,
                        double z_top,
                        std::span<const std::uint8_t> frozen = {});

// The `infile` of `fix rigid/small molecule` for the store's bodies (molecule id = body index
// + 1, in lammps_data's file): each one's mass, centre of mass (wrapped into a periodic box),
// inertia tensor in space, velocity and angular momentum, so that LAMMPS moves each grain with
// its union's mass properties, as aggpack does.
std::string lammps_rigid_bodies(const ParticleStore& particles, const Container& container);

// What a LAMMPS file gave: the spheres (in the order of their atom ids: id k is store index
// k - 1 when the ids are 1..N), and where they came from.
struct LammpsBed {
  ParticleStore particles;
  std::optional<std::int64_t> timestep;  // a dump's; none for a data file
  Box box;                               // the simulation box, in the file's units x length_unit
  std::size_t snapshots = 0;             // in a dump; 0 for a data file
};

// True when the text is a LAMMPS text dump (its first line "ITEM: TIMESTEP") or a LAMMPS
// data file (a title line, header lines such as "N atoms", then an "Atoms" section).
[[nodiscard]] bool is_lammps_dump(std::string_view text);
[[nodiscard]] bool is_lammps_data(std::string_view text);

// A LAMMPS text dump (`dump custom`): the snapshot of `timestep`, or the last one, whose
// ITEM: ATOMS columns name the position (x y z, unwrapped xu yu zu, or scaled xs ys zs,
// which the box bounds turn into lengths; all three of one kind) and the size (radius or
// diameter), in any order among other columns; rows are taken in the order of the id
// column (when there is one).
// Values x `length_unit` (metres per file unit: 1 for `units si`). InputError naming the
// file, the line and what is expected.
LammpsBed parse_lammps_dump(std::string_view text, const std::string& name, double length_unit, double density,
                            std::optional<std::int64_t> timestep = std::nullopt);
// A LAMMPS data file of `atom_style sphere` (Atoms rows: id type diameter density x y z,
// optionally three image flags, which shift the position by whole periods), rows in id order.
// The spheres take `density` (the scenario's material), not the file's.
LammpsBed parse_lammps_data(std::string_view text, const std::string& name, double length_unit, double density);

}  // namespace aggpack
