// A bed seen from Python: the spheres (and grains) of a ParticleStore that something else
// owns (a run's report) or that the bed owns (one made from arrays). Its arrays are numpy
// views into the store, read-only, each keeping the Bed, and so the store, alive.
#pragma once
#include <memory>
#include <string>

#include "aggpack/core/particle_store.hpp"

namespace aggpack::python {

struct PyBed {
  std::shared_ptr<const ParticleStore> store;  // may alias its owner's (a report's) lifetime
  std::string source;  // what it is, in messages: a file's path, "the run's bed", "the bed from arrays"
  std::string format;  // a file's ("CSV", "LAMMPS dump, timestep 1000 (the last of 3)", ...); empty otherwise
};

}  // namespace aggpack::python
