#pragma once

#include <filesystem>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "aggpack/core/particle_store.hpp"
#include "aggpack/dynamics/pour.hpp"
#include "aggpack/io/dem_setup.hpp"
#include "aggpack/io/protocol.hpp"
#include "aggpack/io/scenario.hpp"

namespace aggpack {

// The DEM steps LAMMPS can run for aggpack.
using LammpsStep = DemStep;

// A DEM step handed to LAMMPS: the bed as a data file and an input deck that runs the step as
// aggpack would (README, "Running larger beds on many cores or a cluster"), with the law's
// LAMMPS keywords (contact_law_registry), walls or periodic sides, gravity, the same time step
// and skin, and the quiet criterion's energy condition or max_time as the stopping rule.
//  - settle: bed.data (the spheres of the layers below the step's, atom type 2, held still)
//    and settle.in;
//  - pour: bed.data (the bed before the pour), pour_batch_<k>.data (each batch's random gas,
//    aggpack's own, its heights from its slab's bottom: the deck lifts it to the bed's top plus
//    the gap when it comes in) and pour.in;
//  - tap: bed.data and tap.in, the container (floor and walls) a moving region of
//    `fix wall/gran/region`; the deck writes tap_<k>.dump after each tap's rest.
// Grains (a bed with rigid bodies, or a pour of them): the data file is of `atom_style hybrid
// sphere bond`, each grain's spheres one molecule, moved as a rigid body by `fix rigid/small
// molecule` with the union's mass properties from bodies.txt (lammps_rigid_bodies) and gravity
// at its centre of mass; a pour of grains, or into a bed of them, is one batch, in bed.data
// (rigid/small takes its bodies once, when it is defined).
// Every deck ends by writing settled.dump, and runs unchanged with `lmp -in <deck>` and under
// mpirun.
struct LammpsDeck {
  std::string step;       // what it runs, for messages: "settle, layer 1", "pour, part 1 of 1", "tap"
  std::string deck_file;  // settle.in, pour.in or tap.in
  std::vector<std::pair<std::string, std::string>> files;  // name, contents: the data files and the deck
  static constexpr const char* kDataFile = "bed.data";
  static constexpr const char* kBodiesFile = "bodies.txt";  // with grains only
  static constexpr const char* kDumpFile = "settled.dump";
  static constexpr const char* kLogFile = "lammps.log";
  [[nodiscard]] const std::string& text(const std::string& name) const;  // std::out_of_range if absent
};

// The deck of `step` on `bed` (as it is before the step). A pour step takes the radii of its
// part of the drop sequence (a grain's: its reach at its size), their materials (indices;
// empty: all [material]) and their shapes (PouredShapes: a shape of reach 1, or none for a
// sphere); the others take none. InputError for a pour of several batches with grains.
LammpsDeck lammps_deck(const Scenario& scenario, const ParticleStore& bed, const LammpsStep& step,
                       std::span<const double> pour_radii = {}, std::span<const std::uint8_t> pour_materials = {},
                       const PouredShapes& pour_shapes = {});

// Each of the deck's files written atomically into `folder` (made if missing).
void write_lammps_deck(const std::filesystem::path& folder, const LammpsDeck& deck);

// The Verlet skin a deck gives LAMMPS: the scenario's, else DemSystem's default.
double lammps_skin(const DemSetup& setup, double r_min);

}  // namespace aggpack
