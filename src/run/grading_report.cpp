#include "aggpack/run/grading_report.hpp"

#include <algorithm>
#include <filesystem>
#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "aggpack/core/error.hpp"
#include "aggpack/core/rng.hpp"
#include "aggpack/run/run_grains.hpp"
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

// The sample a run's grains are fitted on: as many sizes as make the quantiles of
// library_fit_sizes steady (each quantile then the median of 16 draws).
constexpr std::size_t kShapeSample = 4096;

GradingShape grading_shape(const GrainShapeSpec& spec, const Grading& grading, const GradingQuery& q) {
  const GradingSampler sampler(cut_grading(grading, q.d_min, q.d_max, "--d-min/--d-max"), SamplingMode::Mass);
  Rng rng = make_rng(q.seed, RngPurpose::Sizes);
  std::vector<double> sizes(kShapeSample);
  for (double& d : sizes) d = sampler.draw(rng);
  GradingShape shape{{}, q.seed, sizes.size(), library_fit_sizes(std::move(sizes)), {}};
  const GrainShapeSpec* specs[] = {&spec};
  check_library_cost(specs, RunLimits{}.max_template_minutes, "--shape", "limit (a scenario's limits.max_template_minutes)");
  try {
    shape.library = make_grain_library(spec, shape.fit_sizes, q.seed * 64, q.watch);  // a run's first component's stream
  } catch (const InputError& e) {
    throw InputError(fmt::format("--shape: the grains of {}: {}", grading.name, e.what()));
  }
  shape.templates = shape_statistics(measure_library(shape.library, shape.fit_sizes));
  return shape;
}

nlohmann::json shape_json(const GradingShape& s) {
  nlohmann::json j = library_json(s.library);
  j["seed"] = s.seed;
  j["sizes_sampled"] = s.sampled;
  j["sizes_measured"] = s.fit_sizes.size();
  j["measured"] = shape_statistics_json(s.templates);
  return j;
}

std::string format_shape(const GradingShape& s) {
  const GrainShapeSpec& spec = s.library.spec;
  const ProportionDistribution& d = s.library.distribution;
  std::string out = fmt::format(
      "grains: {} ({}), {} spheres each, {} templates; elongation I/L {:.3f} +- {:.2f}, flatness S/I {:.3f} "
      "+- {:.2f} ({})\n",
      family_name(spec.family),
      spec.family == GrainFamily::Angular ? fmt::format("a random convex hull of {} corners", spec.corners)
                                          : std::string("an ellipsoid"),
      spec.spheres, spec.templates, d.elongation_mean, d.elongation_spread, d.flatness_mean, d.flatness_spread,
      !spec.target ? "as given"
      : spec.target->measure == ShapeMeasure::FlakinessIndex ? "flatness fitted"
                                                              : "both fitted");
  const ShapeStatistics& m = s.templates;
  // A measure's row, the target beside it when it is the target's measure (and ratio).
  const auto row = [&](std::string_view name, const std::optional<double>& value, const ShapeTarget& as) {
    const bool targeted = spec.target && spec.target->measure == as.measure &&
                          (as.measure != ShapeMeasure::FlatAndElongated || spec.target->ratio == as.ratio);
    std::string line = fmt::format("  {:<32} {:>9} {:>9}", name, value ? fmt::format("{:.1f}", *value) : "-",
                                   targeted ? fmt::format("{:.1f}", spec.target->percent) : "");
    line.erase(line.find_last_not_of(' ') + 1);
    out += line + "\n";
  };
  out += fmt::format("  {:<32} {:>9} {:>9}\n", "measure (% by mass)", "templates", "target");
  row("flakiness index (EN 933-3)", m.flakiness_index, ShapeTarget{ShapeMeasure::FlakinessIndex, 0, 0});
  row("shape index (EN 933-4)", m.shape_index, ShapeTarget{ShapeMeasure::ShapeIndex, 0, 0});
  row("flat and elongated 2:1 (D4791)", m.flat_elongated_2, ShapeTarget{ShapeMeasure::FlatAndElongated, 0, 2});
  row("flat and elongated 3:1 (D4791)", m.flat_elongated_3, ShapeTarget{ShapeMeasure::FlatAndElongated, 0, 3});
  row("flat and elongated 5:1 (D4791)", m.flat_elongated_5, ShapeTarget{ShapeMeasure::FlatAndElongated, 0, 5});
  if (spec.target && spec.target->measure == ShapeMeasure::FlatAndElongated && spec.target->ratio != 2.0 &&
      spec.target->ratio != 3.0 && spec.target->ratio != 5.0)
    row(fmt::format("flat and elongated {:g}:1 (D4791)", spec.target->ratio), s.library.fit->achieved_percent,
        *spec.target);
  out += fmt::format("  every template at {} sizes drawn from the grading by mass (seed {}), as a run's grains; "
                     "'-': the standard measures no grain of these sizes\n",
                     s.fit_sizes.size(), s.seed);
  return out;
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
  const auto named = [&](std::string_view flag) { return option_name(flag, q.named); };
  // A blend's ratio is the user's: a default of 1:1 would describe a mix nobody asked for.
  if (q.fine.has_value() != q.ca_fa.has_value())
    throw InputError(fmt::format("{} and {} go together: the fine grading and the coarse/fine volume ratio of the "
                                 "blend (for example {}), which has no default",
                                 named("--mix"), named("--ca-fa"), option_given("--ca-fa", "1.52", q.named)));
  if (q.fine) {
    d.fine = load_grading(*q.fine, q.length_unit);
    const double ca_fa = *q.ca_fa;
    if (!(ca_fa > 0.0) || !std::isfinite(ca_fa))
      throw InputError(fmt::format("{}: the coarse/fine volume ratio must be positive and finite",
                                   option_given("--ca-fa", fmt::format("{:g}", ca_fa), q.named)));
    // The blend by volume at the union of both sets of sieves (both on the standard series
    // already, so a nominal sieve appears once).
    std::vector<Sieve> openings = main.sieves;
    for (const Sieve& s : d.fine->sieves)
      if (std::none_of(openings.begin(), openings.end(), [&](const Sieve& o) { return o.opening == s.opening; }))
        openings.push_back(s);
    std::vector<Sieve> blend;
    for (const Sieve& s : openings) {
      const double p = (ca_fa * percent_passing_at(main, s.opening) + percent_passing_at(*d.fine, s.opening)) /
                       (1.0 + ca_fa);
      blend.push_back({s.name, s.opening, p});
    }
    d.ca_fa = ca_fa;
    d.mix = make_grading(fmt::format("{} + {} at Ca/Fa {:g}", main.name, d.fine->name, ca_fa), blend, "mix", {});
  }
  const Grading& checked = d.checked();
  if (q.d_min || q.d_max) d.cut = cut_grading(checked, q.d_min, q.d_max, named("--d-min") + "/" + named("--d-max"));
  if (q.band) {
    d.band = named_band(*q.band);
    if (!d.band)
      throw InputError(fmt::format("{}: unknown band; shipped bands: {}", option_given("--band", *q.band, q.named),
                                   fmt::join(named_band_names(), ", ")));
    d.band_check = check_against_band(checked, *d.band);
  }
  if (q.shape) d.shape = grading_shape(*q.shape, main, q);
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
  if (d.shape) j["shape"] = shape_json(*d.shape);
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
  if (d.shape) out += format_shape(*d.shape);
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
