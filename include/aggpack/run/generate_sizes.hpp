#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "aggpack/io/scenario.hpp"
#include "aggpack/sizes/grading_sampler.hpp"

namespace aggpack {

// What one grading of a run generated, against its target.
struct SizesComponent {
  std::string key, grading;          // the scenario key (particles.fine, ...) and the grading's name
  GradingCut cut;                    // the target after the cut-offs
  GradingReport generated;           // the generated particles at every sieve of the target
  std::optional<Band> band;          // asked for with the grading's `band`
};

// What was generated (summary.json "sizes"): by classes, or from one grading or a mix.
struct SizesReport {
  std::string method;                // "classes", "grading" or "mix"
  std::size_t count = 0;
  std::optional<SamplingMode> sampling;  // gradings only, as are the fields below
  GradingReport whole;                   // the whole sample as one curve (count, volume, D10/D50/D90, ...)
  std::vector<SizesComponent> components;
  std::optional<MixOrder> order;         // a mix only, as are the two ratios
  double ca_fa_requested = 0.0, ca_fa_generated = 0.0;
};
nlohmann::json to_json(const SizesReport& report);

// Particle diameters in drop order, with the report of what was generated and the
// modelling notes it implies.
struct GeneratedSizes {
  std::vector<double> diameters;  // m
  // Where each diameter came from, by index: a mix's grading (0 coarse, 1 fine: the order of
  // report.components), a class of particles.classes (as listed); 0 for one grading.
  std::vector<std::int32_t> component;
  SizesReport report;
  std::vector<std::string> notes;
};

// How many particles the source will generate (exact for counts; the expectation for a solid
// volume), without drawing them: for the checks before a run.
[[nodiscard]] double expected_particle_count(const ParticleSource& source);

// The particles the source will generate, and the spheres they are made of: a grain is its
// member spheres (its component's shape.spheres), each of which the DEM holds as a particle.
// Where the split between components is not known before drawing (a total count), every
// particle counts as many spheres as the component with most.
struct ExpectedAmount {
  double particles = 0.0;
  double spheres = 0.0;  // the particles' spheres, grains' members counted
  double grains = 0.0;   // the particles that are grains
};
[[nodiscard]] ExpectedAmount expected_amount(const ParticleSource& source);
// The same for sizes already drawn: exact.
[[nodiscard]] ExpectedAmount drawn_amount(const ParticleSource& source, const GeneratedSizes& sizes);

// From size classes or from gradings (one, or a coarse/fine mix), with the run's seed.
GeneratedSizes generate_sizes(const ParticleSource& source, std::uint64_t seed);

// The material of each generated sphere (its component's); empty when every component is of
// material 0 ([material]).
std::vector<std::uint8_t> sphere_materials(const ParticleSource& source, const GeneratedSizes& sizes);

}  // namespace aggpack
