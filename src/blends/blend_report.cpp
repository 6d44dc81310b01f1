// `aggpack blend`'s outputs: the table, the JSON and the plot of a BlendResult.
#include "aggpack/blends/blend_report.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>

#include "aggpack/core/version.hpp"
#include "aggpack/report/svg_plot.hpp"

namespace aggpack {

namespace {

nlohmann::json point_json(const BlendPoint& p) {
  return {{"volume_fractions", p.volume_fractions},
          {"mass_fractions", p.mass_fractions},
          {"packing_density", p.packing},
          {"packing_density_low", p.packing_low},
          {"packing_density_high", p.packing_high},
          {"virtual_packing_density", p.virtual_packing},
          {"dominant_class", p.dominant},
          {"voids_percent", p.voids_percent},
          {"particle_density_kg_m3", p.particle_density_kg_m3},
          {"bulk_density_kg_m3", p.bulk_density_kg_m3}};
}

nlohmann::json densest_json(const BlendCurve& c) {
  const DensestBlend& d = *c.densest;
  const auto second = [&](std::size_t i) { return 100.0 * c.points[i].volume_fractions.at(1); };
  return {{"point", point_json(c.points[d.index])},
          {"second_volume_percent", second(d.index)},
          {"within_beta_spread_percent", {second(d.spread_first), second(d.spread_last)}},
          {"plateau_percent", {second(d.plateau_first), second(d.plateau_last)}},
          {"plateau_packing_tolerance", DensestBlend::kPlateau}};
}

std::string percents(const std::vector<double>& fractions) {
  std::vector<std::string> out;
  for (const double f : fractions) out.push_back(fmt::format("{:.1f}", 100.0 * f));
  return fmt::format("{}", fmt::join(out, "/"));
}

void describe_curve(fmt::memory_buffer& o, const BlendCurve& c) {
  fmt::format_to(std::back_inserter(o), "\nroute: {}\n", c.route);
  for (const MaterialBetas& m : c.materials) {
    double lo = 1.0, hi = 0.0;
    for (const ClassBeta& k : m.classes) lo = std::min(lo, k.beta), hi = std::max(hi, k.beta);
    fmt::format_to(std::back_inserter(o), "  {}: {} class{}, beta {:.3f}{}; {}\n", m.material, m.classes.size(),
                   m.classes.size() == 1 ? "" : "es", lo, hi > lo ? fmt::format("-{:.3f}", hi) : "", m.source);
  }
  fmt::format_to(std::back_inserter(o), "  {:>16} {:>16} {:>8} {:>17} {:>7} {:>7}\n", "volume %", "mass %", "packing",
                 "band (beta +-sd)", "voids %", "kg/m3");
  for (const BlendPoint& p : c.points)
    fmt::format_to(std::back_inserter(o), "  {:>16} {:>16} {:>8.4f} {:>8.4f}-{:<8.4f} {:>7.1f} {:>7.0f}\n",
                   percents(p.volume_fractions), percents(p.mass_fractions), p.packing, p.packing_low, p.packing_high,
                   p.voids_percent, p.bulk_density_kg_m3);
  if (!c.densest) return;
  const DensestBlend& d = *c.densest;
  const auto second = [&](std::size_t i) { return 100.0 * c.points[i].volume_fractions.at(1); };
  const BlendPoint& top = c.points[d.index];
  fmt::format_to(
      std::back_inserter(o),
      "  densest: {:.1f} % of {} by volume ({:.1f} % by mass): packing {:.4f}, voids {:.1f} %, {:.0f} kg/m3\n"
      "    as dense within the betas' spread: {:.1f}-{:.1f} %; within {:g} of the densest: {:.1f}-{:.1f} %\n",
      second(d.index), c.materials.at(1).material, 100.0 * top.mass_fractions.at(1), top.packing, top.voids_percent,
      top.bulk_density_kg_m3, second(d.spread_first), second(d.spread_last), DensestBlend::kPlateau,
      second(d.plateau_first), second(d.plateau_last));
}

}  // namespace

nlohmann::json to_json(const BlendResult& r) {
  nlohmann::json curves = nlohmann::json::array();
  for (const BlendCurve& c : r.curves) {
    nlohmann::json materials = nlohmann::json::array(), points = nlohmann::json::array();
    for (const MaterialBetas& m : c.materials) materials.push_back(to_json(m));
    for (const BlendPoint& p : c.points) points.push_back(point_json(p));
    nlohmann::json curve{{"route", c.route}, {"materials", materials}, {"points", points}};
    if (c.densest) curve["densest"] = densest_json(c);
    curves.push_back(curve);
  }
  return {{"aggpack_version", kVersion},
          {"kind", "aggpack blend"},
          {"prediction", "CPM (de Larrard 1999) with each material's betas class by class; predicted, not simulated"},
          {"process", r.process.name},
          {"compaction_index", r.process.compaction_index},
          {"sweep", r.sweep},
          {"curves", curves},
          {"modelling", r.modelling},
          {"wall_clock_s", r.wall_clock_s}};
}

std::string describe(const BlendResult& r) {
  fmt::memory_buffer o;
  fmt::format_to(std::back_inserter(o), "aggpack {}: blends predicted by CPM, {} (K {:g}); predicted, not simulated\n",
                 kVersion, r.process.name, r.process.compaction_index);
  for (const BlendCurve& c : r.curves) describe_curve(o, c);
  for (const std::string& m : r.modelling) fmt::format_to(std::back_inserter(o), "- {}\n", m);
  return fmt::to_string(o);
}

std::string blend_svg(const BlendResult& r, const BlendCheck* check) {
  Plot plot;
  const BlendCurve& first = r.curves.front();
  plot.title = fmt::format("{} + {}, {} (K {:g}), CPM", first.materials.at(0).material, first.materials.at(1).material,
                           r.process.name, r.process.compaction_index);
  plot.x_label = fmt::format("{} (% of the solid volume)", first.materials.at(1).material);
  plot.y_label = "packing fraction";
  plot.x_column = "second_volume_percent";
  plot.y_column = "packing_density";
  for (const BlendCurve& c : r.curves) {
    PlotSeries s;
    s.label = fmt::format("{} route", c.route);
    s.dashed = c.route == "lab_test";
    for (const BlendPoint& p : c.points) {
      s.x.push_back(100.0 * p.volume_fractions.at(1));
      s.y.push_back(p.packing);
    }
    plot.series.push_back(s);
    if (c.densest) {
      const BlendPoint& top = c.points[c.densest->index];
      PlotSeries mark;
      mark.label = fmt::format("densest, {} route", c.route);
      mark.x = {100.0 * top.volume_fractions.at(1)};
      mark.y = {top.packing};
      mark.y_error = {0.5 * (top.packing_high - top.packing_low)};
      mark.mark = Mark::Points;
      plot.series.push_back(mark);
    }
  }
  if (check != nullptr && !check->points.empty()) {
    PlotSeries dem;
    dem.label = fmt::format("DEM of the blend, {} (seed mean and sd)", check->procedure);
    for (const BlendCheckPoint& p : check->points) {
      dem.x.push_back(p.percent);
      dem.y.push_back(p.simulated.mean);
      dem.y_error.push_back(std::isfinite(p.simulated.sd) ? p.simulated.sd : 0.0);
    }
    dem.mark = Mark::Points;
    plot.series.push_back(dem);
    // CPM at the checked blends themselves: the same as the curve, unless the check cut the fine.
    PlotSeries cpm;
    cpm.label = "CPM at the checked blends";
    for (const BlendCheckPoint& p : check->points) {
      cpm.x.push_back(p.percent);
      cpm.y.push_back(p.predicted);
    }
    cpm.mark = Mark::Points;
    plot.series.push_back(cpm);
  }
  return svg_plot(plot);
}

}  // namespace aggpack
