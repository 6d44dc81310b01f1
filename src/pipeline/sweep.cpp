#include "aggpack/pipeline/sweep.hpp"

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

  nlohmann::json points = nlohmann::json::array();
  // The header is the first line, as in every CSV aggpack writes; the provenance is in sweep.json.
  std::string csv =
      "fa_percent,ca_fa,seeds,density_mean,density_sd,density_after_deposition_mean,density_after_deposition_sd\n";
  PlotSeries ours{"aggpack (mean ± sd over seeds)", {}, {}, {}, Mark::LineAndPoints, false, "#1f77b4"};
  std::size_t best = 0;
  bool has_dynamics = false;
  for (std::size_t p = 0; p < options.fa_percent.size(); ++p) {
    const double fa = options.fa_percent[p], ca_fa = (100.0 - fa) / fa;
    std::vector<std::string> sets = options.sets;
    sets.push_back(fmt::format("particles.ca_fa={:.17g}", ca_fa));
    sets.push_back("output.formats=[]");
    std::vector<double> final_density, deposited;
    for (int s = 1; s <= options.seeds; ++s) {
      const CaseRun r = campaign.run(fmt::format("Fa {:g} %", fa), options.scenario, sets, static_cast<std::uint64_t>(s),
                                     options.out / fmt::format("fa_{:g}", fa) / fmt::format("seed_{}", s),
                                     options.stop_after);
      final_density.push_back(r.final_density());
      deposited.push_back(r.after_deposition);
      has_dynamics = has_dynamics || !std::isnan(r.after_dynamics);
    }
    const SeedStatistics f = seed_statistics(final_density), d = seed_statistics(deposited);
    const auto or_null = [](double v) { return std::isnan(v) ? nlohmann::json() : nlohmann::json(v); };
    points.push_back({{"fa_percent", fa}, {"ca_fa", ca_fa}, {"density", {{"mean", f.mean}, {"sd", or_null(f.sd)}, {"values", final_density}}},
                      {"density_after_deposition", {{"mean", or_null(d.mean)}, {"sd", or_null(d.sd)}}}});
    csv += fmt::format("{:g},{:.6g},{},{:.6f},{},{},{}\n", fa, ca_fa, options.seeds, f.mean,
                       std::isnan(f.sd) ? "" : fmt::format("{:.6f}", f.sd),
                       std::isnan(d.mean) ? "" : fmt::format("{:.6f}", d.mean),
                       std::isnan(d.sd) ? "" : fmt::format("{:.6f}", d.sd));
    ours.x.push_back(fa);
    ours.y.push_back(f.mean);
    ours.y_error.push_back(std::isnan(f.sd) ? 0.0 : f.sd);
    if (f.mean > points[best]["density"]["mean"].get<double>()) best = p;
  }
  campaign.clear_progress();

  // Points whose mean is within one sd (of either) of the best are not told apart by these seeds.
  const auto& top = points[best]["density"];
  const double top_mean = top["mean"].get<double>(), top_sd = top["sd"].is_null() ? 0.0 : top["sd"].get<double>();
  nlohmann::json indistinguishable = nlohmann::json::array();
  for (const auto& p : points) {
    const double sd = p["density"]["sd"].is_null() ? 0.0 : p["density"]["sd"].get<double>();
    if (top_mean - p["density"]["mean"].get<double>() <= std::max(sd, top_sd)) indistinguishable.push_back(p["fa_percent"]);
  }
  nlohmann::json result;
  result["aggpack_version"] = kVersion;
  result["scenario_file"] = options.scenario.string();
  result["seeds"] = options.seeds;
  result["overrides"] = options.sets;
  result["density_after"] = has_dynamics ? "dynamics" : "deposition";
  result["points"] = points;
  result["best"] = {{"fa_percent", points[best]["fa_percent"]}, {"ca_fa", points[best]["ca_fa"]},
                    {"density_mean", top_mean}, {"density_sd", top["sd"]},
                    {"within_one_sd_fa_percent", indistinguishable}};
  result["wall_clock_s"] = campaign.seconds();

  Plot plot;
  plot.title = fmt::format("Density against sand fraction: {}", options.scenario.filename().string());
  plot.x_label = "fine aggregate Fa (% of aggregate volume)";
  plot.y_label = has_dynamics ? "packing density after DEM" : "packing density after deposition";
  plot.series.push_back(ours);
  plot.series.push_back({fmt::format("densest: Fa = {:g} %", points[best]["fa_percent"].get<double>()),
                         {points[best]["fa_percent"].get<double>()}, {top_mean}, {}, Mark::Points, false, "#d62728"});

  std::filesystem::create_directories(options.out);
  write_file_atomically(options.out / "sweep.csv", csv);
  write_file_atomically(options.out / "sweep.svg", svg_plot(plot));
  write_file_atomically(options.out / "sweep.json", result.dump(2) + "\n");
  if (!options.quiet) {
    fmt::print(log, "{:>6} {:>7} {:>16}\n", "Fa %", "Ca/Fa", "density");
    for (const auto& p : points)
      fmt::print(log, "{:>6g} {:>7.3f} {:>16}\n", p["fa_percent"].get<double>(), p["ca_fa"].get<double>(),
                 p["density"]["sd"].is_null()
                     ? fmt::format("{:.4f}", p["density"]["mean"].get<double>())
                     : fmt::format("{:.4f} ± {:.4f}", p["density"]["mean"].get<double>(), p["density"]["sd"].get<double>()));
    fmt::print(log, "densest blend: Fa = {:g} % (Ca/Fa = {:.3f}), density {:.4f}; within one sd of it: Fa = {} %\n",
               points[best]["fa_percent"].get<double>(), points[best]["ca_fa"].get<double>(), top_mean,
               fmt::format("{}", indistinguishable.dump()));
    fmt::print(log, "wrote {}\n", options.out.string());
  }
  return result;
}

}  // namespace aggpack
