#pragma once
#include <array>

#include "aggpack/core/enum_names.hpp"
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace aggpack {

// One sieve of a sieve analysis (ASTM C136): percent of the mass passing the opening.
struct Sieve {
  std::string name;        // "#4", "3/8in", or empty
  double opening = 0.0;    // m
  double percent_passing = 0.0;
};

// A sieve opening that was moved to the standard series when the grading was read.
struct SnappedSieve {
  std::string name;
  double given = 0.0, standard = 0.0;  // m
};

// A grading curve: sieves in ascending opening, percent passing non-decreasing, 100 at the
// largest. Between sieves the percent passing is linear in log opening (as sieve curves are
// plotted); mass sampling follows the same law (percent_passing_at).
struct Grading {
  std::string name;
  std::vector<Sieve> sieves;
  std::vector<SnappedSieve> snapped;  // openings make_grading moved to the ASTM series
  [[nodiscard]] double smallest() const { return sieves.front().opening; }
  [[nodiscard]] double largest() const { return sieves.back().opening; }
};

// Sorts the sieves by opening and validates them; `source` names where they came from
// (a file or a scenario key) and `row_names[i]` names sieve i as given (a file row or a list
// index), so that errors say which row is wrong. Throws InputError.
// An opening within kSieveSnapTolerance of a standard one (astm_sieve_series) is taken as that
// sieve and recorded in `snapped`: tables converted from inches (1.245 mm for the 1.18 mm #16)
// then meet metric ones at the same sieve. Two openings that would meet at one are left alone.
// A sieve named by a designation ("#200", "No. 4", "3/8in") or a length ("4.75 mm") whose
// opening is further than kSieveSnapTolerance from it is refused (a slip of unit, mostly).
inline constexpr double kSieveSnapTolerance = 0.06;
Grading make_grading(std::string name, std::vector<Sieve> sieves, const std::string& source,
                     const std::vector<std::string>& row_names);

// A CSV grading: a header with an opening column, a percent column (`percent_column`, default
// "percent_passing"), and optionally `sieve`; '#' lines are comments. The opening column says
// its unit (`opening_mm`, `opening_in`, `opening_m`, or opening_<unit> for any unit of
// parse_length), or is a bare `opening` whose values carry their unit ("4.75 mm") or are in
// `length_unit` (metres per unit). Plain numbers with no unit are refused, showing their mm and
// inch readings: the two are common in sieve tables and 25.4 apart.
// A file that is not a regular file, or is over 16 MiB, is refused before it is read.
Grading read_grading_csv(const std::string& file, std::optional<double> length_unit = std::nullopt,
                         const std::string& percent_column = "percent_passing");
// The same reader on text in memory; `file` names it in messages.
Grading parse_grading_csv(std::string_view text, const std::string& file,
                          std::optional<double> length_unit = std::nullopt,
                          const std::string& percent_column = "percent_passing");

// Percent passing by mass at any opening d (m): linear in log d between sieves, 100 above the
// largest sieve, the smallest sieve's value below it.
[[nodiscard]] double percent_passing_at(const Grading& grading, double d);
// The opening at which the curve reaches `percent` (D10 = opening_at_percent(g, 10), ...).
[[nodiscard]] double opening_at_percent(const Grading& grading, double percent);
// ASTM C125 fineness modulus: cumulative percent retained on #100, #50, #30, #16, #8, #4,
// 3/8, 3/4, 1-1/2, 3 and 6 in (fineness_modulus_sieves, m), divided by 100.
[[nodiscard]] double fineness_modulus(const Grading& grading);
const std::vector<double>& fineness_modulus_sieves();
// The sizes of ASTM C125 on a sieve analysis (its own sieves): the maximum size, the smallest
// sieve through which all of it passes (100 %), and the nominal maximum size, the smallest
// sieve through which all of it is permitted to pass under a grading specification. ASTM C33's
// gradings permit 90 to 100 % passing on that sieve, so on a measured analysis it is the
// smallest sieve passing at least 90 % (AASHTO M 323's "one sieve size larger than the first
// sieve to retain more than 10 percent").
[[nodiscard]] double maximum_size(const Grading& grading);
[[nodiscard]] double nominal_maximum_size(const Grading& grading);

// A band of acceptable gradings (ASTM C33): per sieve, minimum and maximum percent passing.
struct BandSieve {
  std::string name;
  double opening = 0.0;  // m
  double min_percent = 0.0, max_percent = 0.0;
};
struct Band {
  std::string name;
  std::vector<BandSieve> sieves;  // ascending opening
};

struct BandCheckRow {
  BandSieve sieve;
  double percent_passing = 0.0;  // the grading's, at the band's sieve
  bool inside = false;
};
struct BandCheck {
  std::vector<BandCheckRow> rows;
  [[nodiscard]] bool all_inside() const;
};
// Where the grading gives no sieve at a band opening, its curve is interpolated there.
BandCheck check_against_band(const Grading& grading, const Band& band);

// Gradings and bands shipped with aggpack:
//   fu2003_table1_coarse                     the paper's Table 1 coarse aggregate
//   astm_c33_fine_{min,max,mid}              ASTM C33 fine aggregate limits and mid-band
//   astm_c33_57_{min,max,mid}, astm_c33_67_{min,max,mid}  C33 coarse sizes No. 57 and No. 67
// Bands: astm_c33_fine, astm_c33_57, astm_c33_67.
std::optional<Grading> named_grading(std::string_view name);
std::optional<Band> named_band(std::string_view name);
std::vector<std::string> named_grading_names();
std::vector<std::string> named_band_names();

// Grading laws, as curves on the ASTM sieve series up to d_max (with d_max itself as the top):
//   fuller: 100 (d/D)^0.5; power_045: 100 (d/D)^0.45; andreasen: 100 (d/D)^q;
//   modified_andreasen (Dinger-Funk): 100 (d^q - dmin^q) / (D^q - dmin^q).
enum class GradingLawKind { Fuller, Power045, Andreasen, ModifiedAndreasen };
inline constexpr std::array kGradingLawNames{
    EnumName<GradingLawKind>{GradingLawKind::Fuller, "fuller"},
    EnumName<GradingLawKind>{GradingLawKind::Power045, "power_045"},
    EnumName<GradingLawKind>{GradingLawKind::Andreasen, "andreasen"},
    EnumName<GradingLawKind>{GradingLawKind::ModifiedAndreasen, "modified_andreasen"}};
struct GradingLaw {
  GradingLawKind kind = GradingLawKind::Fuller;
  double d_max = 0.0;  // m
  double q = 0.5;      // Andreasen exponents
  double d_min = 0.0;  // m, modified Andreasen only
};
Grading grading_from_law(const GradingLaw& law);
[[nodiscard]] double law_percent_passing(const GradingLaw& law, double d);

// The ASTM sieve series used by the laws and the fineness modulus: (name, opening in m).
struct StandardSieve {
  const char* name;
  double opening;
};
const std::vector<StandardSieve>& astm_sieve_series();

}  // namespace aggpack
