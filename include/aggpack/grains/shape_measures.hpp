#pragma once
// What a concrete lab measures about the shape of its coarse aggregate, and the proportions
// of generated grains that reproduce it: a flakiness index (EN 933-3), a shape index
// (EN 933-4) or the flat-and-elongated percentage of ASTM D4791, each by mass.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <utility>
#include <vector>

#include "aggpack/core/rng.hpp"

namespace aggpack {

// A grain's proportions: elongation I/L and flatness S/I, L >= I >= S (ASTM D4791's length,
// width and thickness).
struct Proportions {
  double elongation = 1.0, flatness = 1.0;
};

// How the proportions of a component's grains are spread: each ratio independently
// triangular, `mean` ± `spread` (its peak at the mean; standard deviation spread / √6), each
// draw clamped to [kLeastRatio, 1] (a ratio of 1: a round section). Drawn from our own
// uniform numbers, so a seed gives the same grains with every standard library.
struct ProportionDistribution {
  static constexpr double kLeastRatio = 0.1;
  double elongation_mean = 1.0, elongation_spread = 0.0;
  double flatness_mean = 1.0, flatness_spread = 0.0;
  [[nodiscard]] Proportions draw(Rng& rng) const;
  // Throws InputError naming the field when a mean is outside [kLeastRatio, 1] or a spread
  // outside [0, 0.5].
  void check() const;
};

// The lab's measures of shape, each the percentage by mass of the grains that count.
enum class ShapeMeasure {
  // EN 933-3: grains whose thickness S passes the bar sieve of their size class d/D, a gap of
  // D/2 (classes 4/5 to 63/80 mm, D = 1.25 d; the class by the intermediate dimension I).
  FlakinessIndex,
  // EN 933-4: grains 4 to 63 mm whose L/S exceeds 3 (non-cubical).
  ShapeIndex,
  // ASTM D4791: grains retained on the 4.75 mm sieve whose L/S exceeds `ratio` (2, 3 or 5).
  FlatAndElongated,
};
[[nodiscard]] std::string_view measure_name(ShapeMeasure measure);

struct ShapeTarget {
  ShapeMeasure measure = ShapeMeasure::FlakinessIndex;
  double percent = 0.0;  // by mass of the grains the measure applies to
  double ratio = 3.0;    // L/S, FlatAndElongated only
};

// A grain's dimensions, m, and its mass (any unit: the measures are fractions of mass).
struct GrainMeasure {
  double length = 0.0, width = 0.0, thickness = 0.0, mass = 0.0;
};

// Whether the measure applies to a grain of this size (its class within the standard's
// range), and whether the grain counts.
[[nodiscard]] bool measured(ShapeMeasure measure, const GrainMeasure& grain);
[[nodiscard]] bool counts(const ShapeTarget& target, const GrainMeasure& grain);

// The measure's percentage by mass over the grains it applies to; nothing when it applies to
// none (a sand, for a flakiness index).
[[nodiscard]] std::optional<double> measured_percent(const ShapeTarget& target, std::span<const GrainMeasure> grains);

// What a set of grains measures, as a lab would report it: the mean proportions (by number)
// and each standard's percentage by mass (none where it applies to no grain).
struct ShapeStatistics {
  std::size_t grains = 0;
  double mean_elongation = 0.0, mean_flatness = 0.0;  // I/L and S/I
  std::optional<double> flakiness_index, shape_index;  // EN 933-3, EN 933-4
  std::optional<double> flat_elongated_2, flat_elongated_3, flat_elongated_5;  // ASTM D4791 at 2:1, 3:1, 5:1
};
[[nodiscard]] ShapeStatistics shape_statistics(std::span<const GrainMeasure> grains);

// The distribution whose grains reproduce `target` on grains of these intermediate
// dimensions I (m, as the grading gives them: a grain belongs to the sieve interval that I
// passes), by mass as L I S (the grains' volume up to a factor of shape that the fill
// makes nearly the same for all). What is fitted: for a flakiness index the flatness mean;
// for an L/S measure both means, shifted together. The spreads stay `start`'s. The fit is
// a bisection on `samples` grains per size drawn from one seeded stream (the same numbers
// for every candidate, so the percentage moves only with the fitted mean).
struct ProportionFit {
  ProportionDistribution distribution;
  double parameter = 0.0;         // what was fitted (fitted_distribution's t)
  double achieved_percent = 0.0;  // with the fitted distribution, on those grains
  bool reached = false;           // within 0.5 percentage points of the target
};
// The candidate of fit parameter t: for a flakiness index the flatness mean t, for an L/S
// measure both of start's means shifted by t (each kept within [kLeastRatio, 1]).
[[nodiscard]] ProportionDistribution fitted_distribution(ShapeMeasure measure, const ProportionDistribution& start,
                                                         double t);
// The range of t a fit searches, the percentage falling as t grows.
[[nodiscard]] std::pair<double, double> fit_parameter_range(ShapeMeasure measure);

[[nodiscard]] ProportionFit fit_proportions_to(const ShapeTarget& target, const ProportionDistribution& start,
                                               std::span<const double> intermediate_sizes, std::uint64_t seed,
                                               std::size_t samples = 200);

}  // namespace aggpack
