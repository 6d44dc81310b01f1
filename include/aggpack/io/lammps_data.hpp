#pragma once
#include <string>

#include "aggpack/core/container.hpp"
#include "aggpack/core/particle_store.hpp"

namespace aggpack {

// A LAMMPS data file of the bed for `atom_style sphere` (columns id type diameter density x
// y z; one atom type; SI units), every number with the 17 digits that keep contacts exact.
// The box is the container's footprint, from its floor to `z_top` (m), which must clear
// the highest sphere. Ids count from 1 in store order.
std::string lammps_data(const ParticleStore& particles, const Container& container, double density, double z_top);

}  // namespace aggpack
