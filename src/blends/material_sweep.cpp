// A sweep of two materials: the predicted curve, then the DEM at the checked points only.
#include "aggpack/blends/material_sweep.hpp"

#include <fmt/format.h>

#include <cmath>

#include "aggpack/core/error.hpp"
#include "aggpack/core/version.hpp"

namespace aggpack {

namespace {

nlohmann::json or_null(double x) {
  return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json();
}

}  // namespace

MaterialSweep sweep_materials(const MaterialSweepOptions& o, std::ostream& log) {
  if (o.blend.materials.size() != 2)
    throw InputError(
        fmt::format("a sweep of materials takes two (coarse, then fine), {} given", o.blend.materials.size()));
  for (const double pc : o.check_percents)  // before the curve's betas, which may simulate
    if (!(pc > 0.0 && pc < 100.0)) throw InputError(fmt::format("--check: {} is not a percent between 0 and 100", pc));
  check_blend_request(o.blend);
  MaterialSweep out;
  for (const std::filesystem::path& file : o.blend.materials)
    out.calibrations.push_back(load_material_file(file).calibration);
  out.predicted = predict_blends(o.blend, log);
  if (!o.check_percents.empty()) {
    BlendCheckOptions c;
    c.coarse = o.blend.materials[0];
    c.fine = o.blend.materials[1];
    c.percents = o.check_percents;
    c.fine_d_min = o.check_cut;
    c.coarse_particles = o.check_particles;
    c.betas = o.blend.beds;
    c.interaction = o.blend.interaction;
    out.check = check_blend(c, log);
  }
  return out;
}

nlohmann::json to_json(const MaterialSweep& s) {
  const BlendCurve& curve = s.predicted.curves.front();
  nlohmann::json materials = nlohmann::json::array();
  for (std::size_t i = 0; i < curve.materials.size(); ++i) {
    const MaterialBetas& m = curve.materials[i];
    materials.push_back({{"file", m.file.string()},
                         {"name", m.material},
                         {"betas_route", name_of(kBetaRouteNames, m.route)},
                         {"betas_source", m.source},
                         {"calibration", s.calibrations.at(i)}});
  }
  nlohmann::json points = nlohmann::json::array();
  for (const BlendPoint& p : curve.points)
    points.push_back({{"fa_percent", 100.0 * p.volume_fractions.at(1)},
                      {"source", "predicted"},
                      {"route", curve.route},
                      {"density", p.packing},
                      {"density_low", p.packing_low},
                      {"density_high", p.packing_high},
                      {"voids_content_percent", p.voids_percent},
                      {"bulk_density_kg_m3", p.bulk_density_kg_m3}});
  nlohmann::json checked = nlohmann::json::array();
  if (s.check)
    for (const BlendCheckPoint& p : s.check->points)
      checked.push_back(
          {{"fa_percent", p.percent},
           {"source", "simulated"},
           {"procedure", s.check->procedure},
           {"density", {{"mean", p.simulated.mean}, {"sd", or_null(p.simulated.sd)}, {"values", p.packing}}},
           {"predicted", p.predicted}});
  const BlendPoint& top = curve.points.at(curve.densest->index);
  nlohmann::json j{{"aggpack_version", kVersion},
                   {"kind", "aggpack sweep of materials"},
                   {"materials", materials},
                   {"process", s.predicted.process.name},
                   {"compaction_index", s.predicted.process.compaction_index},
                   {"points", points},
                   {"checked_points", checked},
                   {"best",
                    {{"fa_percent", 100.0 * top.volume_fractions.at(1)},
                     {"source", "predicted"},
                     {"density", top.packing},
                     {"density_low", top.packing_low},
                     {"density_high", top.packing_high},
                     {"bulk_density_kg_m3", top.bulk_density_kg_m3},
                     {"voids_content_percent", top.voids_percent}}},
                   {"prediction", to_json(s.predicted)}};
  if (s.check) j["check"] = to_json(*s.check);
  return j;
}

std::string sweep_csv(const MaterialSweep& s) {
  std::string out = "fa_percent,source,density,density_low,density_high,density_sd,seeds\n";
  const BlendCurve& curve = s.predicted.curves.front();
  for (const BlendPoint& p : curve.points)
    out += fmt::format("{:.6g},predicted,{:.6f},{:.6f},{:.6f},,\n", 100.0 * p.volume_fractions.at(1), p.packing,
                       p.packing_low, p.packing_high);
  if (s.check)
    for (const BlendCheckPoint& p : s.check->points)
      out += fmt::format("{:.6g},simulated,{:.6f},,,{},{}\n", p.percent, p.simulated.mean,
                         std::isfinite(p.simulated.sd) ? fmt::format("{:.6f}", p.simulated.sd) : "", p.packing.size());
  return out;
}

}  // namespace aggpack
