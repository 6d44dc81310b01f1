// A bed seen from Python: the spheres (and grains) of a ParticleStore that something else
// owns (a run's report) or that the bed owns (one made from arrays). Its arrays are numpy
// views into the store, read-only, each keeping the Bed, and so the store, alive.
#pragma once
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "aggpack/core/particle_store.hpp"
#include "aggpack/io/scenario.hpp"

namespace aggpack::python {

struct PyBed {
  std::shared_ptr<const ParticleStore> store;  // may alias its owner's (a report's) lifetime
  std::string source;  // what it is, in messages: a file's path, "the run's bed", "the bed from arrays"
  std::string format;  // a file's ("CSV", "LAMMPS dump, timestep 1000 (the last of 3)", ...); empty otherwise
  // A file's material column, each sphere's material by name (the store's are then all 0): a
  // run from the bed takes them by name from its scenario's materials. Empty otherwise.
  std::vector<std::string> material_names;
};

// The bed a run of `sc` starts from: the store itself, or, for a file's bed whose material
// column names its spheres' materials, a copy in `named` with those of the scenario's materials
// (InputError for a name the scenario lacks).
const ParticleStore* starting_bed_of(const PyBed& bed, const Scenario& sc, std::optional<ParticleStore>& named);

}  // namespace aggpack::python
