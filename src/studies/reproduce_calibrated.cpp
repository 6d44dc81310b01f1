// aggpack reproduce --calibrated-table2: Table 2 predicted from one calibration mix, with stone
// and sand each their own material and the sand's rolling friction the one unknown.
#include <fmt/format.h>

#include <algorithm>

#include "aggpack/core/enum_names.hpp"
#include "reproduce_parts.hpp"

namespace aggpack::reproduction {

namespace {

constexpr double kTargetMeanAbsoluteError = 0.015;  // issue 36: about 2 %
constexpr double kTargetSlopeTolerance = 0.005;     // per 10 points of Fa, about the lab's slope

std::string band_text(double low, double high) {
  return std::isnan(low) ? std::string("no band from one seed") : fmt::format("{:.3f}–{:.3f}", low, high);
}

const Scenario& calibrated_scenario(const Reproduction& rep) {
  return rep.calibrated.front().at_value.front().runs.front().result.report.scenario;
}

// "sand: μ 0.4, μ_r the unknown, ...; stone: μ 0.5, μ_r 0.2, ...", with the rolling law.
std::string materials_text(const Scenario& sc, const CalibratedTable2Plan& plan) {
  std::vector<std::string> parts;
  for (const NamedMaterial& m : sc.materials) {
    const ContactParameters& c = m.material.contact;
    parts.push_back(
        fmt::format("{}: μ {:g}, μ_r {}, E {:.3g} GPa, ν {:g}, e {:g}", m.name, c.friction_particle,
                    m.name == plan.material ? std::string("the unknown") : fmt::format("{:g}", c.rolling_friction),
                    1e-9 * c.youngs_modulus, c.poisson_ratio, c.restitution));
  }
  return fmt::format("{} (rolling law {})", fmt::join(parts, "; "),
                     name_of(kRollingModelNames, sc.material.contact.rolling_model));
}

// The targets, judged on the median choice: its slope against the lab's over the same mixes.
bool mean_error_met(const LeaveOneOutChoice& c) {
  return c.mean_absolute_error <= kTargetMeanAbsoluteError;
}
bool slope_met(const LeaveOneOutChoice& c) {
  return std::abs(c.slope_per_10 - c.lab_slope_per_10) <= kTargetSlopeTolerance;
}

std::vector<GridCurve> grid_curves(const Reproduction& rep) {
  std::vector<GridCurve> curves;
  for (const CalibratedMix& m : rep.calibrated) {
    GridCurve c{m.row.mix, m.row.fa_percent, m.row.experiment, rep.plan.calibrated_table2->values, {}};
    for (const SeedRuns& runs : m.at_value) {
      std::vector<double> carried;
      for (const CaseRun& r : runs.runs) carried.push_back(carried_density(r));
      c.density.push_back(seed_statistics(carried));
    }
    curves.push_back(std::move(c));
  }
  return curves;
}

// Per mix: at each grid value, the density at the cut and carried to the whole grading.
Table grid_table(const Reproduction& rep, const std::vector<GridCurve>& curves) {
  const CalibratedTable2Plan& plan = *rep.plan.calibrated_table2;
  Table t;
  t.header = {"mix", "Fa %", "measured"};
  for (const double v : plan.values) t.header.push_back(fmt::format("μ_r {:g}: at the cut / carried", v));
  for (std::size_t k = 0; k < rep.calibrated.size(); ++k) {
    const CalibratedMix& m = rep.calibrated[k];
    std::vector<std::string> row{fmt::format("{}", m.row.mix), fmt::format("{:.0f}", m.row.fa_percent),
                                 value_text(m.row.experiment, 3)};
    for (std::size_t v = 0; v < plan.values.size(); ++v) {
      const SeedStatistics& carried = curves[k].density[v];
      row.push_back(fmt::format("{} / {}", stat_text(m.at_value[v].final_stats()), stat_text(carried)));
    }
    t.rows.push_back(std::move(row));
  }
  t.caption = fmt::format(
      "Every mix poured at each value of the {}'s rolling friction: the density at the cut (mean "
      "over the virtual boxes, ± sd over seeds) and carried to the whole grading.",
      plan.material);
  return t;
}

Table choices_table(const LeaveOneOutStudy& study) {
  const std::size_t others = study.choices.size() - 1;
  Table t;
  t.header = {"calibration mix",   "Fa %",
              "fitted μ_r (band)", fmt::format("mean absolute error over the other {}", others),
              "largest error",     fmt::format("slope of the predictions per 10 points (lab's, same {})", others)};
  for (const LeaveOneOutChoice& c : study.choices) {
    if (!c.fitted) {
      t.rows.push_back(
          {fmt::format("{}", c.calibration_mix), fmt::format("{:.0f}", c.fa_percent), c.why_not_fitted, "—", "—", "—"});
      continue;
    }
    t.rows.push_back({fmt::format("{}", c.calibration_mix), fmt::format("{:.0f}", c.fa_percent),
                      fmt::format("{:.3f} ({}){}", c.fitted->value, band_text(c.fitted->band_low, c.fitted->band_high),
                                  c.fitted->at_end ? ", at the grid's end"
                                  : c.fitted->crossings > 1
                                      ? fmt::format(", the first of {} crossings: not monotone", c.fitted->crossings)
                                      : std::string()),
                      fmt::format("{:.4f}", c.mean_absolute_error), fmt::format("{:+.4f}", c.largest_error),
                      fmt::format("{:+.4f} ({:+.4f})", c.slope_per_10, c.lab_slope_per_10)});
  }
  t.caption = fmt::format(
      "Each mix in turn is the calibration mix: μ_r is fitted to its measurement alone and the other {} are "
      "predicted at it.",
      others);
  return t;
}

std::string outcome_text(const LeaveOneOutStudy& study, const std::vector<GridCurve>& curves) {
  if (!study.median) {
    // Where the grid's carried densities lie, each mix's lowest and highest, against the lab.
    double lowest = 1.0, highest = 0.0, measured_lo = 1.0, measured_hi = 0.0, lever = 0.0;
    std::size_t above = 0;
    for (const GridCurve& c : curves) {
      const auto [lo, hi] =
          std::minmax_element(c.density.begin(), c.density.end(),
                              [](const SeedStatistics& a, const SeedStatistics& b) { return a.mean < b.mean; });
      lowest = std::min(lowest, lo->mean), highest = std::max(highest, hi->mean);
      measured_lo = std::min(measured_lo, c.measured), measured_hi = std::max(measured_hi, c.measured);
      lever = std::max(lever, hi->mean - lo->mean);
      above += lo->mean > c.measured ? 1 : 0;
    }
    return fmt::format(
        "No calibration mix can be fitted: over the grid the carried densities lie between {:.3f} and {:.3f}, the "
        "measurements between {:.3f} and {:.3f}; {} of {} mixes pack denser than measured at every value, and a mix "
        "moves by at most {:.3f} across the grid. Nothing is predicted, and the targets (mean absolute error ≤ {:g}, "
        "slope within {:g} per 10 points of the lab's) are not reached: what is left is the grains' shape "
        "(docs/validation.md, \"Table 2 from one calibration mix\").",
        lowest, highest, measured_lo, measured_hi, above, curves.size(), lever, kTargetMeanAbsoluteError,
        kTargetSlopeTolerance);
  }
  const LeaveOneOutChoice& m = study.choices[*study.median];
  std::size_t fitted = 0;
  for (const LeaveOneOutChoice& c : study.choices) fitted += c.fitted ? 1 : 0;
  return fmt::format(
      "{} of {} mixes could be calibrated on. The median choice (by mean absolute error) is mix {} (Fa {:.0f} %), "
      "μ_r = {:.3f}: mean absolute error {:.4f} over the {} others (target ≤ {:g}: {}), slope {:+.4f} per 10 "
      "points of Fa against the lab's {:+.4f} over the same mixes ({:+.4f} over all {}; target within {:g}: {}).",
      fitted, study.choices.size(), m.calibration_mix, m.fa_percent, m.fitted->value, m.mean_absolute_error,
      m.predicted.size(), kTargetMeanAbsoluteError, mean_error_met(m) ? "met" : "missed", m.slope_per_10,
      m.lab_slope_per_10, study.lab_slope_per_10, study.choices.size(), kTargetSlopeTolerance,
      slope_met(m) ? "met" : "missed");
}

// Density against Fa: the lab, the paper, the spheres of Table 2 above, the stone-and-sand beds
// at each grid value (carried) and the median choice's predictions.
Plot calibrated_plot(const Reproduction& rep, const std::vector<GridCurve>& curves, const LeaveOneOutStudy& study) {
  const CalibratedTable2Plan& plan = *rep.plan.calibrated_table2;
  PlotSeries lab{"experiment", {}, {}, {}, Mark::Points, false, "#000000"};
  PlotSeries paper{"paper (computed)", {}, {}, {}, Mark::Points, false, "#7f7f7f"};
  PlotSeries spheres{"smooth spheres, as simulated (Table 2)", {}, {}, {}, Mark::Points, false, "#1f77b4"};
  for (const Table2Outcome& m : rep.mixes) {
    lab.x.push_back(m.row.fa_percent), lab.y.push_back(m.row.experiment);
    paper.x.push_back(m.row.fa_percent), paper.y.push_back(m.row.paper_mean);
    if (m.reported_stats().count) spheres.x.push_back(m.row.fa_percent), spheres.y.push_back(m.reported_stats().mean);
  }
  Plot plot;
  plot.title = "Table 2: density against the sand's share";
  plot.x_label = "Fa (% of the blend's volume)";
  plot.y_label = "packing density";
  plot.x_column = "fa_percent";
  plot.y_column = "packing_density";
  plot.legend_at_bottom = true;
  plot.series = {lab, paper, spheres};
  const std::array<const char*, 4> shades{"#fdae6b", "#fd8d3c", "#e6550d", "#a63603"};
  for (std::size_t v = 0; v < plan.values.size(); ++v) {
    PlotSeries s{fmt::format("stone and sand carried, {} μ_r {:g}", plan.material, plan.values[v]),
                 {},
                 {},
                 {},
                 Mark::Line,
                 true,
                 shades[std::min(v, shades.size() - 1)]};
    std::vector<std::pair<double, double>> points;
    for (const GridCurve& c : curves) points.emplace_back(c.fa_percent, c.density[v].mean);
    std::sort(points.begin(), points.end());
    for (const auto& [x, y] : points) s.x.push_back(x), s.y.push_back(y);
    plot.series.push_back(std::move(s));
  }
  if (study.median) {
    const LeaveOneOutChoice& m = study.choices[*study.median];
    PlotSeries predicted{fmt::format("predicted from mix {} (median choice)", m.calibration_mix),
                         {},
                         {},
                         {},
                         Mark::Points,
                         false,
                         "#d62728"};
    for (const PredictedBlend& p : m.predicted) {
      predicted.x.push_back(p.fa_percent), predicted.y.push_back(p.density);
      predicted.y_error.push_back(std::isnan(p.band_low) ? 0.0
                                                         : std::max(p.band_high - p.density, p.density - p.band_low));
    }
    plot.series.push_back(std::move(predicted));
  }
  return plot;
}

nlohmann::json study_json(const Reproduction& rep, const std::vector<GridCurve>& curves,
                          const LeaveOneOutStudy& study) {
  const CalibratedTable2Plan& plan = *rep.plan.calibrated_table2;
  const auto or_null = [](double v) { return std::isnan(v) ? nlohmann::json() : nlohmann::json(v); };
  nlohmann::json mixes = nlohmann::json::array();
  for (std::size_t k = 0; k < rep.calibrated.size(); ++k) {
    nlohmann::json at = nlohmann::json::array();
    for (std::size_t v = 0; v < plan.values.size(); ++v) {
      const SeedRuns& runs = rep.calibrated[k].at_value[v];
      std::vector<double> simulated, carried;
      for (const CaseRun& r : runs.runs) simulated.push_back(r.final_density()), carried.push_back(carried_density(r));
      at.push_back({{"value", plan.values[v]},
                    {"simulated", simulated},
                    {"carried", carried},
                    {"carried_mean", or_null(curves[k].density[v].mean)},
                    {"carried_sd", or_null(curves[k].density[v].sd)},
                    {"particles", runs.runs.empty() ? 0 : particle_count(runs.runs.front())}});
    }
    mixes.push_back(
        {{"mix", curves[k].mix}, {"fa_percent", curves[k].fa_percent}, {"measured", curves[k].measured}, {"at", at}});
  }
  nlohmann::json choices = nlohmann::json::array();
  for (const LeaveOneOutChoice& c : study.choices) {
    nlohmann::json j{{"calibration_mix", c.calibration_mix}, {"fa_percent", c.fa_percent}};
    if (!c.fitted) {
      j["fitted"] = nullptr;
      j["why_not_fitted"] = c.why_not_fitted;
    } else {
      j["fitted"] = {{"value", c.fitted->value},
                     {"band", {or_null(c.fitted->band_low), or_null(c.fitted->band_high)}},
                     {"at_grid_end", c.fitted->at_end},
                     {"crossings", c.fitted->crossings}};
      nlohmann::json predicted = nlohmann::json::array();
      for (const PredictedBlend& p : c.predicted)
        predicted.push_back({{"mix", p.mix},
                             {"density", p.density},
                             {"band", {or_null(p.band_low), or_null(p.band_high)}},
                             {"measured", p.measured}});
      j["predicted"] = predicted;
      j["mean_absolute_error"] = c.mean_absolute_error;
      j["largest_error"] = c.largest_error;
      j["slope_per_10"] = c.slope_per_10;
      j["lab_slope_per_10_same_mixes"] = c.lab_slope_per_10;
    }
    choices.push_back(j);
  }
  const bool met =
      study.median && mean_error_met(study.choices[*study.median]) && slope_met(study.choices[*study.median]);
  return {{"scenario", plan.scenario},
          {"parameter", fmt::format("materials.{}.rolling_friction", plan.material)},
          {"values", plan.values},
          {"bed", plan.bed},
          {"bed_label", plan.bed_label},
          {"carry", "simulated + CPM(whole grading) - CPM(simulated distribution)"},
          {"mixes", mixes},
          {"choices", choices},
          {"median_calibration_mix",
           study.median ? nlohmann::json(study.choices[*study.median].calibration_mix) : nlohmann::json()},
          {"lab_slope_per_10", study.lab_slope_per_10},
          {"targets",
           {{"mean_absolute_error", kTargetMeanAbsoluteError},
            {"slope_tolerance_per_10", kTargetSlopeTolerance},
            {"met", met}}}};
}

}  // namespace

double carried_density(const CaseRun& run) {
  const nlohmann::json& p = run.result.summary.at("predictions");
  return run.final_density() + p.at("whole_grading").at("cpm").at("density").get<double>() -
         p.at("simulated").at("cpm").at("density").get<double>();
}

std::optional<LeaveOneOutStudy> calibrated_study(const Reproduction& rep) {
  if (rep.calibrated.empty()) return std::nullopt;
  return leave_one_out(grid_curves(rep));
}

std::string calibrated_cell(const LeaveOneOutStudy& study, int mix) {
  if (!study.median) return "— (no mix could be fitted)";
  const LeaveOneOutChoice& m = study.choices[*study.median];
  if (m.calibration_mix == mix) return "the calibration mix";
  for (const PredictedBlend& p : m.predicted)
    if (p.mix == mix) return fmt::format("{:.4f} ({})", p.density, band_text(p.band_low, p.band_high));
  return "—";
}

void compose_calibrated_table2(Document& doc, FigureSet& figures, nlohmann::json& result, const Reproduction& rep) {
  if (rep.calibrated.empty()) return;
  const CalibratedTable2Plan& plan = *rep.plan.calibrated_table2;
  const std::vector<GridCurve> curves = grid_curves(rep);
  const LeaveOneOutStudy study = leave_one_out(curves);
  auto& b = doc.blocks;
  b.emplace_back(Heading{2, "Table 2 from one calibration mix: a study, not a target"});
  b.emplace_back(Paragraph{fmt::format(
      "A study kept for what it shows, not a target: Table 2's mixes are four states' materials (\"What Table 2 "
      "can decide\" above), so one stone and sand calibrated on one mix need not predict the other seven. "
      "Every Table 2 mix poured by the DEM from {} with its own Ca/Fa, stone and sand each their own material ({}), at "
      "{} values of the {}'s rolling friction μ_r, the one unknown ({}), over {}. The bed: {}. Each bed is carried to "
      "its whole grading by CPM's own increment, simulated + CPM(whole grading) − CPM(simulated distribution), with "
      "CPM's spheres ({}). For each choice of the calibration mix, μ_r is where that mix's carried seed mean meets "
      "its measured density, read straight between grid values (band: the measurement ∓ the larger standard error "
      "of the two values around it); the other {} mixes are read off their own curves at that μ_r. The "
      "calibration sees that one mix's measurement and nothing else.",
      plan.scenario, materials_text(calibrated_scenario(rep), plan), plan.values.size(), plan.material,
      fmt::join(plan.values, ", "), counted(rep.calibrated.front().at_value.front().runs.size(), "seed"),
      plan.bed_label, cpm_parameters_text(rep), curves.size() - 1)});
  b.emplace_back(grid_table(rep, curves));
  b.emplace_back(choices_table(study));
  b.emplace_back(Paragraph{outcome_text(study, curves)});
  const std::string fig = figures.add("table2_calibrated.svg", calibrated_plot(rep, curves, study));
  b.emplace_back(Figure{fig, fmt::format("Density against Fa: the experiments (black), the paper's computation "
                                         "(grey), this report's smooth spheres (blue), the stone-and-sand beds "
                                         "carried to the whole grading at each value of the {}'s μ_r (dashed) and, "
                                         "when a mix could be fitted, the median choice's predictions (red; the "
                                         "bar reaches the farther end of each prediction's band).",
                                         plan.material)});
  result["calibrated_table2"] = study_json(rep, curves, study);
}

}  // namespace aggpack::reproduction
