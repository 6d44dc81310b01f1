// aggpack reproduce: Examples 1 and 2 made by four protocols (drop-and-roll, DEM, pour, tapping).
#include "reproduce_parts.hpp"

#include <algorithm>

#include <fmt/format.h>
#include <omp.h>

namespace aggpack::reproduction {

namespace {

// The compaction curves of the poured-and-tapped runs: density against tap number (0: as poured).
Plot compaction_plot(const PaperExample& ex, const std::vector<CaseRun>& runs, const std::string& tapping) {
  Plot plot;
  plot.title = fmt::format("{} poured, then tapped: the compaction curve", ex.short_name);
  plot.legend_at_bottom = true;
  plot.x_label = fmt::format("taps ({})", tapping);
  plot.y_label = "packing density in the virtual boxes";
  plot.x_column = "tap";
  plot.y_column = "packing_density";
  double taps = 1.0, lo = ex.experiment, hi = ex.experiment;
  for (const CaseRun& r : runs)
    for (const TapReport& t : r.result.report.tappings) {
      PlotSeries s;
      s.label = fmt::format("aggpack, seed {}", r.result.report.scenario.seed);
      s.mark = Mark::LineAndPoints;
      if (!std::isnan(t.density_before)) s.x.push_back(0.0), s.y.push_back(t.density_before);
      for (const TapSample& sample : t.samples)
        if (!std::isnan(sample.density)) s.x.push_back(static_cast<double>(sample.tap)), s.y.push_back(sample.density);
      for (const double y : s.y) lo = std::min(lo, y), hi = std::max(hi, y);
      taps = std::max(taps, static_cast<double>(t.taps));
      plot.series.push_back(std::move(s));
    }
  plot.series.push_back(reference_line(fmt::format("experiment {:.4f}", ex.experiment), 0, taps, ex.experiment, "#000000"));
  plot.x_range = {{0.0, taps}};
  plot.y_range = {{std::floor(lo * 100 - 0.5) / 100, std::ceil(hi * 100 + 0.5) / 100}};
  return plot;
}

// The mean over the runs of a wall time that `seconds` takes from each run's report.
template <class Seconds>
double mean_of(const std::vector<CaseRun>& runs, Seconds&& seconds) {
  double sum = 0.0;
  for (const CaseRun& r : runs) sum += seconds(r.result.report);
  return runs.empty() ? kNaN : sum / static_cast<double>(runs.size());
}

double deposition_s(const RunReport& r) { return r.deposition ? r.deposition->wall_clock_s : 0.0; }
double dynamics_s(const RunReport& r) { return r.dynamics ? r.dynamics->wall_clock_s() : 0.0; }
double tapping_s(const RunReport& r) {
  double s = 0.0;
  for (const TapReport& tap : r.tappings) s += tap.wall_clock_s;
  return s;
}

// "Until quiet" only where every run's DEM ended quiet; a DEM cut by its time limit says so.
std::string how_long(const std::vector<CaseRun>& runs) {
  std::size_t cut = 0;
  double longest = 0.0;
  for (const CaseRun& r : runs) {
    const std::optional<RunReport::RestState> rest = r.result.report.rest_state();
    if (rest && !rest->settled) ++cut;
    const auto& dynamics = r.result.report.scenario.dynamics;
    if (dynamics) longest = std::max(longest, dynamics->quiet.max_time);
  }
  return cut == 0 ? std::string("until quiet")
                  : fmt::format("cut at its time limit ({:g} s simulated) before quiet in {} of {} runs", longest, cut,
                                runs.size());
}

}  // namespace

// How the bed is made, for each example: drop-and-roll, with DEM, poured, poured and tapped,
// against the paper and the experiment, with the wall time per run.
void compose_protocols(Document& doc, FigureSet& figures, nlohmann::json& result, const Reproduction& rep) {
  if (rep.poured.empty()) return;
  auto& b = doc.blocks;
  b.emplace_back(Heading{2, "How the bed is made: four protocols for Examples 1 and 2"});
  Table t;
  t.header = {"case", "protocol", "density (mean ± sd over seeds)", "wall time per run, s", "ours − experiment"};
  for (const PaperExample& ex : rep.paper) {
    const auto found = rep.poured.find(ex.id);
    if (found == rep.poured.end()) continue;
    const SeedRuns& deposited = rep.examples.at(ex.id);
    const SeedRuns& poured = found->second;
    std::vector<double> pour_values;
    for (const CaseRun& r : poured.runs) {
      const auto a = r.result.report.analyses.find("pour");
      pour_values.push_back(a != r.result.report.analyses.end() ? a->second.report.density.mean : kNaN);
    }
    const SeedStatistics pour_only = seed_statistics(pour_values);
    const auto seconds = [](double s) {
      return std::isnan(s) ? std::string("—") : fmt::format(fmt::runtime(s < 1.0 ? "{:.2f}" : "{:.1f}"), s);
    };
    const auto row = [&](const std::string& protocol, const SeedStatistics& stats, double wall) {
      t.rows.push_back({ex.short_name, protocol, stat_text(stats), seconds(wall), difference_text(stats.mean, ex.experiment)});
    };
    row("drop-and-roll", deposited.deposition, mean_of(deposited.runs, deposition_s));
    row(fmt::format("drop-and-roll, then DEM {} (the paper's method)", how_long(deposited.runs)), deposited.dynamics,
        mean_of(deposited.runs, [&](const RunReport& r) { return deposition_s(r) + dynamics_s(r); }));
    row(fmt::format("pour: a random gas at solid fraction 0.2, fallen through the DEM {}", how_long(poured.runs)),
        pour_only, mean_of(poured.runs, dynamics_s));
    row("pour, then " + rep.plan.tapping_label, poured.dynamics,
        mean_of(poured.runs, [&](const RunReport& r) { return dynamics_s(r) + tapping_s(r); }));
    t.rows.push_back({ex.short_name, "the paper (drop, then DEM)", value_text(ex.after_dem, 3), "", ""});
    t.rows.push_back({ex.short_name, "experiment", value_text(ex.experiment), "", ""});
    result["protocols"][ex.id] = {
        {"drop_and_roll", deposited.json(&CaseRun::after_deposition)},
        {"drop_and_roll_then_dem", deposited.json(&CaseRun::after_dynamics)},
        {"pour", {{"mean", std::isnan(pour_only.mean) ? nlohmann::json() : nlohmann::json(pour_only.mean)},
                  {"sd", std::isnan(pour_only.sd) ? nlohmann::json() : nlohmann::json(pour_only.sd)},
                  {"values", pour_values}}},
        {"pour_then_tapping", poured.json(&CaseRun::after_dynamics)},
        {"tapping", rep.plan.tapping_label}};
  }
  const int threads = rep.threads > 0 ? rep.threads : omp_get_max_threads();
  t.caption = fmt::format("Wall time per run on {} of this machine: the stages that make the bed (deposition, "
                          "DEM, tapping), not sizes, analysis or outputs.", counted(static_cast<std::size_t>(threads), "thread"));
  b.emplace_back(t);
  b.emplace_back(Paragraph{
      "A pour (README, \"Pour\") inserts the spheres as a random gas and lets them fall through the same DEM as the "
      "paper's settling stage; tapping (README, \"Tapping\") then moves the container up and back and lets the bed "
      "land again, as a lab compacts a sample. The material is the examples' own in every row (docs/validation.md "
      "compares the pours with LAMMPS and LIGGGHTS and has the compaction curves over 100 taps)."});
  for (const PaperExample& ex : rep.paper) {
    const auto found = rep.poured.find(ex.id);
    if (found == rep.poured.end()) continue;
    const std::string fig = figures.add(fmt::format("{}_compaction.svg", ex.id),
                                        compaction_plot(ex, found->second.runs, rep.plan.tapping_label));
    b.emplace_back(Figure{fig, fmt::format("{} poured, then tapped ({}): the density after each tap (taps.csv of "
                                           "runs/{}_poured/seed_N), one curve per seed.",
                                           ex.short_name, rep.plan.tapping_label, ex.id)});
  }
}

}  // namespace aggpack::reproduction
