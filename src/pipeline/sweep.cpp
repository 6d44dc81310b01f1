#include "aggpack/pipeline/sweep.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <iostream>

#include "aggpack/core/error.hpp"
#include "aggpack/core/version.hpp"
#include "aggpack/io/atomic_file.hpp"
#include "aggpack/pipeline/campaign.hpp"
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
  std::vector<double> final_density;   // per seed, after the scenario's last stage
  SeedStatistics density, after_deposition;
};

std::string or_empty(double v) { return std::isnan(v) ? std::string() : fmt::format("{:.6f}", v); }
nlohmann::json or_null(double v) { return std::isnan(v) ? nlohmann::json() : nlohmann::json(v); }
double or_zero(double v) { return std::isnan(v) ? 0.0 : v; }

std::string sweep_csv(const std::vector<SweepPoint>& points, int seeds) {
  // The header is the first line, as in every CSV aggpack writes; the provenance is in sweep.json.
  std::string csv =
      "fa_percent,ca_fa,seeds,density_mean,density_sd,density_after_deposition_mean,density_after_deposition_sd\n";
  for (const SweepPoint& p : points)
    csv += fmt::format("{:g},{:.6g},{},{:.6f},{},{},{}\n", p.fa_percent, p.ca_fa, seeds, p.density.mean,
                       or_empty(p.density.sd), or_empty(p.after_deposition.mean), or_empty(p.after_deposition.sd));
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
  plot.series.push_back(ours);
  plot.series.push_back({fmt::format("densest: Fa = {:g} %", points[best].fa_percent), {points[best].fa_percent},
                         {points[best].density.mean}, {}, Mark::Points, false, "#d62728"});
  return svg_plot(plot);
}

}  // namespace

nlohmann::json sweep(const SweepOptions& options, std::ostream& log) {
  if (options.fa_percent.empty()) throw InputError("sweep: give the fine fractions with --fa (e.g. 25:45:5)");
  if (options.seeds < 1) throw InputError("sweep: --seeds must be at least 1");
  {
    ScenarioOverrides check;
    check.set = options.sets;
    const Scenario sc = load_scenario(options.scenario, check);
    if (!sc.particles.graded || !sc.particles.graded->fine)
      throw InputError(fmt::format("{}: [particles]: a sweep needs a coarse/fine mix (particles.coarse, "
                                   "particles.fine and particles.ca_fa)",
                                   options.scenario.string()));
  }
  Campaign campaign(options.threads, options.quiet, log, options.fa_percent.size() * static_cast<std::size_t>(options.seeds));
  std::vector<SweepPoint> points;
  bool has_dynamics = false;
  for (const double fa : options.fa_percent) {
    SweepPoint point{fa, (100.0 - fa) / fa, {}, {}, {}};
    std::vector<std::string> sets = options.sets;
    sets.push_back(fmt::format("particles.ca_fa={:.17g}", point.ca_fa));
    sets.push_back("output.formats=[]");
    std::vector<double> deposited;
    for (int s = 1; s <= options.seeds; ++s) {
      const CaseRun r = campaign.run(fmt::format("Fa {:g} %", fa), options.scenario, sets, static_cast<std::uint64_t>(s),
                                     options.out / fmt::format("fa_{:g}", fa) / fmt::format("seed_{}", s),
                                     options.stop_after);
      point.final_density.push_back(r.final_density());
      deposited.push_back(r.after_deposition);
      has_dynamics = has_dynamics || !std::isnan(r.after_dynamics);
    }
    point.density = seed_statistics(point.final_density);
    point.after_deposition = seed_statistics(deposited);
    points.push_back(std::move(point));
  }
  campaign.clear_progress();
  const auto best_it = std::max_element(points.begin(), points.end(), [](const SweepPoint& a, const SweepPoint& b) {
    return a.density.mean < b.density.mean;
  });
  const std::size_t best = static_cast<std::size_t>(best_it - points.begin());
  const SweepPoint& top = points[best];
  // Points whose mean is within one sd (of either) of the best are not told apart by these seeds.
  std::vector<double> indistinguishable;
  for (const SweepPoint& p : points)
    if (top.density.mean - p.density.mean <= std::max(or_zero(p.density.sd), or_zero(top.density.sd)))
      indistinguishable.push_back(p.fa_percent);

  nlohmann::json result;
  result["aggpack_version"] = kVersion;
  result["scenario_file"] = options.scenario.string();
  result["seeds"] = options.seeds;
  result["overrides"] = options.sets;
  result["density_after"] = has_dynamics ? "dynamics" : "deposition";
  result["points"] = nlohmann::json::array();
  for (const SweepPoint& p : points)
    result["points"].push_back(
        {{"fa_percent", p.fa_percent},
         {"ca_fa", p.ca_fa},
         {"density", {{"mean", p.density.mean}, {"sd", or_null(p.density.sd)}, {"values", p.final_density}}},
         {"density_after_deposition", {{"mean", or_null(p.after_deposition.mean)}, {"sd", or_null(p.after_deposition.sd)}}}});
  result["best"] = {{"fa_percent", top.fa_percent}, {"ca_fa", top.ca_fa}, {"density_mean", top.density.mean},
                    {"density_sd", or_null(top.density.sd)}, {"within_one_sd_fa_percent", indistinguishable}};
  result["wall_clock_s"] = campaign.seconds();

  std::filesystem::create_directories(options.out);
  write_file_atomically(options.out / "sweep.csv", sweep_csv(points, options.seeds));
  write_file_atomically(options.out / "sweep.svg", sweep_svg(points, best, has_dynamics, options.scenario));
  write_file_atomically(options.out / "sweep.json", result.dump(2) + "\n");
  if (!options.quiet) {
    fmt::print(log, "{:>6} {:>7} {:>16}\n", "Fa %", "Ca/Fa", "density");
    for (const SweepPoint& p : points)
      fmt::print(log, "{:>6g} {:>7.3f} {:>16}\n", p.fa_percent, p.ca_fa,
                 std::isnan(p.density.sd) ? fmt::format("{:.4f}", p.density.mean)
                                          : fmt::format("{:.4f} ± {:.4f}", p.density.mean, p.density.sd));
    fmt::print(log, "densest blend: Fa = {:g} % (Ca/Fa = {:.3f}), density {:.4f}; within one sd of it: Fa = {} %\n",
               top.fa_percent, top.ca_fa, top.density.mean, nlohmann::json(indistinguishable).dump());
    fmt::print(log, "wrote {}\n", options.out.string());
  }
  return result;
}

}  // namespace aggpack
