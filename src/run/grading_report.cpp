#include "aggpack/run/grading_report.hpp"

#include <algorithm>
#include <filesystem>
#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "aggpack/core/error.hpp"
#include "aggpack/sizes/grading_sampler.hpp"

namespace aggpack {

nlohmann::json snapped_sieves_json(const Grading& g) {
  nlohmann::json j = nlohmann::json::array();
  for (const SnappedSieve& s : g.snapped)
    j.push_back({{"sieve", s.name}, {"given_m", s.given}, {"standard_m", s.standard}});
  return j;
}

std::string snapped_sieves_text(const std::vector<SnappedSieve>& snapped) {
  std::vector<std::string> moves;
  for (const SnappedSieve& m : snapped)
    moves.push_back(fmt::format("{} {:.4g} -> {:.4g} mm", m.name, 1e3 * m.given, 1e3 * m.standard));
  if (moves.empty()) return {};
  return fmt::format("openings within {:g} % of a standard sieve taken as that sieve (ASTM E11 series): {}",
                     100 * kSieveSnapTolerance, fmt::join(moves, ", "));
}

Grading load_grading(const std::string& name_or_file, std::optional<double> unit) {
  if (auto g = named_grading(name_or_file)) return *g;
  if (std::filesystem::exists(name_or_file)) return read_grading_csv(name_or_file, unit);
  throw InputError(fmt::format("{}: neither a shipped grading ({}) nor a file", name_or_file,
                               fmt::join(named_grading_names(), ", ")));
}

namespace {

nlohmann::json curve_json(const Grading& g) {
  nlohmann::json j;
  j["name"] = g.name;
  for (const Sieve& s : g.sieves)
    j["sieves"].push_back({{"sieve", s.name}, {"opening_m", s.opening}, {"percent_passing", s.percent_passing}});
  j["fineness_modulus"] = fineness_modulus(g);
  j["d10_m"] = opening_at_percent(g, 10);
  j["d50_m"] = opening_at_percent(g, 50);
  j["d90_m"] = opening_at_percent(g, 90);
  j["snapped_sieves"] = snapped_sieves_json(g);
  if (!g.snapped.empty()) j["snapped_note"] = snapped_sieves_text(g.snapped);
  return j;
}
}  // namespace

nlohmann::json band_check_json(const Band& band, const BandCheck& check) {
  nlohmann::json b{{"name", band.name}, {"all_inside", check.all_inside()}, {"sieves", nlohmann::json::array()}};
  for (const BandCheckRow& row : check.rows)
    b["sieves"].push_back({{"sieve", row.sieve.name},
                           {"opening_m", row.sieve.opening},
                           {"min_percent", row.sieve.min_percent},
                           {"max_percent", row.sieve.max_percent},
                           {"percent", row.percent_passing},
                           {"inside", row.inside}});
  return b;
}

GradingDescription describe_grading(const GradingQuery& q) {
  GradingDescription d;
  d.grading = load_grading(q.grading, q.length_unit);
  const Grading& main = d.grading;
  if (q.fine) {
    d.fine = load_grading(*q.fine, q.length_unit);
    if (!(q.ca_fa > 0.0)) throw InputError("--ca-fa: the coarse/fine volume ratio must be positive");
    // The blend by volume at the union of both sets of sieves (both on the standard series
    // already, so a nominal sieve appears once).
    std::vector<Sieve> openings = main.sieves;
    for (const Sieve& s : d.fine->sieves)
      if (std::none_of(openings.begin(), openings.end(), [&](const Sieve& o) { return o.opening == s.opening; }))
        openings.push_back(s);
    std::vector<Sieve> blend;
    for (const Sieve& s : openings) {
      const double p = (q.ca_fa * percent_passing_at(main, s.opening) + percent_passing_at(*d.fine, s.opening)) /
                       (1.0 + q.ca_fa);
      blend.push_back({s.name, s.opening, p});
    }
    d.ca_fa = q.ca_fa;
    d.mix = make_grading(fmt::format("{} + {} at Ca/Fa {:g}", main.name, d.fine->name, q.ca_fa), blend, "mix", {});
  }
  const Grading& checked = d.checked();
  if (q.d_min || q.d_max) d.cut = cut_grading(checked, q.d_min, q.d_max, "--d-min/--d-max");
  if (q.band) {
    d.band = named_band(*q.band);
    if (!d.band)
      throw InputError(fmt::format("--band {}: unknown band; shipped bands: {}", *q.band,
                                   fmt::join(named_band_names(), ", ")));
    d.band_check = check_against_band(checked, *d.band);
  }
  return d;
}

nlohmann::json to_json(const GradingDescription& d) {
  nlohmann::json j;
  j["grading"] = curve_json(d.grading);
  if (d.fine) {
    j["fine"] = curve_json(*d.fine);
    j["ca_fa"] = d.ca_fa;
    j["mix"] = curve_json(*d.mix);
  }
  if (d.cut)
    j["cut"] = {{"d_lo_m", d.cut->d_lo}, {"d_hi_m", d.cut->d_hi}, {"cut_below_fraction", d.cut->cut_below},
                {"cut_above_fraction", d.cut->cut_above}, {"renormalisation", "proportional"}};
  if (d.band) {
    j["band"] = band_check_json(*d.band, d.band_check);
    j["band"]["checked"] = d.checked().name;
  }
  return j;
}

std::string format_grading(const GradingDescription& d) {
  std::string out;
  const auto curve = [&](const Grading& g) {
    out += fmt::format("{}\n  {:>8} {:>10} {:>9}\n", g.name, "sieve", "opening mm", "passing %");
    for (const Sieve& s : g.sieves)
      out += fmt::format("  {:>8} {:>10.4g} {:>9.2f}\n", s.name, 1e3 * s.opening, s.percent_passing);
    out += fmt::format("  fineness modulus {:.2f}; D10 {:.3g} mm, D50 {:.3g} mm, D90 {:.3g} mm (by mass)\n",
                       fineness_modulus(g), 1e3 * opening_at_percent(g, 10), 1e3 * opening_at_percent(g, 50),
                       1e3 * opening_at_percent(g, 90));
    if (!g.snapped.empty()) out += "  " + snapped_sieves_text(g.snapped) + "\n";
  };
  curve(d.grading);
  if (d.fine) {
    curve(*d.fine);
    curve(*d.mix);
  }
  if (d.cut)
    out += fmt::format("cut-offs: {:.4g} to {:.4g} mm kept; {:.2f} % of the volume below and {:.2f} % above removed, "
                       "the rest renormalised proportionally\n",
                       1e3 * d.cut->d_lo, 1e3 * d.cut->d_hi, 100 * d.cut->cut_below, 100 * d.cut->cut_above);
  if (d.band) {
    out += fmt::format("band {} for {}: {}\n", d.band->name, d.checked().name,
                       d.band_check.all_inside() ? "inside at every sieve" : "OUTSIDE at some sieves");
    out += fmt::format("  {:>8} {:>10} {:>7} {:>7} {:>9}\n", "sieve", "opening mm", "min %", "max %", "passing %");
    for (const BandCheckRow& r : d.band_check.rows)
      out += fmt::format("  {:>8} {:>10.4g} {:>7.1f} {:>7.1f} {:>9.2f}  {}\n", r.sieve.name, 1e3 * r.sieve.opening,
                         r.sieve.min_percent, r.sieve.max_percent, r.percent_passing, r.inside ? "inside" : "OUTSIDE");
  }
  return out;
}

}  // namespace aggpack
