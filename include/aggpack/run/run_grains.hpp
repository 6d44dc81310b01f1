#pragma once
// A run's grains (issue 38): each component that has a `shape` gets its library of templates,
// and each of its particles one of them, scaled so that its intermediate dimension is the size
// the grading gave it.
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <nlohmann/json.hpp>

#include "aggpack/core/particle_store.hpp"
#include "aggpack/dynamics/pour.hpp"
#include "aggpack/grains/grain_library.hpp"
#include "aggpack/io/particle_file.hpp"
#include "aggpack/io/scenario.hpp"
#include "aggpack/run/generate_sizes.hpp"
#include "aggpack/run/progress.hpp"

namespace aggpack {

struct RunGrains {
  RunGrains() = default;
  // Not copied: `shapes` and `shape_grain` point into this object's own libraries.
  RunGrains(const RunGrains&) = delete;
  RunGrains& operator=(const RunGrains&) = delete;
  RunGrains(RunGrains&&) = default;
  RunGrains& operator=(RunGrains&&) = default;
  std::vector<std::optional<GrainLibrary>> libraries;  // per component; none: spheres
  // The templates of every library, in order (views into `libraries`, which must not change).
  std::vector<RigidBodyShape> shapes;
  std::vector<const LibraryGrain*> shape_grain;  // per entry of `shapes`
  std::vector<std::uint32_t> shape_component;    // per entry of `shapes`: its component
  std::vector<std::int32_t> shape_of;  // per particle of the drop sequence: an index into shapes, -1: a sphere
  [[nodiscard]] bool empty() const { return shape_of.empty(); }
  // The radii a pour of particles [begin, end) of the drop sequence takes (a grain's reach at
  // its size, a sphere's radius), and their shapes.
  struct PourPart {
    std::vector<double> radii;
    std::vector<const RigidBodyShape*> shapes;
  };
  [[nodiscard]] PourPart pour_part(std::span<const double> sieve_radii, std::size_t begin) const;
  // The spheres that the particles [begin, begin + size) of the drop sequence place, appended
  // to `radii`, and to `grain_of` what each belongs to: a grain its spheres (the particle's
  // index), a sphere itself (kNoBody).
  void append_spheres(std::span<const double> sieve_radii, std::size_t begin, std::vector<double>& radii,
                      std::vector<std::uint32_t>& grain_of) const;
};

// A library's shape as summary.json and `aggpack grading --shape --json` give it: family,
// spheres, templates, filling, elongation, flatness, corners (angular), and with a lab measure
// target, templates_percent (the measure over the templates at the fit's sizes) and fitted.
nlohmann::json library_json(const GrainLibrary& library);
// summary.json's "grains" before the run: each component's shape, its fitted proportions and
// what its templates measure (every template at every size of the component, by mass).
nlohmann::json libraries_json(const RunGrains& grains, const std::vector<SizesComponent>& components);
// What a set of grains measures ({ grains, mean_elongation, mean_flatness,
// flakiness_index_percent, shape_index_percent, flat_elongated_{2,3,5}_to_1_percent, by }; null
// where a standard measures none of them): the bed's grains in summary.json, the templates in
// `aggpack grading --shape`.
nlohmann::json shape_statistics_json(const ShapeStatistics& statistics);
// ... and after: what the grains of the bed measure, by component (shape_component: a body's
// template's component), by mass as a lab would, beside the libraries' targets.
nlohmann::json bed_grains_json(const nlohmann::json& libraries, const ParticleStore& bed,
                               const std::vector<std::uint32_t>& shape_component);
// One GrainMeasure per body of the bed (grains.csv's dimensions).
std::vector<GrainMeasure> measure_bodies(const ParticleStore& bed);
// Per body, the sieves of its component's grading between which its intermediate dimension
// (`measures`' width, the size the grading gave it) lies; none for a component of size classes.
std::vector<SieveInterval> grain_sieve_intervals(const ParticleStore& bed, std::span<const GrainMeasure> measures,
                                                 const std::vector<std::uint32_t>& shape_component,
                                                 const SizesReport& sizes);

// The run's grains from its components' shapes, the generated sizes (diameters: each grain's
// intermediate dimension) and the seed; empty when no component has a shape. Throws InputError
// from a library (a measure that applies to none of a component's sizes or cannot be reached).
// The watch that counts the templates on `progress`'s line as they are made (it starts the
// stage "grain templates"; clear the line after) and stops at `stop`'s request.
LibraryWatch templates_shown_on(Progress& progress, const StopRequest* stop);

// `watch`: told of each template drawn, over all the components (see make_grain_library).
RunGrains make_run_grains(const ParticleSource& source, const GeneratedSizes& sizes, std::uint64_t seed,
                          const LibraryWatch& watch = {});

}  // namespace aggpack
