// A material file as `aggpack material` shows it: JSON (to_json) and lines for a reader
// (describe), both from the same values.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "aggpack/io/material_file.hpp"
#include "aggpack/sizes/grading.hpp"
#include "scenario_tables.hpp"

namespace aggpack {

namespace {

nlohmann::json shape_json(const AggregateMaterial& m) {
  nlohmann::json j = {{"name", m.shape_name}};
  if (!m.shape) return j;
  const GrainShapeSpec& s = *m.shape;
  j["family"] = family_name(s.family);
  j["spheres"] = s.spheres;
  if (s.family == GrainFamily::Angular) j["corners"] = s.corners;
  j["templates"] = s.templates;
  j["elongation_mean"] = s.proportions.elongation_mean;  // I/L
  j["elongation_spread"] = s.proportions.elongation_spread;
  j["flatness_mean"] = s.proportions.flatness_mean;  // S/I
  j["flatness_spread"] = s.proportions.flatness_spread;
  if (s.target) {
    j["target"] = {{"measure", measure_name(s.target->measure)}, {"percent", s.target->percent}};
    if (s.target->measure == ShapeMeasure::FlatAndElongated) j["target"]["ratio"] = s.target->ratio;
  }
  return j;
}

nlohmann::json grading_json(const GradingSource& g) {
  nlohmann::json j = grading_source_json(g);
  j["maximum_size_m"] = maximum_size(g.grading);
  j["nominal_maximum_size_m"] = nominal_maximum_size(g.grading);
  j["fineness_modulus"] = fineness_modulus(g.grading);
  return j;
}

nlohmann::json lab_json(const AggregateMaterial& m) {
  nlohmann::json j = nlohmann::json::object();
  if (m.c29) {
    const double voids = voids_percent(m, m.c29->kg_per_m3);
    j["c29"] = {{"bulk_density_kg_m3", m.c29->kg_per_m3},
                {"bulk_density_lb_ft3", m.c29->kg_per_m3 / kKgPerM3PerLbPerFt3},
                {"method", name_of(kC29MethodNames, m.c29->method)},
                {"voids_percent", voids},
                {"packing_fraction", 1.0 - voids / 100.0}};
  }
  if (m.c1252)
    j["c1252"] = {{"voids_percent", m.c1252->percent},
                  {"method", name_of(kC1252MethodNames, m.c1252->method)},
                  {"packing_fraction", 1.0 - m.c1252->percent / 100.0}};
  return j;
}

std::string sieve_lines(const Grading& grading) {
  std::string lines;
  for (auto s = grading.sieves.rbegin(); s != grading.sieves.rend(); ++s)
    lines += fmt::format("    {:>8}  {:8.3f} mm  {:6.1f} %\n", s->name, 1e3 * s->opening, s->percent_passing);
  return lines;
}

std::string shape_line(const AggregateMaterial& m) {
  if (!m.shape) return "spheres";
  const GrainShapeSpec& s = *m.shape;
  std::string line = m.shape_name.empty() ? std::string(family_name(s.family))
                                          : fmt::format("{} ({})", m.shape_name, family_name(s.family));
  line += fmt::format(", I/L {:.2f} ± {:.2f}, S/I {:.2f} ± {:.2f}, {} spheres per grain, {} templates",
                      s.proportions.elongation_mean, s.proportions.elongation_spread, s.proportions.flatness_mean,
                      s.proportions.flatness_spread, s.spheres, s.templates);
  if (s.target) line += fmt::format(", fitted to {} {:g} %", measure_name(s.target->measure), s.target->percent);
  return line;
}

std::string lab_lines(const AggregateMaterial& m) {
  std::string lines;
  if (m.c29) {
    const double voids = voids_percent(m, m.c29->kg_per_m3);
    lines += fmt::format("  ASTM C29 bulk density ({}): {:.1f} kg/m3 ({:.2f} lb/ft3): voids {:.2f} %, packing "
                         "fraction {:.4f}\n",
                         name_of(kC29MethodNames, m.c29->method), m.c29->kg_per_m3,
                         m.c29->kg_per_m3 / kKgPerM3PerLbPerFt3, voids, 1.0 - voids / 100.0);
  }
  if (m.c1252)
    lines += fmt::format("  ASTM C1252 uncompacted voids (method {}): {:.2f} %, packing fraction {:.4f}\n",
                         name_of(kC1252MethodNames, m.c1252->method), m.c1252->percent, 1.0 - m.c1252->percent / 100.0);
  if (!m.c29 && !m.c1252) lines += "  lab results: none\n";
  return lines;
}

}  // namespace

nlohmann::json to_json(const AggregateMaterial& m) {
  nlohmann::json j = {{"file", m.file.string()},
                      {"name", m.name},
                      {"specific_gravity", m.specific_gravity},
                      {"specific_gravity_basis", name_of(kSpecificGravityBasisNames, m.basis)},
                      {"specific_gravity_oven_dry", oven_dry_specific_gravity(m)},
                      {"particle_density_kg_m3", oven_dry_particle_density(m)},
                      {"grading", grading_json(m.grading)},
                      {"shape", shape_json(m)},
                      {"lab", lab_json(m)},
                      {"calibration", m.calibration}};
  if (!m.notes.empty()) j["notes"] = m.notes;
  if (m.absorption_percent) j["absorption_percent"] = *m.absorption_percent;
  nlohmann::json contact = material_json(m.material);
  for (const char* k : {"density_kg_m3", "wall_youngs_modulus_pa", "wall_poisson_ratio"}) contact.erase(k);
  j["contact"] = std::move(contact);
  return j;
}

std::string describe(const AggregateMaterial& m) {
  const Grading& g = m.grading.grading;
  const ContactParameters& c = m.material.contact;
  std::string text = fmt::format("{}: {}\n", m.file.string(), m.name);
  if (!m.notes.empty()) text += fmt::format("  {}\n", m.notes);
  text += fmt::format("  bulk specific gravity {:.3f} ({}", m.specific_gravity, name_of(kSpecificGravityBasisNames, m.basis));
  if (m.absorption_percent) text += fmt::format(", absorption {:.2f} %", *m.absorption_percent);
  text += fmt::format("); oven-dry {:.4f}: particle density {:.1f} kg/m3\n", oven_dry_specific_gravity(m),
                      oven_dry_particle_density(m));
  text += fmt::format("  grading {}: nominal maximum size {:.3g} mm (maximum size {:.3g} mm), fineness modulus {:.2f}\n",
                      g.name, 1e3 * nominal_maximum_size(g), 1e3 * maximum_size(g), fineness_modulus(g));
  if (m.grading.d_min || m.grading.d_max)
    text += fmt::format("    cut-offs: {} .. {}\n", m.grading.d_min ? fmt::format("{:.4g} mm", 1e3 * *m.grading.d_min) : "-",
                        m.grading.d_max ? fmt::format("{:.4g} mm", 1e3 * *m.grading.d_max) : "-");
  text += sieve_lines(g);
  text += fmt::format("  shape: {}\n", shape_line(m));
  text += fmt::format("  contact: friction {:g} (walls {:g}), rolling friction {:g}, restitution {:g}, Young's modulus "
                      "{:.3g} Pa, Poisson's ratio {:g}\n",
                      c.friction_particle, c.friction_wall, c.rolling_friction, c.restitution, c.youngs_modulus,
                      c.poisson_ratio);
  text += lab_lines(m);
  if (!m.calibration.is_null()) text += fmt::format("  calibration: {}\n", m.calibration.dump());
  return text;
}

}  // namespace aggpack
