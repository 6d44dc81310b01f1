#include "aggpack/pipeline/grading_report.hpp"

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

std::string snapped_sieves_text(const nlohmann::json& snapped) {
  std::vector<std::string> moves;
  for (const auto& m : snapped)
    moves.push_back(fmt::format("{} {:.4g} -> {:.4g} mm", m.at("sieve").get<std::string>(),
                                1e3 * m.at("given_m").get<double>(), 1e3 * m.at("standard_m").get<double>()));
  if (moves.empty()) return {};
  return fmt::format("openings within {:g} % of a standard sieve taken as that sieve (ASTM E11 series): {}",
                     100 * kSieveSnapTolerance, fmt::join(moves, ", "));
}

namespace {
Grading load(const std::string& name_or_file, double unit) {
  if (auto g = named_grading(name_or_file)) return *g;
  if (std::filesystem::exists(name_or_file)) return read_grading_csv(name_or_file, unit);
  throw InputError(fmt::format("{}: neither a shipped grading ({}) nor a file", name_or_file,
                               fmt::join(named_grading_names(), ", ")));
}

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
  if (!g.snapped.empty()) j["snapped_note"] = snapped_sieves_text(j["snapped_sieves"]);
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

nlohmann::json describe_grading(const GradingQuery& q) {
  const Grading main = load(q.grading, q.length_unit);
  nlohmann::json j;
  j["grading"] = curve_json(main);
  Grading checked = main;
  if (q.fine) {
    const Grading fine = load(*q.fine, q.length_unit);
    if (!(q.ca_fa > 0.0)) throw InputError("--ca-fa: the coarse/fine volume ratio must be positive");
    // The blend by volume at the union of both sets of sieves (both on the standard series
    // already, so a nominal sieve appears once).
    std::vector<Sieve> openings = main.sieves;
    for (const Sieve& s : fine.sieves)
      if (std::none_of(openings.begin(), openings.end(), [&](const Sieve& o) { return o.opening == s.opening; }))
        openings.push_back(s);
    std::vector<Sieve> blend;
    for (const Sieve& s : openings) {
      const double p = (q.ca_fa * percent_passing_at(main, s.opening) + percent_passing_at(fine, s.opening)) /
                       (1.0 + q.ca_fa);
      blend.push_back({s.name, s.opening, p});
    }
    checked = make_grading(fmt::format("{} + {} at Ca/Fa {:g}", main.name, fine.name, q.ca_fa), blend, "mix", {});
    j["fine"] = curve_json(fine);
    j["ca_fa"] = q.ca_fa;
    j["mix"] = curve_json(checked);
  }
  if (q.d_min || q.d_max) {
    const GradingCut cut = cut_grading(checked, q.d_min, q.d_max, "--d-min/--d-max");
    j["cut"] = {{"d_lo_m", cut.d_lo}, {"d_hi_m", cut.d_hi}, {"cut_below_fraction", cut.cut_below},
                {"cut_above_fraction", cut.cut_above}, {"renormalisation", "proportional"}};
  }
  if (q.band) {
    const auto band = named_band(*q.band);
    if (!band)
      throw InputError(fmt::format("--band {}: unknown band; shipped bands: {}", *q.band,
                                   fmt::join(named_band_names(), ", ")));
    j["band"] = band_check_json(*band, check_against_band(checked, *band));
    j["band"]["checked"] = checked.name;
  }
  return j;
}

std::string format_grading(const nlohmann::json& d) {
  std::string out;
  const auto curve = [&](const nlohmann::json& c) {
    out += fmt::format("{}\n  {:>8} {:>10} {:>9}\n", c["name"].get<std::string>(), "sieve", "opening mm", "passing %");
    for (const auto& s : c["sieves"])
      out += fmt::format("  {:>8} {:>10.4g} {:>9.2f}\n", s["sieve"].get<std::string>(), 1e3 * s["opening_m"].get<double>(),
                         s["percent_passing"].get<double>());
    out += fmt::format("  fineness modulus {:.2f}; D10 {:.3g} mm, D50 {:.3g} mm, D90 {:.3g} mm (by mass)\n",
                       c["fineness_modulus"].get<double>(), 1e3 * c["d10_m"].get<double>(),
                       1e3 * c["d50_m"].get<double>(), 1e3 * c["d90_m"].get<double>());
    if (c.contains("snapped_note")) out += "  " + c["snapped_note"].get<std::string>() + "\n";
  };
  curve(d["grading"]);
  if (d.contains("fine")) {
    curve(d["fine"]);
    curve(d["mix"]);
  }
  if (d.contains("cut")) {
    const auto& c = d["cut"];
    out += fmt::format("cut-offs: {:.4g} to {:.4g} mm kept; {:.2f} % of the volume below and {:.2f} % above removed, "
                       "the rest renormalised proportionally\n",
                       1e3 * c["d_lo_m"].get<double>(), 1e3 * c["d_hi_m"].get<double>(),
                       100 * c["cut_below_fraction"].get<double>(), 100 * c["cut_above_fraction"].get<double>());
  }
  if (d.contains("band")) {
    const auto& b = d["band"];
    out += fmt::format("band {} for {}: {}\n", b["name"].get<std::string>(), b["checked"].get<std::string>(),
                       b["all_inside"].get<bool>() ? "inside at every sieve" : "OUTSIDE at some sieves");
    out += fmt::format("  {:>8} {:>10} {:>7} {:>7} {:>9}\n", "sieve", "opening mm", "min %", "max %", "passing %");
    for (const auto& s : b["sieves"])
      out += fmt::format("  {:>8} {:>10.4g} {:>7.1f} {:>7.1f} {:>9.2f}  {}\n", s["sieve"].get<std::string>(),
                         1e3 * s["opening_m"].get<double>(), s["min_percent"].get<double>(),
                         s["max_percent"].get<double>(), s["percent"].get<double>(),
                         s["inside"].get<bool>() ? "inside" : "OUTSIDE");
  }
  return out;
}

}  // namespace aggpack
