#pragma once
#include <string>
#include <vector>

#include "aggpack/io/material_file.hpp"
#include "aggpack/sizes/grading.hpp"

namespace aggpack {

// What the standards of an aggregate's bulk density and voids fix, in SI: the measures, which
// procedure a size allows and the gradings of the fine-aggregate test. Sources: ASTM C29/C29M-17a
// "Bulk Density ("Unit Weight") and Voids in Aggregate" (AASHTO T 19) and ASTM C1252-17
// "Uncompacted Void Content of Fine Aggregate" (AASHTO T 304); docs/validation.md,
// "The lab's tests", quotes what is used.

// A cylindrical measure: what a lab weighs. C29's Table 1 gives the capacity for the nominal
// maximum size; its 6.1 asks a height "approximately equal to the diameter", never below 80 %
// nor above 150 % of it: aggpack's measures have height = diameter at the nominal capacity.
struct Measure {
  std::string name;          // "1/3 ft3 (9.3 L)"
  double capacity_m3 = 0.0;  // nominal
  double largest_size_m = 0.0;  // the nominal maximum size it serves, at most
  double diameter_m = 0.0, height_m = 0.0;
  [[nodiscard]] double volume_m3() const;  // pi D^2 H / 4 of the modelled measure
};

// C29 Table 1: the smallest measure for a nominal maximum size; InputError naming `source` above
// 125 mm (the standard ends there).
[[nodiscard]] Measure c29_measure(double nominal_maximum_size_m, const std::string& source);
[[nodiscard]] const std::vector<Measure>& c29_measures();

// C29's procedures by size (its sections 1.3, 9, 10, 11): rodding up to 37.5 mm, jigging above
// 37.5 mm up to 125 mm, shovelling (the loose bulk density) up to 125 mm. InputError naming
// `source` when the method is not the standard's for that size.
void check_c29_method(C29Method method, double nominal_maximum_size_m, const std::string& source);

// The C29 tamping rod: 16 mm round, hemispherical tip (6.3); 25 strokes a layer, three layers.
inline constexpr double kC29RodDiameter = 0.016;
inline constexpr int kC29StrokesPerLayer = 25;
inline constexpr int kC29Layers = 3;
// Jigging: each layer dropped 50 times from about 50 mm (25 on each side).
inline constexpr int kC29DropsPerLayer = 50;
inline constexpr double kC29DropHeight = 0.050;
// Shovelling: discharged from at most 50 mm above the top of the measure.
inline constexpr double kC29ShovelHeight = 0.050;

// C1252's measure: a copper tube of about 100 mL, 39 mm inside diameter, 86 mm high (its 5.2);
// the funnel's opening 12.7 mm held 115 mm above the top of the measure (5.3, 5.4).
inline constexpr double kC1252Diameter = 0.039;
inline constexpr double kC1252Height = 0.086;
inline constexpr double kC1252FunnelOpening = 0.0127;
inline constexpr double kC1252FunnelHeight = 0.115;
inline constexpr double kC1252SampleMassKg = 0.190;
// Method C's sample: the sand as received, passing 4.75 mm.
inline constexpr double kC1252MethodCLargest = 4.75e-3;
// The finest sieve of method A's sample (0.150 mm): aggpack's default cut-off for method C.
inline constexpr double kC1252FinestDefault = 0.150e-3;

// A size fraction of a C1252 sample: between two sieves, its mass in the sample.
struct SieveFraction {
  double lower_m = 0.0, upper_m = 0.0;
  double mass_kg = 0.0;
};
// Method A's standard graded sample (its 9.1): 44 g of 2.36-1.18 mm, 57 g of 1.18-0.600, 72 g
// of 0.600-0.300 and 17 g of 0.300-0.150: 190 g.
[[nodiscard]] const std::vector<SieveFraction>& c1252_method_a_fractions();
// Method B's three individual fractions, 190 g each (its 9.2): 2.36-1.18, 1.18-0.600, 0.600-0.300.
[[nodiscard]] const std::vector<SieveFraction>& c1252_method_b_fractions();

// C1252 takes a fine aggregate (at least 85 % of it passing 4.75 mm: a coarse aggregate is
// not C1252's); methods A and B need each of their fractions in the sand (at least 1 % of its
// mass between the fraction's sieves); method C takes it as received below 4.75 mm.
// InputError naming `source` otherwise.
void check_c1252_grading(C1252Method method, const Grading& grading, const std::string& source);

// The grading of a sample: by mass, fractions (uniform in log size within each) as sieves.
[[nodiscard]] Grading grading_of_fractions(const std::vector<SieveFraction>& fractions, const std::string& name);

}  // namespace aggpack
