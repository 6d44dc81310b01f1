#include "aggpack/sizes/grading.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "aggpack/core/error.hpp"
#include "aggpack/core/input_file.hpp"
#include "aggpack/core/text.hpp"
#include "aggpack/core/units.hpp"

namespace aggpack {

namespace {
constexpr double kInch = 0.0254;
constexpr double kMm = 0.001;

Grading grading_in_inches(std::string name, std::vector<std::pair<const char*, std::pair<double, double>>> rows) {
  std::vector<Sieve> sieves;
  std::vector<std::string> row_names;
  for (const auto& [sieve, values] : rows) {
    sieves.push_back({sieve, values.first * kInch, values.second});
    row_names.push_back(sieve);
  }
  return make_grading(std::move(name), std::move(sieves), "built-in grading", row_names);
}

// ASTM C33 bands as (sieve, opening in mm, min %, max %), standard metric openings.
struct BandRow {
  const char* sieve;
  double opening_mm, min, max;
};
Band make_band(std::string name, const std::vector<BandRow>& rows) {
  Band band{std::move(name), {}};
  for (const auto& r : rows) band.sieves.push_back({r.sieve, r.opening_mm * kMm, r.min, r.max});
  std::sort(band.sieves.begin(), band.sieves.end(), [](auto& a, auto& b) { return a.opening < b.opening; });
  return band;
}

// ASTM C33 Table 1 (fine aggregate) and Table 2 (coarse sizes No. 57 and No. 67).
const std::vector<BandRow> kC33Fine = {{"3/8in", 9.5, 100, 100}, {"#4", 4.75, 95, 100}, {"#8", 2.36, 80, 100},
                                       {"#16", 1.18, 50, 85},    {"#30", 0.600, 25, 60}, {"#50", 0.300, 5, 30},
                                       {"#100", 0.150, 0, 10}};
const std::vector<BandRow> kC33No57 = {{"1-1/2in", 37.5, 100, 100}, {"1in", 25.0, 95, 100}, {"1/2in", 12.5, 25, 60},
                                       {"#4", 4.75, 0, 10},          {"#8", 2.36, 0, 5}};
const std::vector<BandRow> kC33No67 = {{"1in", 25.0, 100, 100}, {"3/4in", 19.0, 90, 100}, {"3/8in", 9.5, 20, 55},
                                       {"#4", 4.75, 0, 10},      {"#8", 2.36, 0, 5}};

Grading band_curve(const std::string& name, const std::vector<BandRow>& rows, int which) {
  std::vector<Sieve> sieves;
  std::vector<std::string> row_names;
  for (const auto& r : rows) {
    sieves.push_back({r.sieve, r.opening_mm * kMm, which < 0 ? r.min : (which > 0 ? r.max : 0.5 * (r.min + r.max))});
    row_names.push_back(r.sieve);
  }
  return make_grading(name, std::move(sieves), "built-in grading", row_names);
}

// A designation as the series spells it: "No. 4" and "no4" as "#4", `3/8"` and "3/8 in" as
// "3/8in", "1 1/2 in" as "1-1/2in".
std::string designation_key(std::string_view name) {
  const std::string_view t = trim(name);
  std::string key;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const auto c = static_cast<unsigned char>(t[i]);
    if (std::isspace(c)) {
      if (!key.empty() && std::isdigit(static_cast<unsigned char>(key.back())) && i + 1 < t.size() &&
          std::isdigit(static_cast<unsigned char>(t[i + 1])))
        key += '-';
      continue;
    }
    key += static_cast<char>(std::tolower(c));
  }
  for (const std::string_view prefix : {"no.", "no"})
    if (key.starts_with(prefix) && key.size() > prefix.size() &&
        std::isdigit(static_cast<unsigned char>(key[prefix.size()]))) {
      key = "#" + key.substr(prefix.size());
      break;
    }
  for (const std::string_view suffix : {"\"", "in.", "inch", "inches"})
    if (key.ends_with(suffix)) {
      key = key.substr(0, key.size() - suffix.size()) + "in";
      break;
    }
  return key;
}

// The opening (m) a sieve's name stands for: a standard designation ("#200", "3/8in") or a
// length with its unit ("4.75 mm"); nothing for other names ("pan", "2", empty).
std::optional<double> designated_opening(std::string_view name) {
  const std::string key = designation_key(name);
  if (key.empty()) return std::nullopt;
  for (const StandardSieve& standard : astm_sieve_series())
    if (key == standard.name) return standard.opening;
  // A bare number ("2", EN 933-2's 2 mm sieve) has no unit to check against.
  if (std::none_of(key.begin(), key.end(), [](unsigned char c) { return std::isalpha(c); })) return std::nullopt;
  return parse_length(name);
}

// A sieve whose name and opening disagree by more than the snapping tolerance: one of the two
// is wrong (most often the unit of the openings), so neither is taken.
void check_designations(const std::vector<Sieve>& sieves, const std::string& source,
                        const std::function<std::string(std::size_t)>& row) {
  for (std::size_t i = 0; i < sieves.size(); ++i) {
    const Sieve& s = sieves[i];
    const auto designated = designated_opening(s.name);
    if (!designated || std::abs(s.opening / *designated - 1.0) <= kSieveSnapTolerance) continue;
    throw InputError(fmt::format(
        "{}: {}: sieve '{}' is the {:.4g} mm ({:.4g} in) sieve, but its opening reads {:.4g} mm ({:.4g} in), {:.3g} "
        "times {}; the designation and the opening contradict each other (beyond {:g} %): check the unit of the "
        "openings (opening_mm or opening_in in a file's header) or the designation",
        source, row(i), s.name, *designated / kMm, *designated / kInch, s.opening / kMm, s.opening / kInch,
        s.opening > *designated ? s.opening / *designated : *designated / s.opening,
        s.opening > *designated ? "as large" : "as small", 100 * kSieveSnapTolerance));
  }
}

// Moves each opening within kSieveSnapTolerance of a standard sieve onto it (unless another
// opening is already there or would land there too) and returns what moved.
std::vector<SnappedSieve> snap_to_standard_sieves(std::vector<Sieve>& sieves) {
  std::vector<const StandardSieve*> target(sieves.size(), nullptr);
  for (std::size_t i = 0; i < sieves.size(); ++i)
    for (const StandardSieve& standard : astm_sieve_series())
      if (std::abs(sieves[i].opening / standard.opening - 1.0) <= kSieveSnapTolerance) target[i] = &standard;
  const auto landing_on = [&](double opening) {
    std::size_t n = 0;
    for (std::size_t j = 0; j < sieves.size(); ++j) n += (target[j] ? target[j]->opening : sieves[j].opening) == opening;
    return n;
  };
  std::vector<SnappedSieve> snapped;
  for (std::size_t i = 0; i < sieves.size(); ++i) {
    if (!target[i] || sieves[i].opening == target[i]->opening || landing_on(target[i]->opening) > 1) continue;
    if (sieves[i].name.empty()) sieves[i].name = target[i]->name;
    snapped.push_back({sieves[i].name, sieves[i].opening, target[i]->opening});
  }
  for (const SnappedSieve& moved : snapped)
    for (Sieve& sieve : sieves)
      if (sieve.opening == moved.given) sieve.opening = moved.standard;
  return snapped;
}
}  // namespace

Grading make_grading(std::string name, std::vector<Sieve> sieves, const std::string& source,
                     const std::vector<std::string>& row_names) {
  const auto row = [&](std::size_t i) { return i < row_names.size() ? row_names[i] : fmt::format("row {}", i + 1); };
  if (sieves.size() < 2)
    throw InputError(fmt::format("{}: grading '{}' has {} sieve(s); a grading needs at least two", source, name,
                                 sieves.size()));
  for (std::size_t i = 0; i < sieves.size(); ++i) {
    const Sieve& s = sieves[i];
    if (!(s.opening > 0.0) || !std::isfinite(s.opening))
      throw InputError(fmt::format("{}: {}: sieve opening must be a positive length, got {:g} m", source, row(i),
                                   s.opening));
    if (!(s.percent_passing >= 0.0 && s.percent_passing <= 100.0))
      throw InputError(fmt::format("{}: {}: percent passing must be between 0 and 100, got {:g}", source, row(i),
                                   s.percent_passing));
  }
  check_designations(sieves, source, row);
  std::vector<SnappedSieve> snapped = snap_to_standard_sieves(sieves);
  std::vector<std::size_t> order(sieves.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](auto a, auto b) { return sieves[a].opening < sieves[b].opening; });
  for (std::size_t k = 1; k < order.size(); ++k) {
    const Sieve& lo = sieves[order[k - 1]];
    const Sieve& hi = sieves[order[k]];
    if (hi.opening == lo.opening)
      throw InputError(fmt::format("{}: {} and {}: duplicate sieve opening {:g} m", source, row(order[k - 1]),
                                   row(order[k]), hi.opening));
    if (hi.percent_passing < lo.percent_passing)
      throw InputError(fmt::format("{}: {}: percent passing {:g} at {:g} m is less than {:g} at the smaller sieve "
                                   "{:g} m ({}); percent passing must not decrease as the opening grows",
                                   source, row(order[k]), hi.percent_passing, hi.opening, lo.percent_passing,
                                   lo.opening, row(order[k - 1])));
  }
  const Sieve& top = sieves[order.back()];
  if (top.percent_passing != 100.0)
    throw InputError(fmt::format("{}: {}: the largest sieve ({:g} m) passes {:g} %; a grading needs a sieve that "
                                 "passes 100 % (add the next larger sieve at 100)",
                                 source, row(order.back()), top.opening, top.percent_passing));
  Grading g{std::move(name), {}, std::move(snapped)};
  for (std::size_t i : order) g.sieves.push_back(sieves[i]);
  return g;
}

Grading read_grading_csv(const std::string& file, std::optional<double> length_unit,
                         const std::string& percent_column) {
  // A sieve analysis is a few dozen rows: 16 MiB is far beyond any real one.
  return parse_grading_csv(read_input_text(file, "the grading file", std::uintmax_t{16} << 20), file, length_unit,
                           percent_column);
}

namespace {
// An opening column: its header and its unit (metres per unit), which a bare `opening` header
// has only from the caller.
struct OpeningColumn {
  int col = -1;
  std::string header;
  std::optional<double> unit;
};
std::optional<OpeningColumn> opening_column(const std::string& header, int col, std::optional<double> length_unit) {
  if (header == "opening") return OpeningColumn{col, header, length_unit};
  if (!header.starts_with("opening_")) return std::nullopt;
  const auto unit = metres_per_unit(std::string_view(header).substr(8));
  if (!unit) return std::nullopt;
  return OpeningColumn{col, header, static_cast<double>(*unit)};
}

// A bare `opening` column of plain numbers and no unit from the caller: millimetres and inches
// are both common in sieve tables and 25.4 apart, so the column is refused showing what its
// first rows would be in each (and which one the sieve designations agree with).
struct BareOpening {
  std::size_t line = 0;
  double value = 0.0;
  std::string sieve;  // the row's designation, if any
};
[[noreturn]] void refuse_unitless_openings(const std::string& file, std::size_t header_line,
                                           const std::vector<BareOpening>& bare) {
  std::vector<std::string> readings;
  for (std::size_t k = 0; k < std::min<std::size_t>(bare.size(), 3); ++k)
    readings.push_back(fmt::format("line {}: {:g} is {:.4g} mm, or {:.4g} mm if inches", bare[k].line, bare[k].value,
                                   bare[k].value, bare[k].value * kInch / kMm));
  std::string hint;
  for (std::size_t k = 0; k < bare.size() && hint.empty(); ++k) {
    const auto designated = designated_opening(bare[k].sieve);
    if (!designated) continue;
    for (const auto& [unit, symbol] : {std::pair{kMm, "mm"}, std::pair{kInch, "in"}})
      if (std::abs(bare[k].value * unit / *designated - 1.0) <= kSieveSnapTolerance)
        hint = fmt::format(" (its sieve column agrees with {}: {} is {:.4g} mm)", symbol, bare[k].sieve,
                           *designated / kMm);
  }
  throw InputError(fmt::format(
      "{}:{}: the column 'opening' gives no unit{}; {}; name the column opening_mm, opening_in or opening_m, or "
      "write the unit in each value (\"{:g} mm\"), or give the unit of a bare 'opening' column (length_unit in the "
      "scenario's grading table, --length-unit of aggpack grading)",
      file, header_line, hint, fmt::join(readings, "; "), bare.front().value));
}
}  // namespace

Grading parse_grading_csv(std::string_view text, const std::string& file, std::optional<double> length_unit,
                          const std::string& percent_column) {
  std::istringstream in{std::string(text)};
  std::string line;
  std::vector<std::string> header;
  std::size_t line_no = 0, header_line = 0;
  std::vector<Sieve> sieves;
  std::vector<std::string> rows;
  int name_col = -1, percent_col = -1;
  std::optional<OpeningColumn> opening;
  std::vector<BareOpening> bare;  // plain numbers in a column without a unit
  while (std::getline(in, line)) {
    ++line_no;
    line = std::string(trim(line));
    // "# text" is a comment; "#4,4.75,95" is a sieve row.
    if (line.empty() || (line[0] == '#' && (line.size() == 1 || std::isspace(static_cast<unsigned char>(line[1])))))
      continue;
    const auto fields = split_csv_fields(line);
    if (header.empty()) {
      header = fields;
      header_line = line_no;
      for (std::size_t c = 0; c < header.size(); ++c) {
        const std::string& h = header[c];
        if (h == "sieve") name_col = static_cast<int>(c);
        else if (h == percent_column) percent_col = static_cast<int>(c);
        else if (!opening) opening = opening_column(h, static_cast<int>(c), length_unit);
      }
      if (!opening || percent_col < 0)
        throw InputError(fmt::format("{}:{}: the header needs an opening column (opening_mm, opening_in, opening_m, "
                                     "or opening with a unit in each value) and a '{}' column; got '{}'",
                                     file, line_no, percent_column, line));
      continue;
    }
    const auto field = [&](int col, const char* what) -> const std::string& {
      if (col >= static_cast<int>(fields.size()) || fields[col].empty())
        throw InputError(fmt::format("{}:{}: missing {}", file, line_no, what));
      return fields[col];
    };
    const auto plain_number = [](const std::string& value) -> std::optional<double> {
      try {
        std::size_t used = 0;
        const double v = std::stod(value, &used);
        if (used == value.size()) return v;
      } catch (const std::exception&) {
      }
      return std::nullopt;
    };
    Sieve s;
    if (name_col >= 0 && name_col < static_cast<int>(fields.size())) s.name = fields[name_col];
    const std::string& opening_text = field(opening->col, "sieve opening");
    if (const auto v = plain_number(opening_text)) {
      if (opening->unit) s.opening = *v * *opening->unit;
      else bare.push_back({line_no, *v, s.name});
    } else if (opening->header != "opening") {
      // A unit in the value would repeat the header's or contradict it.
      throw InputError(fmt::format("{}:{}: sieve opening '{}' is not a number; column '{}' takes plain numbers", file,
                                   line_no, opening_text, opening->header));
    } else {
      std::string why;
      const auto length = parse_length(opening_text, &why);
      if (!length)
        throw InputError(fmt::format("{}:{}: sieve opening '{}' is not a length ({}); expected a number or a length "
                                     "such as \"4.75 mm\"",
                                     file, line_no, opening_text, why));
      s.opening = *length;
    }
    const std::string& percent_text = field(percent_col, "percent passing");
    const auto percent = plain_number(percent_text);
    if (!percent)
      throw InputError(fmt::format("{}:{}: percent passing '{}' is not a number", file, line_no, percent_text));
    s.percent_passing = *percent;
    sieves.push_back(s);
    rows.push_back(fmt::format("line {}", line_no));
  }
  if (!bare.empty()) refuse_unitless_openings(file, header_line, bare);
  std::string stem = file.substr(file.find_last_of('/') + 1);
  stem = stem.substr(0, stem.find_last_of('.'));
  return make_grading(stem, std::move(sieves), file, rows);
}

bool BandCheck::all_inside() const {
  return std::all_of(rows.begin(), rows.end(), [](const BandCheckRow& r) { return r.inside; });
}

double percent_passing_at(const Grading& grading, double d) {
  const auto& s = grading.sieves;
  if (d >= s.back().opening) return 100.0;
  if (d <= s.front().opening) return s.front().percent_passing;
  const auto hi = std::lower_bound(s.begin(), s.end(), d, [](const Sieve& a, double v) { return a.opening < v; });
  const auto lo = hi - 1;
  const double t = std::log(d / lo->opening) / std::log(hi->opening / lo->opening);
  return lo->percent_passing + t * (hi->percent_passing - lo->percent_passing);
}

double opening_at_percent(const Grading& grading, double percent) {
  const auto& s = grading.sieves;
  if (percent <= s.front().percent_passing) return s.front().opening;
  for (std::size_t i = 1; i < s.size(); ++i)
    if (percent <= s[i].percent_passing) {
      const double span = s[i].percent_passing - s[i - 1].percent_passing;
      const double t = span > 0.0 ? (percent - s[i - 1].percent_passing) / span : 1.0;
      return s[i - 1].opening * std::pow(s[i].opening / s[i - 1].opening, t);
    }
  return s.back().opening;
}

const std::vector<double>& fineness_modulus_sieves() {
  static const std::vector<double> openings = {0.150e-3, 0.300e-3, 0.600e-3, 1.18e-3, 2.36e-3, 4.75e-3,
                                               9.5e-3,   19.0e-3,  37.5e-3,  75.0e-3, 150.0e-3};
  return openings;
}

double fineness_modulus(const Grading& grading) {
  double sum = 0.0;
  for (double opening : fineness_modulus_sieves()) sum += 100.0 - percent_passing_at(grading, opening);
  return sum / 100.0;
}

namespace {
// The smallest of the grading's sieves passing at least `percent` (the largest passes 100).
double smallest_sieve_passing(const Grading& grading, double percent) {
  for (const Sieve& s : grading.sieves)
    if (s.percent_passing >= percent - 1e-9) return s.opening;
  return grading.largest();
}
}  // namespace

double maximum_size(const Grading& grading) { return smallest_sieve_passing(grading, 100.0); }
double nominal_maximum_size(const Grading& grading) { return smallest_sieve_passing(grading, 90.0); }

BandCheck check_against_band(const Grading& grading, const Band& band) {
  BandCheck check;
  for (const BandSieve& b : band.sieves) {
    const double p = percent_passing_at(grading, b.opening);
    const double slack = 1e-9;
    check.rows.push_back({b, p, p >= b.min_percent - slack && p <= b.max_percent + slack});
  }
  return check;
}

std::optional<Grading> named_grading(std::string_view name) {
  if (name == "fu2003_table1_coarse")
    return grading_in_inches("fu2003_table1_coarse", {{"#200", {0.0029, 0}},
                                                      {"#100", {0.0059, 0}},
                                                      {"#50", {0.0117, 0}},
                                                      {"#30", {0.0232, 0}},
                                                      {"#16", {0.049, 0}},
                                                      {"#8", {0.097, 2.7}},
                                                      {"#4", {0.185, 6.8}},
                                                      {"3/8in", {0.375, 25.6}},
                                                      {"1/2in", {0.5, 45.4}},
                                                      {"3/4in", {0.75, 90.4}},
                                                      {"1in", {1.0, 100}}});
  const std::map<std::string_view, const std::vector<BandRow>*> bands = {
      {"astm_c33_fine", &kC33Fine}, {"astm_c33_57", &kC33No57}, {"astm_c33_67", &kC33No67}};
  for (const auto& [band, rows] : bands)
    for (const auto& [suffix, which] : {std::pair{"_min", -1}, std::pair{"_max", 1}, std::pair{"_mid", 0}})
      if (name == std::string(band) + suffix) return band_curve(std::string(name), *rows, which);
  return std::nullopt;
}

std::optional<Band> named_band(std::string_view name) {
  if (name == "astm_c33_fine") return make_band("astm_c33_fine", kC33Fine);
  if (name == "astm_c33_57") return make_band("astm_c33_57", kC33No57);
  if (name == "astm_c33_67") return make_band("astm_c33_67", kC33No67);
  return std::nullopt;
}

std::vector<std::string> named_grading_names() {
  std::vector<std::string> names{"fu2003_table1_coarse"};
  for (const char* band : {"astm_c33_fine", "astm_c33_57", "astm_c33_67"})
    for (const char* suffix : {"_min", "_max", "_mid"}) names.push_back(std::string(band) + suffix);
  return names;
}

std::vector<std::string> named_band_names() { return {"astm_c33_fine", "astm_c33_57", "astm_c33_67"}; }

const std::vector<StandardSieve>& astm_sieve_series() {
  static const std::vector<StandardSieve> series = {
      {"#200", 0.075e-3}, {"#100", 0.150e-3}, {"#50", 0.300e-3}, {"#30", 0.600e-3}, {"#16", 1.18e-3},
      {"#8", 2.36e-3},    {"#4", 4.75e-3},    {"3/8in", 9.5e-3}, {"1/2in", 12.5e-3}, {"3/4in", 19.0e-3},
      {"1in", 25.0e-3},   {"1-1/2in", 37.5e-3}, {"2in", 50.0e-3}, {"3in", 75.0e-3}};
  return series;
}

double law_percent_passing(const GradingLaw& law, double d) {
  if (d >= law.d_max) return 100.0;
  switch (law.kind) {
    case GradingLawKind::Fuller: return 100.0 * std::sqrt(d / law.d_max);
    case GradingLawKind::Power045: return 100.0 * std::pow(d / law.d_max, 0.45);
    case GradingLawKind::Andreasen: return 100.0 * std::pow(d / law.d_max, law.q);
    case GradingLawKind::ModifiedAndreasen:
      if (d <= law.d_min) return 0.0;
      return 100.0 * (std::pow(d, law.q) - std::pow(law.d_min, law.q)) /
             (std::pow(law.d_max, law.q) - std::pow(law.d_min, law.q));
  }
  return 0.0;
}

Grading grading_from_law(const GradingLaw& law) {
  if (!(law.d_max > 0.0)) throw InputError("grading law: d_max must be a positive length");
  if (!(law.q > 0.0)) throw InputError("grading law: the exponent q must be positive");
  if (law.kind == GradingLawKind::ModifiedAndreasen && !(law.d_min > 0.0 && law.d_min < law.d_max))
    throw InputError("grading law: modified Andreasen needs 0 < d_min < d_max");
  std::vector<Sieve> sieves;
  std::vector<std::string> rows;
  for (const StandardSieve& s : astm_sieve_series())
    if (s.opening < law.d_max * (1 - 1e-9)) {
      sieves.push_back({s.name, s.opening, law_percent_passing(law, s.opening)});
      rows.push_back(s.name);
    }
  sieves.push_back({"d_max", law.d_max, 100.0});
  rows.push_back("d_max");
  return make_grading(std::string(name_of(kGradingLawNames, law.kind)), std::move(sieves), "grading law", rows);
}

}  // namespace aggpack
