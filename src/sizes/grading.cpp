#include "aggpack/sizes/grading.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/core/input_file.hpp"
#include "aggpack/core/text.hpp"

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

Grading read_grading_csv(const std::string& file, double length_unit, const std::string& percent_column) {
  // A sieve analysis is a few dozen rows: 16 MiB is far beyond any real one.
  return parse_grading_csv(read_input_text(file, "the grading file", std::uintmax_t{16} << 20), file, length_unit,
                           percent_column);
}

Grading parse_grading_csv(std::string_view text, const std::string& file, double length_unit,
                          const std::string& percent_column) {
  std::istringstream in{std::string(text)};
  std::string line;
  std::vector<std::string> header;
  std::size_t line_no = 0;
  std::vector<Sieve> sieves;
  std::vector<std::string> rows;
  int name_col = -1, opening_col = -1, percent_col = -1;
  double unit = length_unit;
  while (std::getline(in, line)) {
    ++line_no;
    line = std::string(trim(line));
    // "# text" is a comment; "#4,4.75,95" is a sieve row.
    if (line.empty() || (line[0] == '#' && (line.size() == 1 || std::isspace(static_cast<unsigned char>(line[1])))))
      continue;
    const auto fields = split_csv_fields(line);
    if (header.empty()) {
      header = fields;
      for (std::size_t c = 0; c < header.size(); ++c) {
        const std::string& h = header[c];
        if (h == "sieve") name_col = static_cast<int>(c);
        else if (h == percent_column) percent_col = static_cast<int>(c);
        else if (opening_col < 0 && (h == "opening_in" || h == "opening_mm" || h == "opening_m" || h == "opening")) {
          opening_col = static_cast<int>(c);
          unit = h == "opening_in" ? kInch : h == "opening_mm" ? kMm : h == "opening_m" ? 1.0 : length_unit;
        }
      }
      if (opening_col < 0 || percent_col < 0)
        throw InputError(fmt::format("{}:{}: the header needs an opening column (opening_in, opening_mm, opening_m "
                                     "or opening) and a '{}' column; got '{}'",
                                     file, line_no, percent_column, line));
      continue;
    }
    const auto number = [&](int col, const char* what) {
      if (col >= static_cast<int>(fields.size()) || fields[col].empty())
        throw InputError(fmt::format("{}:{}: missing {}", file, line_no, what));
      try {
        std::size_t used = 0;
        const double v = std::stod(fields[col], &used);
        if (used != fields[col].size()) throw std::invalid_argument("trailing");
        return v;
      } catch (const std::exception&) {
        throw InputError(fmt::format("{}:{}: {} '{}' is not a number", file, line_no, what, fields[col]));
      }
    };
    Sieve s;
    s.opening = number(opening_col, "sieve opening") * unit;
    s.percent_passing = number(percent_col, "percent passing");
    if (name_col >= 0 && name_col < static_cast<int>(fields.size())) s.name = fields[name_col];
    sieves.push_back(s);
    rows.push_back(fmt::format("line {}", line_no));
  }
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
