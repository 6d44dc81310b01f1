#include "aggpack/studies/sweep.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <fmt/ranges.h>
#include <iostream>

#include "aggpack/analysis/bulk_density.hpp"
#include "aggpack/core/error.hpp"
#include "aggpack/core/version.hpp"
#include "aggpack/io/atomic_file.hpp"
#include "aggpack/io/scenario.hpp"
#include "aggpack/studies/campaign.hpp"
#include "aggpack/studies/whole_grading.hpp"
#include "aggpack/report/svg_plot.hpp"
#include "aggpack/sizes/grading_sampler.hpp"

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
  // Without cut-offs, what the scenario's own cut-offs leave out of the blend and of its sand
  // (volume fractions): the densities are of the rest only.
  double left_out = 0.0, fine_left_out = 0.0;
  double particle_density = 0.0;  // kg/m^3, of the blend's grains (several materials: by volume)
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
  plot.x_column = "fa_percent";
  plot.y_column = "packing_density";
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

namespace {

// What a sweep runs, read and checked before any run: each blend's scenario and, with cut-offs,
// its scenario at each cut-off.
struct SweepPlan {
  std::vector<double> cuts;  // m, coarsest first; empty: the scenario's own cut-off
  std::string key;           // the cut-off's key
  ModelParameters parameters;
  std::vector<Scenario> blends;
  std::vector<std::vector<Scenario>> at_cuts;  // [blend][cut]
  [[nodiscard]] bool whole() const { return !cuts.empty(); }
};

std::vector<std::string> blend_sets(const SweepOptions& options, double fa) {
  std::vector<std::string> sets = options.sets;
  sets.push_back(fmt::format("particles.ca_fa={:.17g}", (100.0 - fa) / fa));
  sets.push_back("output.formats=[]");
  return sets;
}

std::vector<std::string> cut_sets(const SweepOptions& options, double fa, const std::string& key, double cut) {
  std::vector<std::string> sets = blend_sets(options, fa);
  sets.push_back(cut_off_assignment(key, cut));
  return sets;
}

SweepPlan plan_sweep(const SweepOptions& options) {
  if (options.fa_percent.empty()) throw InputError("sweep: give the fine fractions with --fa (e.g. 25:45:5)");
  if (options.seeds < 1) throw InputError("sweep: --seeds must be at least 1");
  SweepPlan plan;
  plan.cuts = options.cut_offs;
  std::sort(plan.cuts.begin(), plan.cuts.end(), std::greater<>());
  if (!plan.cuts.empty() && plan.cuts.size() < 3)
    throw InputError(fmt::format("--cut-offs: {} given; expected three or more (or none)", plan.cuts.size()));
  if (std::adjacent_find(plan.cuts.begin(), plan.cuts.end()) != plan.cuts.end())
    throw InputError("--cut-offs: a cut-off is given twice");
  if (options.calibration && !plan.whole()) throw InputError("--calibration: it is used with --cut-offs only");
  {
    ScenarioOverrides check;
    check.set = options.sets;
    check.typed_as = options.typed_as;
    const Scenario sc = load_scenario(options.scenario, check);
    if (sc.output.frame_interval)  // its runs write no VTP files (output.formats=[])
      throw InputError(fmt::format("{}: output.frame_interval: a sweep writes no VTP files, so no frames; remove the "
                                   "key (aggpack run writes a blend's frames)",
                                   options.scenario.string()));
    if (!sc.particles.graded || !sc.particles.graded->fine)
      throw InputError(fmt::format("{}: [particles]: a sweep needs a coarse/fine mix (particles.coarse, "
                                   "particles.fine and particles.ca_fa)",
                                   options.scenario.string()));
    if (plan.whole()) {
      check_cut_offs(*sc.particles.graded, options.cut_offs, options.cut_off_texts);
      plan.key = cut_off_key(*sc.particles.graded), plan.parameters = whole_grading_parameters(sc, options.calibration);
    }
  }
  for (const double fa : options.fa_percent) {
    ScenarioOverrides o;
    o.set = blend_sets(options, fa);
    o.typed_as = options.typed_as;
    plan.blends.push_back(load_scenario(options.scenario, o));
    if (!plan.whole()) continue;
    plan.at_cuts.emplace_back();
    for (const double cut : plan.cuts) {
      // The assignments of cut_sets, which the runs take; these quote the cut as typed.
      const ScenarioOverrides at_cut = with_cut_off(o, plan.key, cut, options.cut_offs, options.cut_off_texts);
      plan.at_cuts.back().push_back(load_scenario(options.scenario, at_cut));
    }
  }
  return plan;
}

// One blend's series of runs over seeds 1..N: at a cut-off, or at the scenario's own.
struct BlendSeries {
  std::string label;
  std::vector<std::string> sets;
  fs::path folder;  // of the seeds' folders
  double cut = kNaN;
};

std::vector<BlendSeries> blend_series(const SweepOptions& options, const SweepPlan& plan, std::size_t blend) {
  const double fa = options.fa_percent[blend];
  const fs::path blend_dir = options.out / fmt::format("fa_{:g}", fa);
  if (!plan.whole()) return {{fmt::format("Fa {:g} %", fa), blend_sets(options, fa), blend_dir}};
  std::vector<BlendSeries> series;
  for (const double cut : plan.cuts)
    series.push_back({fmt::format("Fa {:g} %, cut {:.3g} mm", fa, 1e3 * cut), cut_sets(options, fa, plan.key, cut),
                      blend_dir / fmt::format("cut_{:g}mm", 1e3 * cut), cut});
  return series;
}

// Every run of the sweep checked as `aggpack check` would, before the first runs (its sizes
// made, its grains fitted): a blend that cannot run stops the sweep before hours of the others.
void check_runs(const SweepOptions& options, const SweepPlan& plan, std::size_t planned, std::ostream& log) {
  Campaign checks(options.threads, true, log, planned, Campaign::Checkpoints::removed, Campaign::Mode::check);
  for (std::size_t b = 0; b < options.fa_percent.size(); ++b)
    for (const BlendSeries& series : blend_series(options, plan, b))
      for (int s = 1; s <= options.seeds; ++s)
        (void)checks.run(series.label, options.scenario, series.sets, static_cast<std::uint64_t>(s),
                         series.folder / fmt::format("seed_{}", s), options.stop_after);
}

// One blend's runs: at each cut-off (or once, at the scenario's own) over seeds 1..N.
SweepPoint run_blend(const SweepOptions& options, const SweepPlan& plan, std::size_t blend, Campaign& campaign,
                     bool& has_dynamics) {
  const double fa = options.fa_percent[blend];
  SweepPoint point{fa, (100.0 - fa) / fa, {}, {}, {}, std::nullopt};
  point.particle_density = grains_density(plan.blends[blend]);
  std::vector<CutOffPoint> cut_points;
  std::vector<double> deposited;
  const std::vector<BlendSeries> series = blend_series(options, plan, blend);
  for (std::size_t c = 0; c < series.size(); ++c) {
    std::vector<double> final_density;
    std::size_t spheres = 0;
    deposited.clear();
    for (int s = 1; s <= options.seeds; ++s) {
      const CaseRun r = campaign.run(series[c].label, options.scenario, series[c].sets, static_cast<std::uint64_t>(s),
                                     series[c].folder / fmt::format("seed_{}", s), options.stop_after);
      final_density.push_back(r.final_density());
      deposited.push_back(r.after_deposition);
      if (s == 1) spheres = r.particle_count;
      has_dynamics = has_dynamics || !std::isnan(r.after_dynamics);
    }
    // The point's own densities are the finest cut-off's (the last), or the scenario's.
    point.final_density = final_density;
    if (plan.whole())
      cut_points.push_back(cut_off_point(plan.at_cuts[blend][c], plan.parameters, series[c].cut, final_density, spheres));
  }
  point.density = seed_statistics(point.final_density);
  point.after_deposition = seed_statistics(deposited);
  if (!plan.whole()) {
    const GradedParticles& graded = *plan.blends[blend].particles.graded;
    point.left_out = left_out_fraction(graded);
    const GradingCut fine = cut_grading(graded.fine->grading, graded.fine->d_min, graded.fine->d_max, graded.fine->key);
    point.fine_left_out = fine.cut_below + fine.cut_above;
  }
  if (plan.whole()) {
    point.whole = fit_whole_grading(plan.blends[blend], plan.parameters, std::move(cut_points));
    point.whole->scenario = options.scenario.string();
  }
  return point;
}

nlohmann::json sweep_json(const SweepOptions& options, const SweepPlan& plan, const std::vector<SweepPoint>& points,
                          std::size_t best, const std::vector<double>& indistinguishable, bool has_dynamics,
                          double seconds) {
  const SweepPoint& top = points[best];
  const double particle_density = top.particle_density;  // kg/m3, the densest blend's (bulk density, voids)
  nlohmann::json result;
  result["aggpack_version"] = kVersion;
  result["scenario_file"] = options.scenario.string();
  result["seeds"] = options.seeds;
  result["overrides"] = options.sets;
  result["density_after"] = has_dynamics ? "dynamics" : "deposition";
  result["points"] = nlohmann::json::array();
  for (const SweepPoint& p : points) {
    nlohmann::json point = {{"fa_percent", p.fa_percent},
                            {"ca_fa", p.ca_fa},
                            {"source", "simulated"},
                            {"density",
                             {{"mean", p.density.mean},
                              {"sd", or_null(p.density.sd)},
                              {"values", p.final_density},
                              {"voids_content_percent", bulk_density(p.density.mean, p.particle_density).voids_percent},
                              {"bulk_density_kg_m3", bulk_density(p.density.mean, p.particle_density).kg_per_m3},
                              {"bulk_density_lb_ft3", bulk_density(p.density.mean, p.particle_density).lb_per_ft3}}},
                            {"density_after_deposition",
                             {{"mean", or_null(p.after_deposition.mean)}, {"sd", or_null(p.after_deposition.sd)}}}};
    if (!p.whole) {
      point["left_out_volume_fraction"] = p.left_out;
      point["fine_left_out_volume_fraction"] = p.fine_left_out;
    }
    if (p.whole) {
      nlohmann::json w = to_json(*p.whole);
      w.erase("aggpack_version");
      w.erase("scenario_file");
      w["source"] = "predicted: CPM carrying the simulated cut-offs to the whole grading";
      point["whole_grading"] = w;
    }
    result["points"].push_back(point);
  }
  const BulkDensity best_bulk = bulk_density(top.judged(), particle_density);
  result["best"] = {{"fa_percent", top.fa_percent}, {"ca_fa", top.ca_fa}, {"density_mean", top.density.mean},
                    {"density_sd", or_null(top.density.sd)}, {"within_one_sd_fa_percent", indistinguishable},
                    {"chosen_by", plan.whole() ? "whole_grading" : "density"},
                    {"voids_content_percent", best_bulk.voids_percent},
                    {"bulk_density_kg_m3", best_bulk.kg_per_m3},
                    {"bulk_density_lb_ft3", best_bulk.lb_per_ft3},
                    {"particle_density_kg_m3", particle_density}};
  if (plan.whole()) {
    result["best"]["whole_grading"] = {{"density", top.whole->density},
                                       {"band", {top.whole->low, top.whole->high}},
                                       {"trustworthy", top.whole->trustworthy()}};
    result["cut_offs"] = {{"key", plan.key}, {"values_m", plan.cuts}};
    const ModelParameters& m = plan.parameters;
    result["models"] = {{"cpm_compaction_index", m.compaction_index},
                        {"cpm_compaction_index_source", m.compaction_source},
                        {"cpm_residual_packing_density", m.beta},
                        {"cpm_residual_packing_density_source", m.beta_source}};
    result["notes"] = {fmt::format(
        "each blend simulated at the cut-offs {} of {}; its whole grading is modelled below them by CPM (K {:g}, "
        "beta {:g}); density_mean is at the finest cut-off; the best blend is the one of the densest whole grading",
        nlohmann::json(plan.cuts).dump(), plan.key, m.compaction_index, m.beta)};
  } else if (top.fine_left_out > 0.0) {
    result["notes"] = {fmt::format(
        "each blend is simulated without what its scenario's cut-offs leave out ({:.0f} % of the sand's volume and "
        "{:.0f} % of the blend's at the densest blend, Fa = {:g} %): the densities are of the simulated part only; "
        "--cut-offs estimates each blend's whole grading",
        100.0 * top.fine_left_out, 100.0 * top.left_out, top.fa_percent)};
  }
  result["wall_clock_s"] = seconds;
  return result;
}

void print_sweep(std::ostream& log, const SweepOptions& options, const std::vector<SweepPoint>& points,
                 std::size_t best, const std::vector<double>& indistinguishable, double particle_density) {
  const SweepPoint& top = points[best];
  const bool whole = top.whole.has_value();
  fmt::print(log, "{:>6} {:>7} {:>16}{}\n", "Fa %", "Ca/Fa", whole ? "finest cut-off" : "density",
             whole ? fmt::format(" {:>28}", "whole grading (band)") : "");
  for (const SweepPoint& p : points)
    fmt::print(log, "{:>6g} {:>7.3f} {:>16}{}\n", p.fa_percent, p.ca_fa,
               std::isnan(p.density.sd) ? fmt::format("{:.4f}", p.density.mean)
                                        : fmt::format("{:.4f} ± {:.4f}", p.density.mean, p.density.sd),
               p.whole ? fmt::format(" {:>9.4f} ({:.4f} to {:.4f}){}", p.whole->density, p.whole->low, p.whole->high,
                                     p.whole->trustworthy() ? "" : " wide")
                       : "");
  // One seed has no spread: nothing is told apart from the best, and saying "within one sd" would
  // claim a comparison that was never made.
  const std::string told_apart =
      whole || options.seeds > 1
          ? fmt::format("; within {} of it: Fa = {} %", whole ? "half a band" : "one sd",
                        fmt::join(indistinguishable, ", "))
          : "; one seed: no spread to tell blends apart (run --seeds 3 or more)";
  fmt::print(log, "densest blend{}: Fa = {:g} % (Ca/Fa = {:.3f}), density {:.4f}{}\n", whole ? " (whole grading)" : "",
             top.fa_percent, top.ca_fa, top.judged(), told_apart);
  fmt::print(log, "densest blend: {} (particle density {:g} kg/m3)\n", describe(bulk_density(top.judged(), particle_density)),
             particle_density);
  if (!whole && top.fine_left_out > 0.0)
    fmt::print(log, "note: {:.0f} % of the sand's volume ({:.0f} % of this blend's) is outside the scenario's cut-offs "
                    "and was not simulated: these densities are of the simulated part only; --cut-offs estimates "
                    "each blend's whole grading\n",
               100.0 * top.fine_left_out, 100.0 * top.left_out);
  if (whole && !top.whole->trustworthy())
    fmt::print(log, "warning: the densest blend's whole-grading band is {:.3f} wide (more than 0.04): the cut-offs "
                    "leave too much out, or their densities scatter too much, to rank the blends; simulate finer "
                    "cut-offs, or more seeds\n",
               top.whole->high - top.whole->low);
  fmt::print(log, "wrote {}\n", options.out.string());
}

}  // namespace

nlohmann::json sweep(const SweepOptions& options, std::ostream& log) {
  const SweepPlan plan = plan_sweep(options);
  const std::size_t planned = options.fa_percent.size() * std::max<std::size_t>(plan.cuts.size(), 1) *
                              static_cast<std::size_t>(options.seeds);
  check_runs(options, plan, planned, log);
  Campaign campaign(options.threads, options.quiet, log, planned,
                    options.resume ? Campaign::Checkpoints::kept_and_resumed : Campaign::Checkpoints::kept);
  std::vector<SweepPoint> points;
  bool has_dynamics = false;
  for (std::size_t b = 0; b < options.fa_percent.size(); ++b)
    points.push_back(run_blend(options, plan, b, campaign, has_dynamics));
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
  nlohmann::json result = sweep_json(options, plan, points, best, indistinguishable, has_dynamics, campaign.seconds());
  result["resumed_runs"] = campaign.runs_resumed();  // continued from an interrupted sweep's checkpoints

  std::filesystem::create_directories(options.out);
  for (const SweepPoint& p : points)
    if (p.whole) {  // the figure, and its data beside it
      const Plot plot = whole_grading_plot(*p.whole, std::nullopt,
                                           fmt::format("Fa = {:g} %: the whole grading from its cut-offs", p.fa_percent));
      const std::filesystem::path folder = options.out / fmt::format("fa_{:g}", p.fa_percent);
      write_file_atomically(folder / "whole_grading.svg", svg_plot(plot));
      write_file_atomically(folder / "whole_grading.csv", plot_csv(plot));
    }
  write_file_atomically(options.out / "sweep.csv", sweep_csv(points, options.seeds, plan.whole()));
  write_file_atomically(options.out / "sweep.svg", sweep_svg(points, best, has_dynamics, options.scenario));
  write_file_atomically(options.out / "sweep.json", result.dump(2) + "\n");
  remove_checkpoints(campaign.kept_checkpoints());
  if (!options.quiet)
    print_sweep(log, options, points, best, indistinguishable, points[best].particle_density);
  return result;
}

}  // namespace aggpack
