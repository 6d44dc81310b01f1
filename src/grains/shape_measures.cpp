#include "aggpack/grains/shape_measures.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"

namespace aggpack {
namespace {

// EN 933-3's size classes d/D (mm) and their bar sieves' gaps, D/2 (Table 1 of the standard).
struct FlakinessClass {
  double d, upper, gap;  // mm
};
constexpr std::array<FlakinessClass, 13> kFlakinessClasses{{{4, 5, 2.5},
                                                             {5, 6.3, 3.15},
                                                             {6.3, 8, 4},
                                                             {8, 10, 5},
                                                             {10, 12.5, 6.3},
                                                             {12.5, 16, 8},
                                                             {16, 20, 10},
                                                             {20, 25, 12.5},
                                                             {25, 31.5, 16},
                                                             {31.5, 40, 20},
                                                             {40, 50, 25},
                                                             {50, 63, 31.5},
                                                             {63, 80, 40}}};

// The class whose square sieves the grain's intermediate dimension falls between, if any.
const FlakinessClass* flakiness_class(double width) {
  const double mm = 1e3 * width;
  for (const FlakinessClass& c : kFlakinessClasses)
    if (mm >= c.d && mm < c.upper) return &c;
  return nullptr;
}

// A triangular draw of mean ± spread from two uniform numbers, clamped to the ratios' range.
double triangular(double mean, double spread, double u1, double u2) {
  return std::clamp(mean + spread * (u1 + u2 - 1.0), ProportionDistribution::kLeastRatio, 1.0);
}

}  // namespace

Proportions ProportionDistribution::draw(Rng& rng) const {
  const double u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform(), u4 = rng.uniform();
  return {triangular(elongation_mean, elongation_spread, u1, u2), triangular(flatness_mean, flatness_spread, u3, u4)};
}

void ProportionDistribution::check() const {
  const auto check_mean = [](std::string_view name, double mean) {
    if (!(mean >= kLeastRatio && mean <= 1.0))
      throw InputError(fmt::format("{} {} is not a ratio in [{}, 1]", name, mean, kLeastRatio));
  };
  const auto check_spread = [](std::string_view name, double spread) {
    if (!(spread >= 0.0 && spread <= 0.5)) throw InputError(fmt::format("{} {} is outside [0, 0.5]", name, spread));
  };
  check_mean("elongation I/L", elongation_mean);
  check_mean("flatness S/I", flatness_mean);
  check_spread("the spread of elongation", elongation_spread);
  check_spread("the spread of flatness", flatness_spread);
}

std::string_view measure_name(ShapeMeasure measure) {
  switch (measure) {
    case ShapeMeasure::FlakinessIndex: return "flakiness index (EN 933-3)";
    case ShapeMeasure::ShapeIndex: return "shape index (EN 933-4)";
    case ShapeMeasure::FlatAndElongated: return "flat and elongated (ASTM D4791)";
  }
  return "?";
}

bool measured(ShapeMeasure measure, const GrainMeasure& grain) {
  switch (measure) {
    case ShapeMeasure::FlakinessIndex: return flakiness_class(grain.width) != nullptr;
    case ShapeMeasure::ShapeIndex: return grain.width >= 4e-3 && grain.width < 63e-3;
    case ShapeMeasure::FlatAndElongated: return grain.width >= 4.75e-3;
  }
  return false;
}

bool counts(const ShapeTarget& target, const GrainMeasure& grain) {
  switch (target.measure) {
    case ShapeMeasure::FlakinessIndex: {
      const FlakinessClass* c = flakiness_class(grain.width);
      return c != nullptr && 1e3 * grain.thickness < c->gap;
    }
    case ShapeMeasure::ShapeIndex: return grain.length > 3.0 * grain.thickness;
    case ShapeMeasure::FlatAndElongated: return grain.length > target.ratio * grain.thickness;
  }
  return false;
}

std::optional<double> measured_percent(const ShapeTarget& target, std::span<const GrainMeasure> grains) {
  double all = 0.0, counted = 0.0;
  for (const GrainMeasure& g : grains) {
    if (!measured(target.measure, g)) continue;
    all += g.mass;
    if (counts(target, g)) counted += g.mass;
  }
  if (!(all > 0.0)) return std::nullopt;
  return 100.0 * counted / all;
}

ShapeStatistics shape_statistics(std::span<const GrainMeasure> grains) {
  ShapeStatistics s;
  s.grains = grains.size();
  for (const GrainMeasure& g : grains) {
    s.mean_elongation += g.width / g.length;
    s.mean_flatness += g.thickness / g.width;
  }
  if (!grains.empty()) {
    s.mean_elongation /= static_cast<double>(grains.size());
    s.mean_flatness /= static_cast<double>(grains.size());
  }
  s.flakiness_index = measured_percent({ShapeMeasure::FlakinessIndex, 0.0, 0.0}, grains);
  s.shape_index = measured_percent({ShapeMeasure::ShapeIndex, 0.0, 0.0}, grains);
  s.flat_elongated_2 = measured_percent({ShapeMeasure::FlatAndElongated, 0.0, 2.0}, grains);
  s.flat_elongated_3 = measured_percent({ShapeMeasure::FlatAndElongated, 0.0, 3.0}, grains);
  s.flat_elongated_5 = measured_percent({ShapeMeasure::FlatAndElongated, 0.0, 5.0}, grains);
  return s;
}

ProportionDistribution fitted_distribution(ShapeMeasure measure, const ProportionDistribution& start, double t) {
  ProportionDistribution d = start;
  const auto ratio = [](double v) { return std::clamp(v, ProportionDistribution::kLeastRatio, 1.0); };
  if (measure == ShapeMeasure::FlakinessIndex) {
    d.flatness_mean = ratio(t);
  } else {
    d.elongation_mean = ratio(start.elongation_mean + t);
    d.flatness_mean = ratio(start.flatness_mean + t);
  }
  return d;
}

std::pair<double, double> fit_parameter_range(ShapeMeasure measure) {
  return measure == ShapeMeasure::FlakinessIndex ? std::pair{ProportionDistribution::kLeastRatio, 1.0}
                                                 : std::pair{-1.0, 1.0};
}

ProportionFit fit_proportions_to(const ShapeTarget& target, const ProportionDistribution& start,
                                 std::span<const double> intermediate_sizes, std::uint64_t seed, std::size_t samples) {
  start.check();
  if (!(target.percent >= 0.0 && target.percent <= 100.0))
    throw InputError(fmt::format("a {} of {} % is not a percentage", measure_name(target.measure), target.percent));
  if (target.measure == ShapeMeasure::FlatAndElongated && !(target.ratio > 1.0 && target.ratio <= 10.0))
    throw InputError(fmt::format("a flat-and-elongated ratio of {} is outside (1, 10]", target.ratio));
  // The same uniform numbers for every candidate: four per grain (two per ratio, as draw()).
  Rng rng = make_rng(seed, RngPurpose::Shapes);
  std::vector<double> size_of, uniforms;
  for (const double width : intermediate_sizes)
    for (std::size_t k = 0; k < samples; ++k) {
      size_of.push_back(width);
      for (int u = 0; u < 4; ++u) uniforms.push_back(rng.uniform());
    }
  const bool flakiness = target.measure == ShapeMeasure::FlakinessIndex;
  const auto candidate = [&](double t) { return fitted_distribution(target.measure, start, t); };
  std::vector<GrainMeasure> grains(size_of.size());
  const auto percent_of = [&](const ProportionDistribution& d) {
    for (std::size_t k = 0; k < grains.size(); ++k) {
      const double* u = &uniforms[4 * k];
      const double e = triangular(d.elongation_mean, d.elongation_spread, u[0], u[1]);
      const double f = triangular(d.flatness_mean, d.flatness_spread, u[2], u[3]);
      const double width = size_of[k], length = width / e, thickness = width * f;
      grains[k] = {length, width, thickness, length * width * thickness};
    }
    return measured_percent(target, grains);
  };
  const std::optional<double> probe = percent_of(start);
  if (!probe)
    throw InputError(fmt::format("a {} applies to no grain of these sizes ({})", measure_name(target.measure),
                                 flakiness ? "classes 4/5 to 63/80 mm" : "4 mm and up"));
  // The percentage falls as t grows (flatter and longer grains count): bisect on t.
  auto [lo, hi] = fit_parameter_range(target.measure);
  for (int step = 0; step < 60; ++step) {
    const double mid = 0.5 * (lo + hi);
    if (*percent_of(candidate(mid)) > target.percent) lo = mid;
    else hi = mid;
  }
  // Of the two ends of the last bracket, the closer.
  const double at_lo = *percent_of(candidate(lo)), at_hi = *percent_of(candidate(hi));
  const bool take_lo = std::abs(at_lo - target.percent) <= std::abs(at_hi - target.percent);
  ProportionFit fit{candidate(take_lo ? lo : hi), take_lo ? lo : hi, take_lo ? at_lo : at_hi, false};
  fit.reached = std::abs(fit.achieved_percent - target.percent) <= 0.5;
  return fit;
}

}  // namespace aggpack
