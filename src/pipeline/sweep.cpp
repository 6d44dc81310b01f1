#include "aggpack/pipeline/sweep.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <iostream>

#include "aggpack/core/error.hpp"
#include "aggpack/core/version.hpp"
#include "aggpack/io/atomic_file.hpp"
#include "aggpack/io/scenario.hpp"
#include "aggpack/pipeline/campaign.hpp"
#include "aggpack/pipeline/whole_grading.hpp"
#include "aggpack/report/svg_plot.hpp"

namespace aggpack {

std::vector<double> parse_fa_points(const std::string& text) {
  const auto number = [&](const std::string& part) {
    std::size_t used = 0;
    double v = 0.0;
    try {
      v = std::stod(part, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != part.size() || !(v > 0.0 && v < 100.0))
      throw InputError(fmt::format("--fa {}: \"{}\" is not a percentage between 0 and 100 (exclusive)", text, part));
    return v;
  };
  std::vector<double> points;
  if (text.find(':') != std::string::npos) {
    const auto a = text.find(':'), b = text.find(':', a + 1);
    if (b == std::string::npos) throw InputError(fmt::format("--fa {}: expected FROM:TO:STEP, e.g. 25:45:5", text));
    const double from = number(text.substr(0, a)), to = number(text.substr(a + 1, b - a - 1));
    const double step = number(text.substr(b + 1));
    if (to < from) throw InputError(fmt::format("--fa {}: TO is below FROM", text));
    const auto n = static_cast<std::size_t>(std::floor((to - from) / step + 1e-9)) + 1;
    if (n > 200) throw InputError(fmt::format("--fa {}: {} points; at most 200", text, n));
    for (std::size_t k = 0; k < n; ++k) points.push_back(from + static_cast<double>(k) * step);
    return points;
  }
  std::size_t start = 0;
  while (true) {
    const auto comma = text.find(',', start);
    points.push_back(number(text.substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return points;
}

namespace {

// One fine fraction's runs, summarised.
struct SweepPoint {
  double fa_percent = 0.0, ca_fa = 0.0;
  std::vector<double> final_density;   // per seed, after the scenario's last stage (at the finest cut-off)
  SeedStatistics density, after_deposition;
  std::optional<WholeGradingEstimate> whole;  // with cut-offs
  // What the best blend is chosen by, and how far off it the point may be and not be told apart.
  [[nodiscard]] double judged() const { return whole ? whole->density : density.mean; }
  [[nodiscard]] double uncertainty() const {
    return whole ? 0.5 * (whole->high - whole->low) : (std::isnan(density.sd) ? 0.0 : density.sd);
  }
};

namespace fs = std::filesystem;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string or_empty(double v) { return std::isnan(v) ? std::string() : fmt::format("{:.6f}", v); }
nlohmann::json or_null(double v) { return std::isnan(v) ? nlohmann::json() : nlohmann::json(v); }
double or_zero(double v) { return std::isnan(v) ? 0.0 : v; }

std::string sweep_csv(const std::vector<SweepPoint>& points, int seeds, bool whole) {
  // The header is the first line, as in every CSV aggpack writes; the provenance is in sweep.json.
  std::string csv =
      "fa_percent,ca_fa,seeds,density_mean,density_sd,density_after_deposition_mean,density_after_deposition_sd";
  csv += whole ? ",whole_grading,whole_grading_low,whole_grading_high\n" : "\n";
  for (const SweepPoint& p : points) {
    csv += fmt::format("{:g},{:.6g},{},{:.6f},{},{},{}", p.fa_percent, p.ca_fa, seeds, p.density.mean,
                       or_empty(p.density.sd), or_empty(p.after_deposition.mean), or_empty(p.after_deposition.sd));
    csv += p.whole ? fmt::format(",{:.6f},{:.6f},{:.6f}\n", p.whole->density, p.whole->low, p.whole->high) : "\n";
  }
  return csv;
}

std::string sweep_svg(const std::vector<SweepPoint>& points, std::size_t best, bool has_dynamics,
                      const std::filesystem::path& scenario) {
  PlotSeries ours{"aggpack (mean ± sd over seeds)", {}, {}, {}, Mark::LineAndPoints, false, "#1f77b4"};
  for (const SweepPoint& p : points) {
    ours.x.push_back(p.fa_percent);
    ours.y.push_back(p.density.mean);
    ours.y_error.push_back(or_zero(p.density.sd));
  }
  Plot plot;
  plot.title = fmt::format("Density against sand fraction: {}", scenario.filename().string());
  plot.x_label = "fine aggregate Fa (% of aggregate volume)";
  plot.y_label = has_dynamics ? "packing density after DEM" : "packing density after deposition";
  if (points[best].whole) ours.label = "aggpack at the finest cut-off (mean ± sd over seeds)";
  plot.series.push_back(ours);
  if (points[best].whole) {
    PlotSeries whole{"whole grading: CPM carrying the cut-off series below it (band)", {}, {}, {}, Mark::LineAndPoints,
                     false, "#ff7f0e"};
    for (const SweepPoint& p : points)
      whole.x.push_back(p.fa_percent), whole.y.push_back(p.whole->density), whole.y_error.push_back(p.uncertainty());
    plot.series.push_back(whole);
  }
  plot.series.push_back({fmt::format("densest: Fa = {:g} %", points[best].fa_percent), {points[best].fa_percent},
                         {points[best].judged()}, {}, Mark::Points, false, "#d62728"});
  return svg_plot(plot);
}

}  // namespace

nlohmann::json sweep(const SweepOptions& options, std::ostream& log) {
  if (options.fa_percent.empty()) throw InputError("sweep: give the fine fractions with --fa (e.g. 25:45:5)");
  if (options.seeds < 1) throw InputError("sweep: --seeds must be at least 1");
  std::vector<double> cuts = options.cut_offs;
  std::sort(cuts.begin(), cuts.end(), std::greater<>());
  if (!cuts.empty() && cuts.size() < 3)
    throw InputError(fmt::format("--cut-offs: {} given; expected three or more (or none)", cuts.size()));
  if (std::adjacent_find(cuts.begin(), cuts.end()) != cuts.end()) throw InputError("--cut-offs: a cut-off is given twice");
  const bool whole = !cuts.empty();
  if (options.calibration && !whole) throw InputError("--calibration: it is used with --cut-offs only");
  const auto blend_sets = [&](double fa) {
    std::vector<std::string> sets = options.sets;
    sets.push_back(fmt::format("particles.ca_fa={:.17g}", (100.0 - fa) / fa));
    sets.push_back("output.formats=[]");
    return sets;
  };
  const auto cut_sets = [&](double fa, const std::string& key, double cut) {
    std::vector<std::string> sets = blend_sets(fa);
    if (!key.empty()) sets.push_back(fmt::format("{}={:.17g}", key, cut));
    return sets;
  };
  {
    ScenarioOverrides check;
    check.set = options.sets;
    const Scenario sc = load_scenario(options.scenario, check);
    if (!sc.particles.graded || !sc.particles.graded->fine)
      throw InputError(fmt::format("{}: [particles]: a sweep needs a coarse/fine mix (particles.coarse, "
                                   "particles.fine and particles.ca_fa)",
                                   options.scenario.string()));
  }
  // Every blend's scenario (at every cut-off) is read, and so checked, before any run.
  std::string key;
  ModelParameters parameters;
  std::vector<Scenario> blends;
  std::vector<std::vector<Scenario>> at_cuts;
  for (const double fa : options.fa_percent) {
    ScenarioOverrides o;
    o.set = blend_sets(fa);
    blends.push_back(load_scenario(options.scenario, o));
    const Scenario& sc = blends.back();
    if (!whole) continue;
    if (key.empty()) key = cut_off_key(*sc.particles.graded), parameters = whole_grading_parameters(sc, options.calibration);
    at_cuts.emplace_back();
    for (const double cut : cuts) {
      o.set = cut_sets(fa, key, cut);
      at_cuts.back().push_back(load_scenario(options.scenario, o));
    }
  }
  const std::vector<double> own_cut{kNaN};  // no cut-off series: the scenario's own
  const std::vector<double>& series = whole ? cuts : own_cut;
  Campaign campaign(options.threads, options.quiet, log,
                    options.fa_percent.size() * series.size() * static_cast<std::size_t>(options.seeds));
  std::vector<SweepPoint> points;
  bool has_dynamics = false;
  for (std::size_t b = 0; b < options.fa_percent.size(); ++b) {
    const double fa = options.fa_percent[b];
    SweepPoint point{fa, (100.0 - fa) / fa, {}, {}, {}, std::nullopt};
    std::vector<CutOffPoint> cut_points;
    std::vector<double> deposited;
    for (std::size_t c = 0; c < series.size(); ++c) {
      const fs::path blend_dir = options.out / fmt::format("fa_{:g}", fa);
      const fs::path dir = whole ? blend_dir / fmt::format("cut_{:g}mm", 1e3 * series[c]) : blend_dir;
      std::vector<double> final_density;
      std::size_t spheres = 0;
      deposited.clear();
      for (int s = 1; s <= options.seeds; ++s) {
        const std::string label = whole ? fmt::format("Fa {:g} %, cut {:.3g} mm", fa, 1e3 * series[c]) : fmt::format("Fa {:g} %", fa);
        const CaseRun r = campaign.run(label, options.scenario, whole ? cut_sets(fa, key, series[c]) : blend_sets(fa),
                                       static_cast<std::uint64_t>(s), dir / fmt::format("seed_{}", s), options.stop_after);
        final_density.push_back(r.final_density());
        deposited.push_back(r.after_deposition);
        if (s == 1) spheres = r.particle_count;
        has_dynamics = has_dynamics || !std::isnan(r.after_dynamics);
      }
      // The point's own densities are the finest cut-off's (the last), or the scenario's.
      point.final_density = final_density;
      if (whole) cut_points.push_back(cut_off_point(at_cuts[b][c], parameters, series[c], final_density, spheres));
    }
    point.density = seed_statistics(point.final_density);
    point.after_deposition = seed_statistics(deposited);
    if (whole) {
      point.whole = fit_whole_grading(blends[b], parameters, std::move(cut_points));
      point.whole->scenario = options.scenario.string();
    }
    points.push_back(std::move(point));
  }
  campaign.clear_progress();
  const auto best_it = std::max_element(points.begin(), points.end(),
                                        [](const SweepPoint& a, const SweepPoint& b) { return a.judged() < b.judged(); });
  const std::size_t best = static_cast<std::size_t>(best_it - points.begin());
  const SweepPoint& top = points[best];
  // Points within one sd over seeds (with cut-offs: half a band) of the best, by either's
  // uncertainty, are not told apart by these runs.
  std::vector<double> indistinguishable;
  for (const SweepPoint& p : points)
    if (top.judged() - p.judged() <= std::max(p.uncertainty(), top.uncertainty())) indistinguishable.push_back(p.fa_percent);

  nlohmann::json result;
  result["aggpack_version"] = kVersion;
  result["scenario_file"] = options.scenario.string();
  result["seeds"] = options.seeds;
  result["overrides"] = options.sets;
  result["density_after"] = has_dynamics ? "dynamics" : "deposition";
  result["points"] = nlohmann::json::array();
  for (const SweepPoint& p : points) {
    nlohmann::json point = {
        {"fa_percent", p.fa_percent},
        {"ca_fa", p.ca_fa},
        {"density", {{"mean", p.density.mean}, {"sd", or_null(p.density.sd)}, {"values", p.final_density}}},
        {"density_after_deposition", {{"mean", or_null(p.after_deposition.mean)}, {"sd", or_null(p.after_deposition.sd)}}}};
    if (p.whole) {
      nlohmann::json w = to_json(*p.whole);
      w.erase("aggpack_version");
      w.erase("scenario_file");
      point["whole_grading"] = w;
    }
    result["points"].push_back(point);
  }
  result["best"] = {{"fa_percent", top.fa_percent}, {"ca_fa", top.ca_fa}, {"density_mean", top.density.mean},
                    {"density_sd", or_null(top.density.sd)}, {"within_one_sd_fa_percent", indistinguishable},
                    {"chosen_by", whole ? "whole_grading" : "density"}};
  if (whole) {
    result["best"]["whole_grading"] = {{"density", top.whole->density},
                                       {"band", {top.whole->low, top.whole->high}},
                                       {"trustworthy", top.whole->trustworthy()}};
    result["cut_offs"] = {{"key", key}, {"values_m", cuts}};
    result["models"] = {{"cpm_compaction_index", parameters.compaction_index},
                        {"cpm_compaction_index_source", parameters.compaction_source},
                        {"cpm_residual_packing_density", parameters.beta},
                        {"cpm_residual_packing_density_source", parameters.beta_source}};
    result["notes"] = {fmt::format(
        "each blend simulated at the cut-offs {} of {}; its whole grading is modelled below them by CPM (K {:g}, "
        "beta {:g}); density_mean is at the finest cut-off; the best blend is the one of the densest whole grading",
        nlohmann::json(cuts).dump(), key, parameters.compaction_index, parameters.beta)};
  }
  result["wall_clock_s"] = campaign.seconds();

  std::filesystem::create_directories(options.out);
  for (const SweepPoint& p : points)
    if (p.whole)
      write_file_atomically(options.out / fmt::format("fa_{:g}", p.fa_percent) / "whole_grading.svg",
                            whole_grading_svg(*p.whole, std::nullopt,
                                              fmt::format("Fa = {:g} %: the whole grading from its cut-offs", p.fa_percent)));
  write_file_atomically(options.out / "sweep.csv", sweep_csv(points, options.seeds, whole));
  write_file_atomically(options.out / "sweep.svg", sweep_svg(points, best, has_dynamics, options.scenario));
  write_file_atomically(options.out / "sweep.json", result.dump(2) + "\n");
  if (!options.quiet) {
    fmt::print(log, "{:>6} {:>7} {:>16}{}\n", "Fa %", "Ca/Fa", whole ? "finest cut-off" : "density",
               whole ? fmt::format(" {:>28}", "whole grading (band)") : "");
    for (const SweepPoint& p : points)
      fmt::print(log, "{:>6g} {:>7.3f} {:>16}{}\n", p.fa_percent, p.ca_fa,
                 std::isnan(p.density.sd) ? fmt::format("{:.4f}", p.density.mean)
                                          : fmt::format("{:.4f} ± {:.4f}", p.density.mean, p.density.sd),
                 p.whole ? fmt::format(" {:>9.4f} ({:.4f} to {:.4f}){}", p.whole->density, p.whole->low, p.whole->high,
                                       p.whole->trustworthy() ? "" : " wide")
                         : "");
    fmt::print(log, "densest blend{}: Fa = {:g} % (Ca/Fa = {:.3f}), density {:.4f}; within {} of it: Fa = {} %\n",
               whole ? " (whole grading)" : "", top.fa_percent, top.ca_fa, top.judged(),
               whole ? "half a band" : "one sd", nlohmann::json(indistinguishable).dump());
    if (whole && !top.whole->trustworthy())
      fmt::print(log, "warning: the densest blend's whole-grading band is {:.3f} wide (more than 0.04): the cut-offs "
                      "leave too much out, or their densities scatter too much, to rank the blends; simulate finer "
                      "cut-offs, or more seeds\n",
                 top.whole->high - top.whole->low);
    fmt::print(log, "wrote {}\n", options.out.string());
  }
  return result;
}

}  // namespace aggpack
