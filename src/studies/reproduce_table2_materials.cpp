// aggpack reproduce: what Table 2 can decide. Its eight mixes are four states' materials, two
// mixes each, none of them described: the section sets the within-state pairs' slopes beside the
// lab's overall one, and the shipped stone and sand's predicted curve against the eight values.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "reproduce_parts.hpp"

namespace aggpack::reproduction {

namespace {

// The curve's packing at `fa` (percent), linear between its points; NaN outside it.
double packing_at(const MaterialsCurve& c, double fa) {
  for (std::size_t i = 1; i < c.fa_percent.size(); ++i)
    if (fa >= c.fa_percent[i - 1] && fa <= c.fa_percent[i]) {
      const double t = (fa - c.fa_percent[i - 1]) / (c.fa_percent[i] - c.fa_percent[i - 1]);
      return c.packing[i - 1] + t * (c.packing[i] - c.packing[i - 1]);
    }
  return kNaN;
}

// A state's two mixes, by Fa.
struct StatePair {
  std::string state;
  Table2Row low, high;
  [[nodiscard]] double slope(double a, double b) const { return 10.0 * (b - a) / (high.fa_percent - low.fa_percent); }
};

std::vector<StatePair> state_pairs(const std::vector<Table2Outcome>& mixes) {
  std::map<std::string, std::vector<Table2Row>> by_state;
  for (const Table2Outcome& m : mixes) by_state[m.row.state].push_back(m.row);
  std::vector<StatePair> out;
  for (auto& [state, rows] : by_state) {
    if (rows.size() != 2) continue;
    std::sort(rows.begin(), rows.end(),
              [](const Table2Row& a, const Table2Row& b) { return a.fa_percent < b.fa_percent; });
    if (rows[1].fa_percent > rows[0].fa_percent) out.push_back({state, rows[0], rows[1]});
  }
  return out;
}

Plot materials_plot(const std::vector<Table2Outcome>& mixes, const MaterialsCurve* curve) {
  Plot plot;
  plot.title = "Table 2's eight mixes against one stone and one sand's predicted curve";
  plot.x_label = "fine aggregate, % of the solid volume";
  plot.y_label = "packing fraction";
  plot.x_column = "fa_percent";
  plot.y_column = "packing";
  if (curve) {
    PlotSeries s;
    s.label = fmt::format("{} + {}, predicted (CPM, {})", curve->coarse, curve->fine, curve->process);
    s.x = curve->fa_percent;
    s.y = curve->packing;
    plot.series.push_back(s);
  }
  for (const StatePair& p : state_pairs(mixes)) {
    PlotSeries s;
    s.label = fmt::format("{}, lab (mixes {} and {})", p.state, p.low.mix, p.high.mix);
    s.x = {p.low.fa_percent, p.high.fa_percent};
    s.y = {p.low.experiment, p.high.experiment};
    s.mark = Mark::LineAndPoints;
    plot.series.push_back(s);
  }
  return plot;
}

// A slope with its sign, "—" when there is none.
std::string signed_text(double x) { return std::isnan(x) ? "—" : fmt::format("{:+.4f}", x); }

// The section's conclusion: what the slopes say, and what would decide.
std::string decision_text(double lab_slope, const std::vector<double>& pair_slopes, const MaterialsCurve* curve,
                          double predicted_slope) {
  return fmt::format(
      "The lab's overall slope is {} per 10 points of Fa; the pairs' run from {} to {}: the states' materials answer "
      "Fa differently, by as much as the overall slope itself, and one curve through all eight is not one blend's "
      "curve. The shipped stone and sand, predicted, {}: they are not any state's materials. Neither this nor any other one pair of materials is Table 2's: calibrating on "
      "one mix and predicting the other seven (reproduce --calibrated-table2, kept as a study) asks a question the "
      "table cannot answer. What would decide it, per state: the stone's ASTM C29 rodded bulk density, grading and "
      "specific gravity (C127), and the sand's C1252 uncompacted voids (method A), grading and specific gravity "
      "(C128). With them, aggpack blend STONE.toml SAND.toml --sweep 25:45:1 gives each state's curve in seconds, "
      "and its pair of lab values tests it with the material held.",
      signed_text(lab_slope), pair_slopes.empty() ? "—" : signed_text(*std::min_element(pair_slopes.begin(), pair_slopes.end())),
      pair_slopes.empty() ? "—" : signed_text(*std::max_element(pair_slopes.begin(), pair_slopes.end())),
      curve ? fmt::format("change by {} per 10 points over the same Fa, densest at {:g} % sand (packing {:.3f})",
                          signed_text(predicted_slope),
                          curve->fa_percent[std::max_element(curve->packing.begin(), curve->packing.end()) -
                                            curve->packing.begin()],
                          *std::max_element(curve->packing.begin(), curve->packing.end()))
            : "were not computed");
}

}  // namespace

void compose_table2_materials(Document& doc, FigureSet& figures, nlohmann::json& result, const Reproduction& rep) {
  auto& b = doc.blocks;
  const MaterialsCurve* curve = rep.plan.table2_materials ? &*rep.plan.table2_materials : nullptr;
  b.emplace_back(Heading{3, "What Table 2 can decide: four states' materials"});
  b.emplace_back(Paragraph{
      "Table 2's eight mixes are four states' DOT aggregates, two mixes from each (Indiana, Michigan, Ohio, "
      "Illinois), and the paper describes none of them: no stone's or sand's grading, bulk density, shape or "
      "specific gravity. From one mix to the next both Fa and the materials change, so the lab's trend over all "
      "eight mixes is not one blend's curve. Only within a state is the material (presumably) held while Fa moves: "
      "four pairs of two points."});
  std::vector<double> fa, measured, predicted;
  for (const Table2Outcome& m : rep.mixes) {
    fa.push_back(m.row.fa_percent);
    measured.push_back(m.row.experiment);
    predicted.push_back(curve ? packing_at(*curve, m.row.fa_percent) : kNaN);
  }
  Table t;
  t.header = {"state",
              "mixes",
              "Fa %",
              "lab packing",
              "lab slope per 10 points of Fa",
              "predicted packing",
              "predicted slope per 10 points"};
  nlohmann::json pairs = nlohmann::json::array();
  std::vector<double> pair_slopes;  // the lab's, state by state
  for (const StatePair& p : state_pairs(rep.mixes)) {
    pair_slopes.push_back(p.slope(p.low.experiment, p.high.experiment));
    const double lo = curve ? packing_at(*curve, p.low.fa_percent) : kNaN;
    const double hi = curve ? packing_at(*curve, p.high.fa_percent) : kNaN;
    t.rows.push_back({p.state, fmt::format("{}, {}", p.low.mix, p.high.mix),
                      fmt::format("{:g} → {:g}", p.low.fa_percent, p.high.fa_percent),
                      fmt::format("{:.3f} → {:.3f}", p.low.experiment, p.high.experiment),
                      signed_text(p.slope(p.low.experiment, p.high.experiment)),
                      curve ? fmt::format("{:.3f} → {:.3f}", lo, hi) : "—",
                      signed_text(curve ? p.slope(lo, hi) : kNaN)});
    pairs.push_back({{"state", p.state},
                     {"mixes", {p.low.mix, p.high.mix}},
                     {"fa_percent", {p.low.fa_percent, p.high.fa_percent}},
                     {"lab", {p.low.experiment, p.high.experiment}},
                     {"lab_slope_per_10", p.slope(p.low.experiment, p.high.experiment)},
                     {"predicted_slope_per_10", curve ? nlohmann::json(p.slope(lo, hi)) : nlohmann::json()}});
  }
  const double lab_slope = fa.size() >= 2 ? slope_per_10(fa, measured) : kNaN;
  const double predicted_slope = curve && fa.size() >= 2 ? slope_per_10(fa, predicted) : kNaN;
  t.rows.push_back(
      {"all eight (least squares)", "", "", "", signed_text(lab_slope), "", signed_text(predicted_slope)});
  t.caption =
      curve ? fmt::format(
                  "Predicted: aggpack blend's lab route for the shipped {} and {}, {} (K {:g}): {}; "
                  "predicted, nothing simulated. The lab's Table 2 method is not given; rodded is "
                  "our choice.",
                  curve->coarse, curve->fine, curve->process, curve->compaction_index, fmt::join(curve->betas, "; "))
            : "Predicted: not computed (no shipped materials beside the scenarios).";
  b.emplace_back(t);
  const std::string fig = figures.add("table2_materials.svg", materials_plot(rep.mixes, curve));
  b.emplace_back(Figure{fig,
                        "Table 2's lab values, each state's pair joined, against one stone and one sand's "
                        "predicted curve (the shipped defaults, not the states' materials)."});
  b.emplace_back(Paragraph{decision_text(lab_slope, pair_slopes, curve, predicted_slope)});
  result["table2_materials"] = {
      {"pairs", pairs},
      {"lab_slope_per_10", lab_slope},
      {"predicted_slope_per_10", curve ? nlohmann::json(predicted_slope) : nlohmann::json()},
      {"predicted", curve ? nlohmann::json{{"coarse", curve->coarse},
                                           {"fine", curve->fine},
                                           {"process", curve->process},
                                           {"compaction_index", curve->compaction_index},
                                           {"betas", curve->betas},
                                           {"source", "predicted by CPM from the materials' lab numbers"},
                                           {"fa_percent", curve->fa_percent},
                                           {"packing", curve->packing}}
                          : nlohmann::json()}};
}

}  // namespace aggpack::reproduction
