// aggpack reproduce: the Table 2 mixes' cut-off series carried to their whole grading.
#include "reproduce_parts.hpp"

#include <fmt/format.h>

namespace aggpack::reproduction {

// A mix's deposited runs at every sand cut-off it was run at (its own, its --whole-grading
// series and, for the sensitivity mix, the cut-off variants), carried to the whole grading by
// CPM with aggpack whole-grading's fit; none below three cut-offs.
std::optional<WholeGradingEstimate> table2_whole_grading(const Reproduction& rep, const Table2Outcome& m) {
  if (m.runs.empty()) return std::nullopt;
  const ModelParameters parameters = table2_parameters(rep);
  std::vector<CutOffPoint> points;
  const auto add = [&](const SeedRuns& runs) {
    if (runs.runs.empty()) return;
    const Scenario& at_cut = runs.runs.front().result.report.scenario;
    const std::optional<double> cut = at_cut.particles.graded->fine->d_min;
    if (!cut) return;
    for (const CutOffPoint& p : points)
      if (std::abs(p.cut_off - *cut) < 1e-12) return;  // one point per cut-off
    points.push_back(cut_off_point(at_cut, parameters, *cut, runs.values(&CaseRun::after_deposition),
                                   runs.runs.front().particle_count));
  };
  add(m);
  for (const auto& cut_runs : m.cut_series) add(cut_runs.second);
  if (&m == &rep.sensitivity_mix())
    for (const Variant& v : rep.variants)
      if (!std::isnan(v.spec.sand_cut_in)) add(v);
  if (points.size() < 3) return std::nullopt;
  return fit_whole_grading(m.runs.front().result.report.scenario, parameters, std::move(points));
}

// The sensitivity mix's cut-off series carried to its whole grading, with its plot.
void compose_whole_grading(Document& doc, FigureSet& figures, nlohmann::json& result, const Reproduction& rep) {
  if (!table2_scenario(rep)) return;
  const std::optional<WholeGradingEstimate> estimate = table2_whole_grading(rep, rep.sensitivity_mix());
  if (!estimate) return;
  const Table2Row& row = rep.sensitivity_mix().row;
  const WholeGradingEstimate& e = *estimate;
  nlohmann::json j = to_json(e);
  j["mix"] = row.mix;
  j["experiment"] = row.experiment;
  result["table2_whole_grading"] = j;
  auto& b = doc.blocks;
  std::string series;
  for (const CutOffPoint& p : e.points)
    series += fmt::format("{}{:g} in: {:.3f}", series.empty() ? "" : ", ", p.cut_off / 0.0254, p.mean);
  // A band wider than 0.04 gives no estimate: then no number is quoted as one.
  const std::string outcome =
      e.trustworthy()
          ? fmt::format("The whole grading then packs at {:.3f} (band {:.3f} to {:.3f}), against {:.3f} measured: "
                        "{:+.3f}.",
                        e.density, e.low, e.high, row.experiment, e.density - row.experiment)
          : fmt::format("Its band, {:.3f} to {:.3f}, is wider than 0.04: these runs give no estimate of the whole "
                        "grading (measured: {:.3f}).",
                        e.low, e.high, row.experiment);
  b.emplace_back(Paragraph{fmt::format(
      "The whole grading of mix {}. Its cut-off series after deposition ({}) is carried below the finest cut by "
      "CPM ({}): the residual simulated − CPM, a line in the volume left out, is extrapolated to nothing left out "
      "(aggpack whole-grading's fit, on these runs). {} The simulation covers {:.1f} % of the blend's volume, the "
      "model the {:.1f} % below the finest cut. {}",
      row.mix, series, cpm_parameters_text(rep), outcome, 100.0 * e.simulated_fraction,
      100.0 * (1.0 - e.simulated_fraction),
      !e.trustworthy() ? "The band is too wide to conclude anything; more seeds and finer cut-offs narrow it."
      : e.low > row.experiment
          ? "Frictionless spheres laid by drop-and-roll pack denser than the measured aggregate once the whole sand "
            "is kept: the remaining difference is the particles, not the cut-off (CPM with a sand looser than "
            "spheres, beta 0.58 to 0.62, falls into the experiments' range; docs/validation.md, all eight mixes)."
          : "The experiment lies within the band or above it.")});
  const std::string fig = figures.add(
      fmt::format("table2_mix{}_whole_grading.svg", row.mix),
      whole_grading_plot(e, row.experiment, fmt::format("Table 2 mix {}: density against the sand cut-off", row.mix)));
  b.emplace_back(Figure{fig, fmt::format("Mix {}: the density after deposition against the volume of the blend the "
                                         "cut-offs leave out (each point a sand cut-off, mean ± se over seeds), CPM on "
                                         "each simulated distribution, and the model fitted to them carried to the "
                                         "whole grading (left edge, with its band); black: the experiment.",
                                         row.mix)});
}

// A whole-grading estimate for a table cell: "0.782 (0.771–0.793)", "wide" past 0.04, or none.
std::string whole_grading_text(const std::optional<WholeGradingEstimate>& e) {
  if (!e) return "—";
  return fmt::format("{:.3f} ({:.3f}–{:.3f}){}", e->density, e->low, e->high, e->trustworthy() ? "" : ", wide");
}

}  // namespace aggpack::reproduction
