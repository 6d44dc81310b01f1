// A lab test's result in summary.json and on the console, in the lab's units.
#include <fmt/format.h>

#include <cmath>

#include "aggpack/analysis/bulk_density.hpp"
#include "aggpack/core/version.hpp"
#include "aggpack/labtests/lab_test.hpp"

namespace aggpack {

namespace {

nlohmann::json number_or_null(double v) { return std::isnan(v) ? nlohmann::json() : nlohmann::json(v); }

nlohmann::json to_json(const SeedStatistics& s) {
  return {{"mean", number_or_null(s.mean)}, {"sd", number_or_null(s.sd)}, {"seeds", s.count}};
}

// "0.597 +- 0.004" (no spread for one seed).
std::string with_spread(double mean, double sd, const char* format) {
  const std::string m = fmt::format(fmt::runtime(format), mean);
  return std::isnan(sd) || sd == 0.0 ? m : m + " +- " + fmt::format(fmt::runtime(format), sd);
}

// Where the time went, over the seeds.
nlohmann::json to_json(const LabTestTiming& t) {
  return {{"sizes_s", t.sizes_s},     {"grains_s", t.grains_s},   {"pour_s", t.pour_s},
          {"rodding_s", t.rodding_s}, {"jigging_s", t.jigging_s}, {"analysis_s", t.analysis_s},
          {"dem_steps", t.dem_steps}, {"spheres", t.spheres},     {"simulated_s", t.simulated_s}};
}

}  // namespace

nlohmann::json to_json(const LabTestResult& r) {
  const LabTestPlan& p = r.plan;
  nlohmann::json parts = nlohmann::json::array();
  for (std::size_t i = 0; i < r.parts.size(); ++i) {
    const LabTestPartResult& pr = r.parts[i];
    const LabTestPart& part = p.parts[i];
    parts.push_back({{"label", pr.label},
                     {"measure_diameter_m", part.measure_diameter_m},
                     {"measure_height_m", part.measure_height_m},
                     {"simulated_diameter_m", part.simulated_diameter_m},
                     {"simulated_height_m", part.simulated_height_m},
                     {"scale", part.scale},
                     {"representative", part.scale < 1.0},
                     {"full_size_particles_expected", part.full_size_particles},
                     {"cut_off_m", part.cut_off_m},
                     {"cut_off_percent_of_mass", part.cut_off_percent},
                     {"packing_density", pr.packing},
                     {"packing_density_whole_particles", pr.packing_whole},
                     {"packing_density_simulated_measure", pr.packing_simulated},
                     {"packing_density_core", pr.packing_core},
                     {"particles", pr.particles},
                     {"packing_density_statistics", to_json(pr.packing_stats)},
                     {"packing_density_whole_particles_statistics", to_json(pr.packing_whole_stats)},
                     {"wall_clock_s", pr.wall_clock_s},
                     {"time", to_json(pr.timing)}});
  }
  nlohmann::json lab = nullptr;
  if (r.lab_value)
    lab = p.test == LabTestKind::C29 ? nlohmann::json{{"bulk_density_kg_m3", *r.lab_value}, {"method", p.method}}
                                     : nlohmann::json{{"uncompacted_voids_percent", *r.lab_value}, {"method", p.method}};
  nlohmann::json out{{"aggpack_version", kVersion},
                     {"test", std::string(name_of(kLabTestNames, p.test))},
                     {"standard", p.standard},
                     {"method", p.method},
                     {"material", to_json(p.material)},
                     {"nominal_maximum_size_m", p.nominal_maximum_size_m},
                     {"measure", p.measure_name},
                     {"seeds", r.seeds},
                     {"parts", parts},
                     {"packing_density", to_json(r.packing)},
                     {"voids_percent", r.voids_percent},
                     {"voids_sd_percent", r.voids_sd_percent},
                     {"strike_off", "exact cut at the rim"},
                     {"lab", lab},
                     {"modelling", p.modelling},
                     {"wall_clock_s", r.wall_clock_s}};
  if (p.test == LabTestKind::C29) {
    out["bulk_density_kg_m3"] = r.bulk_density_kg_m3;
    out["bulk_density_sd_kg_m3"] = r.bulk_density_sd_kg_m3;
    out["water_density_kg_m3"] = kWaterDensity;
  }
  return out;
}

std::string describe(const LabTestResult& r) {
  const LabTestPlan& p = r.plan;
  std::string out = fmt::format("{} {} of {} in the {} ({} seed{}):\n", p.standard, p.method, p.material.name,
                                p.measure_name, r.seeds.size(), r.seeds.size() == 1 ? "" : "s");
  const double sd = r.packing.sd;
  if (p.test == LabTestKind::C29) {
    out += fmt::format("  bulk density {} kg/m3 ({:.1f} lb/ft3), voids {} %, packing fraction {}\n",
                       with_spread(r.bulk_density_kg_m3, r.bulk_density_sd_kg_m3, "{:.0f}"),
                       r.bulk_density_kg_m3 / kKgPerM3InLbPerFt3, with_spread(r.voids_percent, r.voids_sd_percent, "{:.1f}"),
                       with_spread(r.packing.mean, sd, "{:.4f}"));
    if (r.lab_value)
      out += fmt::format("  lab: {:.0f} kg/m3 ({}), voids {:.1f} %\n", *r.lab_value, p.method,
                         voids_percent(p.material, *r.lab_value));
  } else {
    out += fmt::format("  uncompacted voids U {} %, packing fraction {}\n",
                       with_spread(r.voids_percent, r.voids_sd_percent, "{:.1f}"), with_spread(r.packing.mean, sd, "{:.4f}"));
    if (r.lab_value) out += fmt::format("  lab: U = {:.1f} % (method {})\n", *r.lab_value, p.method);
  }
  for (std::size_t i = 0; i < r.parts.size(); ++i) {
    const LabTestPartResult& pr = r.parts[i];
    const LabTestPart& part = p.parts[i];
    out += fmt::format("  {}: packing {} (whole particles below the rim: {}), {} particles{}\n", pr.label,
                       with_spread(pr.packing_stats.mean, pr.packing_stats.sd, "{:.4f}"),
                       with_spread(pr.packing_whole_stats.mean, pr.packing_whole_stats.sd, "{:.4f}"),
                       pr.particles.empty() ? 0 : pr.particles.front(),
                       part.scale < 1.0 ? fmt::format(" in a representative measure {:.1f} mm across (x {:.3f})",
                                                      part.simulated_diameter_m * 1e3, part.scale)
                                        : "");
  }
  for (const std::string& m : p.modelling) out += fmt::format("  note: {}\n", m);
  return out;
}

}  // namespace aggpack
