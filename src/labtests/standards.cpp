// The standards' numbers (ASTM C29/C29M-17a, ASTM C1252-17), and the checks of what each allows.
#include "aggpack/labtests/standards.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "aggpack/core/error.hpp"

namespace aggpack {

namespace {

constexpr double kMm = 1e-3;

Measure measure_of_capacity(std::string name, double capacity_m3, double largest_size_m) {
  const double diameter = std::cbrt(4.0 * capacity_m3 / std::numbers::pi);  // height = diameter
  return {std::move(name), capacity_m3, largest_size_m, diameter, diameter};
}

// Percent of the mass between two openings.
double percent_between(const Grading& g, double lower, double upper) {
  return percent_passing_at(g, upper) - percent_passing_at(g, lower);
}

}  // namespace

double Measure::volume_m3() const { return 0.25 * std::numbers::pi * diameter_m * diameter_m * height_m; }

const std::vector<Measure>& c29_measures() {
  // C29 Table 1: "The indicated size of measure shall be used to test aggregates of a nominal
  // maximum size equal to or smaller than that listed."
  static const std::vector<Measure> measures{
      measure_of_capacity("1/10 ft3 (2.8 L)", 2.8e-3, 12.5 * kMm),
      measure_of_capacity("1/3 ft3 (9.3 L)", 9.3e-3, 25.0 * kMm),
      measure_of_capacity("1/2 ft3 (14 L)", 14e-3, 37.5 * kMm),
      measure_of_capacity("1 ft3 (28 L)", 28e-3, 75.0 * kMm),
      measure_of_capacity("2 1/2 ft3 (70 L)", 70e-3, 100.0 * kMm),
      measure_of_capacity("3 1/2 ft3 (100 L)", 100e-3, 125.0 * kMm),
  };
  return measures;
}

Measure c29_measure(double nominal_maximum_size_m, const std::string& source) {
  for (const Measure& m : c29_measures())
    if (nominal_maximum_size_m <= m.largest_size_m * (1.0 + 1e-9)) return m;
  throw InputError(fmt::format("{}: a nominal maximum size of {:.1f} mm is above the 125 mm of ASTM C29's largest "
                               "measure (Table 1); the standard does not test it",
                               source, nominal_maximum_size_m / kMm));
}

void check_c29_method(C29Method method, double nominal_maximum_size_m, const std::string& source) {
  const double nms_mm = nominal_maximum_size_m / kMm;
  const auto refuse = [&](const char* why) {
    throw InputError(fmt::format("{}: ASTM C29 {} {} (this aggregate's nominal maximum size is {:.1f} mm)", source,
                                 name_of(kC29MethodNames, method), why, nms_mm));
  };
  constexpr double kRoddingLimit = 37.5 * (1.0 + 1e-9), kLargest = 125.0 * (1.0 + 1e-9);
  if (nms_mm > kLargest) refuse("is defined up to a nominal maximum size of 125 mm");
  if (method == C29Method::Rodding && nms_mm > kRoddingLimit)
    refuse("is defined up to a nominal maximum size of 37.5 mm; above it the standard jigs (--method jigging)");
  if (method == C29Method::Jigging && nms_mm <= kRoddingLimit)
    refuse("is defined above a nominal maximum size of 37.5 mm; below it the standard rods (--method rodding)");
}

const std::vector<SieveFraction>& c1252_method_a_fractions() {
  static const std::vector<SieveFraction> fractions{{1.18 * kMm, 2.36 * kMm, 0.044},
                                                    {0.600 * kMm, 1.18 * kMm, 0.057},
                                                    {0.300 * kMm, 0.600 * kMm, 0.072},
                                                    {0.150 * kMm, 0.300 * kMm, 0.017}};
  return fractions;
}

const std::vector<SieveFraction>& c1252_method_b_fractions() {
  static const std::vector<SieveFraction> fractions{{1.18 * kMm, 2.36 * kMm, kC1252SampleMassKg},
                                                    {0.600 * kMm, 1.18 * kMm, kC1252SampleMassKg},
                                                    {0.300 * kMm, 0.600 * kMm, kC1252SampleMassKg}};
  return fractions;
}

void check_c1252_grading(C1252Method method, const Grading& grading, const std::string& source) {
  const double passing = percent_passing_at(grading, 4.75 * kMm);
  if (passing < 85.0)
    throw InputError(fmt::format("{}: {:.0f} % passes 4.75 mm: ASTM C1252 tests a fine aggregate (at least 85 % "
                                 "passing 4.75 mm expected; a coarse aggregate's test is C29)",
                                 source, passing));
  if (method == C1252Method::C) return;
  const auto& fractions = method == C1252Method::A ? c1252_method_a_fractions() : c1252_method_b_fractions();
  for (const SieveFraction& f : fractions) {
    const double percent = percent_between(grading, f.lower_m, f.upper_m);
    if (percent < 1.0)
      throw InputError(fmt::format("{}: ASTM C1252 method {} needs the {:.3g}-{:.3g} mm fraction, and this grading "
                                   "has {:.2g} % of its mass there (at least 1 % expected): test it by method C "
                                   "(as received)",
                                   source, name_of(kC1252MethodNames, method), f.upper_m / kMm, f.lower_m / kMm,
                                   percent));
  }
}

Grading grading_of_fractions(const std::vector<SieveFraction>& fractions, const std::string& name) {
  double total = 0.0;
  for (const SieveFraction& f : fractions) total += f.mass_kg;
  std::vector<SieveFraction> sorted = fractions;
  std::sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) { return a.lower_m < b.lower_m; });
  std::vector<Sieve> sieves{{"", sorted.front().lower_m, 0.0}};
  double passing = 0.0;
  for (const SieveFraction& f : sorted) {
    passing += 100.0 * f.mass_kg / total;
    sieves.push_back({"", f.upper_m, std::min(100.0, passing)});
  }
  sieves.back().percent_passing = 100.0;
  std::vector<std::string> rows;
  for (std::size_t i = 0; i < sieves.size(); ++i) rows.push_back(fmt::format("sieve {}", i + 1));
  return make_grading(name, std::move(sieves), name, rows);
}

}  // namespace aggpack
