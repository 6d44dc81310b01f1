#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "aggpack/io/scenario.hpp"

namespace aggpack {

// Particle diameters in drop order, with the report of what was generated (summary.json
// "sizes") and the modelling notes it implies.
struct GeneratedSizes {
  std::vector<double> diameters;  // m
  nlohmann::json report;
  std::vector<std::string> notes;
};

// From size classes or from gradings (one, or a coarse/fine mix), with the run's seed.
GeneratedSizes generate_sizes(const ParticleSource& source, std::uint64_t seed);

}  // namespace aggpack
