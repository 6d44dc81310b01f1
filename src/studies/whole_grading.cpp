#include "aggpack/studies/whole_grading.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <fmt/ranges.h>

#include "aggpack/analysis/bulk_density.hpp"
#include "aggpack/core/error.hpp"
#include "aggpack/core/units.hpp"
#include "aggpack/core/version.hpp"
#include "aggpack/studies/calibration.hpp"
#include "aggpack/studies/campaign.hpp"
#include "aggpack/run/protocol.hpp"
#include "aggpack/run/run.hpp"
#include "aggpack/report/svg_plot.hpp"

namespace aggpack {

LineFit fit_line(const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& y_error) {
  const std::size_t n = x.size();
  if (n < 2 || y.size() != n || (!y_error.empty() && y_error.size() != n))
    throw InputError("a line needs two points or more");
  double mx = 0.0, my = 0.0;
  for (std::size_t k = 0; k < n; ++k) mx += x[k] / static_cast<double>(n), my += y[k] / static_cast<double>(n);
  double sxx = 0.0, sxy = 0.0;
  for (std::size_t k = 0; k < n; ++k) sxx += (x[k] - mx) * (x[k] - mx), sxy += (x[k] - mx) * (y[k] - my);
  if (!(sxx > 0.0)) throw InputError("a line through points of one abscissa is not defined");
  LineFit f;
  f.slope = sxy / sxx;
  f.intercept = my - f.slope * mx;
  double variance = 0.0;
  if (n > 2) {
    double ss = 0.0;
    for (std::size_t k = 0; k < n; ++k) {
      const double e = y[k] - (f.intercept + f.slope * x[k]);
      ss += e * e;
    }
    variance += ss / static_cast<double>(n - 2) * (1.0 / static_cast<double>(n) + mx * mx / sxx);
  }
  // intercept = sum_k c_k y_k with c_k = 1/n - mx (x_k - mx) / sxx.
  for (std::size_t k = 0; k < y_error.size(); ++k) {
    const double c = 1.0 / static_cast<double>(n) - mx * (x[k] - mx) / sxx;
    variance += c * c * y_error[k] * y_error[k];
  }
  f.intercept_standard_error = std::sqrt(variance);
  return f;
}

double left_out_fraction(const GradedParticles& g) {
  const auto removed = [](const GradingSource& s) {
    const GradingCut c = cut_grading(s.grading, s.d_min, s.d_max, s.key);
    return c.cut_below + c.cut_above;
  };
  if (!g.fine) return removed(g.main);
  const double coarse = g.ca_fa / (1.0 + g.ca_fa);
  return coarse * removed(g.main) + (1.0 - coarse) * removed(*g.fine);
}

std::string cut_off_key(const GradedParticles& g) { return (g.fine ? g.fine->key : g.main.key) + ".d_min"; }

void check_cut_offs(const GradedParticles& g, std::span<const double> cuts, std::span<const std::string> texts) {
  const GradingSource& finest = g.fine ? *g.fine : g.main;
  const Sieve& smallest = finest.grading.sieves.front();
  const std::string sieve = smallest.name.empty() ? fmt::format("{:.4g} mm", 1e3 * smallest.opening)
                                                  : fmt::format("{}, {:.4g} mm", smallest.name, 1e3 * smallest.opening);
  std::vector<std::string> below;
  for (std::size_t k = 0; k < cuts.size(); ++k) {
    const double cut = cuts[k];
    if (!(cut > 0.0) || cut > smallest.opening) continue;  // a cut-off of 0 or less: the scenario refuses it
    below.push_back(texts.size() == cuts.size() ? fmt::format("{} ({:.4g} mm)", texts[k], 1e3 * cut)
                                                : fmt::format("{:.4g} mm ({:.4g} in)", 1e3 * cut, cut / 0.0254));
  }
  if (!below.empty())
    throw InputError(fmt::format(
        "--cut-offs: {} {} at or below the smallest sieve of {}'s grading '{}' ({}): such a cut-off leaves nothing "
        "out, so every one of them would simulate the same bed; expected cut-offs above {:.4g} mm, each leaving a "
        "different part of the grading out",
        fmt::join(below, ", "), below.size() == 1 ? "is" : "are", finest.key, finest.grading.name, sieve,
        1e3 * smallest.opening));
}

std::string cut_off_assignment(const std::string& key, double cut) { return fmt::format("{}={:.17g}", key, cut); }

ScenarioOverrides with_cut_off(ScenarioOverrides base, const std::string& key, double cut,
                               const std::vector<double>& cut_offs, const std::vector<std::string>& texts) {
  const std::string assignment = cut_off_assignment(key, cut);
  const auto at = std::find(cut_offs.begin(), cut_offs.end(), cut);
  const auto k = static_cast<std::size_t>(at - cut_offs.begin());
  base.typed_as[assignment] = texts.size() == cut_offs.size() && at != cut_offs.end()
                                   ? "--cut-offs " + texts[k]
                                   : fmt::format("--cut-offs {:g} m", cut);
  base.set.push_back(assignment);
  return base;
}

ModelParameters whole_grading_parameters(const Scenario& whole, const std::optional<std::filesystem::path>& calibration) {
  if (calibration) return read_calibration(*calibration);
  if (whole.models_calibration) return read_calibration(*whole.models_calibration);
  return default_model_parameters(protocol_taps(scenario_protocol(whole)));
}

CutOffPoint cut_off_point(const Scenario& at_cut, const ModelParameters& parameters, double cut_off,
                          std::vector<double> density, std::size_t spheres) {
  CutOffPoint p;
  p.cut_off = cut_off;
  p.left_out = left_out_fraction(*at_cut.particles.graded);
  p.cpm = predict_scenario(at_cut, parameters).distributions.front().cpm.density;
  p.spheres = spheres;
  p.density = std::move(density);
  const SeedStatistics stats = seed_statistics(p.density);
  p.mean = stats.mean;
  p.standard_error = stats.count > 1 ? stats.sd / std::sqrt(static_cast<double>(stats.count)) : 0.0;
  return p;
}

WholeGradingEstimate fit_whole_grading(const Scenario& whole, const ModelParameters& parameters,
                                       std::vector<CutOffPoint> points) {
  if (points.size() < 3)
    throw InputError(fmt::format("a whole-grading fit needs three cut-offs or more; {} given", points.size()));
  std::sort(points.begin(), points.end(), [](const CutOffPoint& a, const CutOffPoint& b) { return a.cut_off > b.cut_off; });
  WholeGradingEstimate e;
  e.scenario = whole.file.string();
  e.key = cut_off_key(*whole.particles.graded);
  e.parameters = parameters;
  e.particle_density = grains_density(whole);
  e.points = std::move(points);
  std::vector<double> x, y, y_error;
  for (const CutOffPoint& p : e.points)
    x.push_back(p.left_out), y.push_back(p.residual()), y_error.push_back(p.standard_error);
  const LineFit fit = fit_line(x, y, y_error);
  e.residual_at_zero = fit.intercept;
  e.residual_slope = fit.slope;
  e.residual_standard_error = fit.intercept_standard_error;
  e.cpm_whole = predict_scenario(whole, parameters).distributions.back().cpm.density;
  e.density = e.cpm_whole + e.residual_at_zero;
  e.low = e.density - 2.0 * e.residual_standard_error;
  e.high = e.density + 2.0 * e.residual_standard_error;
  e.simulated_fraction = 1.0 - e.points.back().left_out;
  return e;
}

WholeGradingEstimate estimate_whole_grading(const WholeGradingOptions& options, std::ostream& log) {
  if (options.cut_offs.size() < 3)
    throw InputError(fmt::format("--cut-offs: {} given; expected three or more (the line through the residuals needs a "
                                 "scatter to say how far it can be trusted)",
                                 options.cut_offs.size()));
  if (options.seeds < 1 || options.seeds > 100)
    throw InputError(fmt::format("--seeds {}: expected 1 to 100", options.seeds));
  const Scenario whole = load_scenario(options.scenario, options.overrides);
  if (!whole.particles.graded)
    throw InputError(fmt::format("{}: its particles are not sampled from a grading: there is no cut-off to carry to "
                                 "the whole grading",
                                 whole.file.string()));
  const std::string key = cut_off_key(*whole.particles.graded);
  check_cut_offs(*whole.particles.graded, options.cut_offs, options.cut_off_texts);
  const ModelParameters parameters = whole_grading_parameters(whole, options.calibration);

  // Every cut-off's scenario is read (and so checked) before any simulation.
  std::vector<double> cuts = options.cut_offs;
  std::sort(cuts.begin(), cuts.end(), std::greater<>());
  if (std::adjacent_find(cuts.begin(), cuts.end()) != cuts.end())
    throw InputError("--cut-offs: a cut-off is given twice");
  std::vector<Scenario> scenarios;
  for (const double cut : cuts)
    scenarios.push_back(load_scenario(
        options.scenario, with_cut_off(options.overrides, key, cut, options.cut_offs, options.cut_off_texts)));
  Campaign campaign(options.threads, options.quiet, log, cuts.size() * static_cast<std::size_t>(options.seeds));
  std::vector<CutOffPoint> points;
  for (std::size_t k = 0; k < cuts.size(); ++k) {
    std::vector<double> density;
    std::size_t spheres = 0;
    const std::string at_cut = fmt::format("{} = {}", key, length_text(cuts[k], scenarios[k].written_length_unit));
    for (int seed = 1; seed <= options.seeds; ++seed) {
      const CaseRun c = campaign.run(at_cut, scenarios[k], static_cast<std::uint64_t>(seed), [&](const CaseRun& r) {
        return fmt::format("  whole-grading: {}, seed {}: {} spheres, density {:.4f}", at_cut, seed,
                           r.result.report.particles.size(), r.result.report.final.density.mean);
      });
      if (seed == 1) spheres = c.result.report.particles.size();
      density.push_back(c.result.report.final.density.mean);
    }
    points.push_back(cut_off_point(scenarios[k], parameters, cuts[k], std::move(density), spheres));
  }
  campaign.clear_progress();
  return fit_whole_grading(whole, parameters, std::move(points));
}

nlohmann::json to_json(const WholeGradingEstimate& e) {
  nlohmann::json points = nlohmann::json::array();
  for (const CutOffPoint& p : e.points)
    points.push_back({{"cut_off_m", p.cut_off},
                      {"left_out_volume_fraction", p.left_out},
                      {"spheres", p.spheres},
                      {"density_per_seed", p.density},
                      {"mean", p.mean},
                      {"standard_error", p.standard_error},
                      {"cpm", p.cpm},
                      {"residual", p.residual()}});
  return {{"aggpack_version", kVersion},
          {"scenario_file", e.scenario},
          {"cut_off_key", e.key},
          {"parameters",
           {{"cpm_compaction_index", e.parameters.compaction_index},
            {"cpm_compaction_index_source", e.parameters.compaction_source},
            {"cpm_residual_packing_density", e.parameters.beta},
            {"cpm_residual_packing_density_source", e.parameters.beta_source}}},
          {"cut_offs", points},
          {"residual_fit", {{"at_nothing_left_out", e.residual_at_zero},
                            {"slope", e.residual_slope},
                            {"standard_error", e.residual_standard_error}}},
          {"whole_grading",
           {{"cpm", e.cpm_whole},
            {"density", e.density},
            {"band", {e.low, e.high}},
            {"voids_content_percent", bulk_density(e.density, e.particle_density).voids_percent},
            {"bulk_density_kg_m3", bulk_density(e.density, e.particle_density).kg_per_m3},
            {"bulk_density_lb_ft3", bulk_density(e.density, e.particle_density).lb_per_ft3},
            {"bulk_density_band_kg_m3",
             {bulk_density(e.low, e.particle_density).kg_per_m3, bulk_density(e.high, e.particle_density).kg_per_m3}},
            {"particle_density_kg_m3", e.particle_density},
            {"simulated_volume_fraction", e.simulated_fraction},
            {"modelled_volume_fraction", 1.0 - e.simulated_fraction},
            {"trustworthy", e.trustworthy()}}}};
}

std::string describe(const WholeGradingEstimate& e) {
  fmt::memory_buffer out;
  auto o = std::back_inserter(out);
  fmt::format_to(o, "aggpack {}: the whole grading of {} from cut-offs of {} (CPM K {:g}, beta {:g})\n", kVersion,
                 e.scenario, e.key, e.parameters.compaction_index, e.parameters.beta);
  for (const CutOffPoint& p : e.points)
    fmt::format_to(o, "  cut-off {:.4g} mm ({:.1f} % of the grading left out, {} spheres): simulated {:.4f} ± {:.4f}, "
                      "CPM {:.4f}, residual {:+.4f}\n",
                   1e3 * p.cut_off, 100.0 * p.left_out, p.spheres, p.mean, p.standard_error, p.cpm, p.residual());
  fmt::format_to(o, "  residual at nothing left out {:+.4f} ± {:.4f} (a line in the fraction left out)\n",
                 e.residual_at_zero, e.residual_standard_error);
  fmt::format_to(o,
                 "  whole grading: {:.4f} (band {:.4f} to {:.4f}) = CPM {:.4f} {:+.4f}; simulated: the {:.1f} % of the "
                 "volume above the finest cut, modelled: the {:.1f} % below it\n",
                 e.density, e.low, e.high, e.cpm_whole, e.residual_at_zero, 100.0 * e.simulated_fraction,
                 100.0 * (1.0 - e.simulated_fraction));
  fmt::format_to(o, "  whole grading: {} (particle density {:g} kg/m3)\n", describe(bulk_density(e.density, e.particle_density)),
                 e.particle_density);
  if (!e.trustworthy())
    fmt::format_to(o, "  warning: the band is {:.3f} wide: the cut-offs leave too much of the grading out (or their "
                      "densities scatter too much) to carry the simulation to the whole grading; simulate finer "
                      "cut-offs, or more seeds\n",
                   e.high - e.low);
  return fmt::to_string(out);
}

std::string whole_grading_svg(const WholeGradingEstimate& e, std::optional<double> measured, const std::string& title) {
  return svg_plot(whole_grading_plot(e, measured, title));
}

Plot whole_grading_plot(const WholeGradingEstimate& e, std::optional<double> measured, const std::string& title) {
  PlotSeries simulated{"simulated (mean ± se over seeds)", {}, {}, {}, Mark::Points, false, "#1f77b4"};
  PlotSeries cpm{"CPM on the simulated distribution", {}, {}, {}, Mark::LineAndPoints, true, "#7f7f7f"};
  PlotSeries fitted{"CPM + the fitted residual line, to the whole grading", {}, {}, {}, Mark::Line, false, "#ff7f0e"};
  // Finest cut first, so that the lines run left to right from the whole grading.
  for (auto it = e.points.rbegin(); it != e.points.rend(); ++it) {
    const CutOffPoint& p = *it;
    const double x = 100.0 * p.left_out;
    simulated.x.push_back(x), simulated.y.push_back(p.mean), simulated.y_error.push_back(p.standard_error);
    cpm.x.push_back(x), cpm.y.push_back(p.cpm);
    fitted.x.push_back(x), fitted.y.push_back(p.cpm + e.residual_at_zero + e.residual_slope * p.left_out);
  }
  // Nothing left out: the model's whole grading and the estimate, the end of the fitted line.
  cpm.x.insert(cpm.x.begin(), 0.0), cpm.y.insert(cpm.y.begin(), e.cpm_whole);
  fitted.x.insert(fitted.x.begin(), 0.0), fitted.y.insert(fitted.y.begin(), e.density);
  Plot plot;
  plot.title = title.empty() ? fmt::format("The whole grading from cut-offs of {}", e.key) : title;
  plot.x_label = "volume of the grading left out by the cut-offs (%)";
  plot.y_label = "packing density";
  plot.x_column = "left_out_volume_percent";
  plot.y_column = "packing_density";
  plot.legend_at_bottom = true;
  plot.series = {cpm, fitted, simulated,
                 {fmt::format("whole grading: {:.3f} (band {:.3f} to {:.3f})", e.density, e.low, e.high),
                  {0.0},
                  {e.density},
                  {0.5 * (e.high - e.low)},
                  Mark::Points,
                  false,
                  "#d62728"}};
  if (measured) plot.series.push_back({fmt::format("measured: {:.3f}", *measured), {0.0}, {*measured}, {}, Mark::Points, false, "#000000"});
  return plot;
}

}  // namespace aggpack
