#pragma once
// The grains of one grading component: a library of templates drawn from the component's
// shape (given, or fitted to a lab's measure), each grain of the component one of them, scaled
// so that its intermediate dimension I is the size the grading gave it.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "aggpack/core/particle_store.hpp"
#include "aggpack/core/stop_request.hpp"
#include "aggpack/grains/grain_shape.hpp"
#include "aggpack/grains/shape_measures.hpp"

namespace aggpack {

enum class GrainFamily { Rounded, Angular };
[[nodiscard]] std::string_view family_name(GrainFamily family);

// What a scenario says of a component's grains.
struct GrainShapeSpec {
  GrainFamily family = GrainFamily::Rounded;
  std::size_t spheres = 8;              // member spheres per grain
  std::size_t corners = 12;             // of an angular grain's hull
  ProportionDistribution proportions;   // I/L and S/I: means and spreads
  std::optional<ShapeTarget> target;    // a lab's measure the proportions are fitted to
  std::size_t templates = 12;           // distinct grains drawn from the proportions
};

// One template, ready for the store: reach 1 (RigidBodyShape's convention for a pour), and
// what it measures at that scale.
struct LibraryGrain {
  GrainTemplate grain;             // body frame, L = 1 (as rounded_grain / angular_grain make it)
  std::vector<Vec3> unit_centres;  // the members at reach 1
  std::vector<double> unit_radii;
  double unit_volume = 0.0;
  Vec3 unit_moments;               // principal, per unit density
  double reach = 0.0;              // the template's reach at L = 1
  // Its shape at reach 1, viewing this grain's arrays.
  [[nodiscard]] RigidBodyShape shape() const { return {unit_centres, unit_radii, unit_volume, unit_moments}; }
  // The reach of this grain when its intermediate dimension is `width` (the sieve size it passes).
  [[nodiscard]] double reach_for_width(double width) const { return width / grain.dimensions.width * reach; }
};

struct GrainLibrary {
  GrainShapeSpec spec;
  ProportionDistribution distribution;  // the proportions used: the spec's, or fitted
  std::optional<ProportionFit> fit;     // when the spec has a target: over the templates
  std::vector<LibraryGrain> grains;
};

// The library of `spec` for a component whose grains have these intermediate dimensions (m,
// the sizes the grading gave; the fit needs them), seeded. With a target, the proportions are
// fitted first on ideal grains (fit_proportions_to), then on the templates as their fill came
// out, every template at every size by mass (within 0.5 percentage points if it can, 1 at
// most). Throws InputError when a target's measure applies to none of the sizes or cannot be
// reached within 1 percentage point.
// `watch`: told after each template drawn (the fit draws the library several times: `drawn`
// counts them all, `expected` is the most it may draw), and a stop requested is honoured there
// (Interrupted).
struct LibraryWatch {
  const StopRequest* stop = nullptr;
  std::function<void(std::size_t drawn, std::size_t expected)> progress;
};
[[nodiscard]] GrainLibrary make_grain_library(const GrainShapeSpec& spec, std::span<const double> intermediate_sizes,
                                              std::uint64_t seed, const LibraryWatch& watch = {});

// The most templates make_grain_library draws for `spec` (with a target, the fit draws the
// library up to 19 times), and an estimate of the seconds that takes on one core of a
// machine like the one it was measured on (BENCHMARKS.md), for the checks before a run.
[[nodiscard]] std::size_t most_templates_drawn(const GrainShapeSpec& spec);
[[nodiscard]] double estimated_library_seconds(const GrainShapeSpec& spec);
// InputError, before any template is made, when the libraries of `specs` would take more than
// `max_minutes` by estimated_library_seconds; `where` names what the user gave (a scenario's
// key, --shape) and `limit_key` how to raise the limit.
void check_library_cost(std::span<const GrainShapeSpec* const> specs, double max_minutes, std::string_view where,
                        std::string_view limit_key);

// The intermediate sizes a library is fitted on, from all the sizes of its component: at most
// 256 evenly spaced quantiles (the fit's cost then does not grow with the bed).
[[nodiscard]] std::vector<double> library_fit_sizes(std::vector<double> sizes);

// Every template of the library at every one of these intermediate sizes, as a lab measures
// them (mass per unit density): a component whose grains pick templates at random, by mass.
[[nodiscard]] std::vector<GrainMeasure> measure_library(const GrainLibrary& library,
                                                        std::span<const double> intermediate_sizes);

// The dimensions and mass of body b of the store, as a lab measures them: L, I and S the
// extents of its members along its body frame's axes (its principal axes, longest first for
// the templates of a library).
[[nodiscard]] GrainMeasure measure_body(const ParticleStore& particles, std::size_t b);

// The dimensions and mass of grain `k` of the library scaled to `width`, as a lab measures them.
[[nodiscard]] GrainMeasure measure_grain(const LibraryGrain& grain, double width, double density);

}  // namespace aggpack
