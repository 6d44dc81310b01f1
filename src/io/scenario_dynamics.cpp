// The stages' tables: [material], [dynamics], [deposition], [pour], [tapping], [rodding] and [jigging].
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "aggpack/dynamics/contact_law_registry.hpp"
#include "scenario_tables.hpp"

namespace aggpack {

namespace {

// rolling_model and the spring-dashpot's coefficients, which apply to that model alone.
void read_rolling_model(const TomlSection& s, ContactParameters& c) {
  c.rolling_model = s.choice("rolling_model", kRollingModelNames).value_or(c.rolling_model);
  if (c.rolling_model != RollingModel::SpringDashpot) {
    for (const char* k : {"rolling_stiffness", "rolling_damping"})
      if (s.has(k)) s.fail(k, "applies only with rolling_model = \"spring_dashpot\"");
    return;
  }
  c.rolling_stiffness = s.number("rolling_stiffness", kPositive).value_or(c.rolling_stiffness);
  if (!(c.rolling_stiffness > 0.0))
    s.fail("rolling_stiffness", "is required with rolling_model = \"spring_dashpot\" (the rolling spring's k_roll, N/m)");
  c.rolling_damping = s.number("rolling_damping", kNonNegative).value_or(c.rolling_damping);
}

}  // namespace

void read_contact_keys(const TomlSection& s, ContactParameters& c) {
  c.youngs_modulus = s.number("youngs_modulus", kPositive).value_or(c.youngs_modulus);
  c.poisson_ratio = s.number("poisson_ratio", kPoissonRatio).value_or(c.poisson_ratio);
  c.friction_particle = s.number("friction_particle", kNonNegative).value_or(c.friction_particle);
  c.friction_wall = s.number("friction_wall", kNonNegative).value_or(c.friction_wall);
  c.restitution = s.number("restitution", kFraction).value_or(c.restitution);
  c.rolling_friction = s.number("rolling_friction", kNonNegative).value_or(c.rolling_friction);
}

Material read_material(const TomlSection& s, Material base) {
  s.allow_only({"file", "density", "youngs_modulus", "poisson_ratio", "wall_youngs_modulus", "wall_poisson_ratio",
                "friction_particle", "friction_wall", "restitution", "rolling_friction", "rolling_model",
                "rolling_stiffness", "rolling_damping"});
  Material m = std::move(base);
  ContactParameters& c = m.contact;
  m.file = s.string("file").value_or("");  // applied before (apply_material_files): kept for the echo
  m.density = s.number("density", kPositive).value_or(m.density);
  c.wall_youngs_modulus = s.number("wall_youngs_modulus", kPositive).value_or(c.wall_youngs_modulus);
  c.wall_poisson_ratio = s.number("wall_poisson_ratio", kPoissonRatio).value_or(c.wall_poisson_ratio);
  read_contact_keys(s, c);
  read_rolling_model(s, c);
  return m;
}

DynamicsStage read_dynamics(const TomlSection& s, Material& material) {
  s.allow_only({"friction_model", "time_step", "time_step_safety", "max_time", "sample_interval", "quiet_window",
                "quiet_kinetic_fraction", "density_tolerance", "layers", "skin", "gravity",
                "allow_unstable_time_step", "engine", "lammps_ranks", "lammps_binary"});
  DynamicsStage d;
  d.engine = s.choice("engine", kDemEngineNames).value_or(d.engine);
  d.lammps_ranks = static_cast<int>(s.integer("lammps_ranks", 1, 4096).value_or(d.lammps_ranks));
  d.lammps_binary = s.string("lammps_binary").value_or(d.lammps_binary);
  if (d.engine != DemEngine::Lammps)
    for (const char* k : {"lammps_ranks", "lammps_binary"})
      if (s.has(k)) s.fail(k, "applies only with engine = \"lammps\"");
  std::vector<std::string_view> laws;
  for (const ContactLawEntry& law : contact_laws()) laws.push_back(law.name);
  material.contact.friction_model = s.choice("friction_model", laws).value_or(material.contact.friction_model);
  d.time_step.fixed = s.number("time_step", {0.0, 1.0, true, false});
  d.time_step.safety = s.number("time_step_safety", {0.0, 1.0, true, false}).value_or(d.time_step.safety);
  QuietCriterion& q = d.quiet;
  q.max_time = s.number("max_time", {0.0, 1e4, true, false}).value_or(q.max_time);
  q.sample_interval = s.number("sample_interval", {0.0, 1e3, true, false}).value_or(q.sample_interval);
  q.window = s.number("quiet_window", kPositive).value_or(q.window);
  if (q.window < q.sample_interval)
    s.fail("quiet_window", fmt::format("{} s is shorter than the sample interval {} s; expected at least one "
                                       "sample interval", q.window, q.sample_interval));
  q.kinetic_fraction = s.number("quiet_kinetic_fraction", kPositive).value_or(q.kinetic_fraction);
  q.density_tolerance = s.number("density_tolerance", kPositive).value_or(q.density_tolerance);
  d.layers = static_cast<std::size_t>(s.integer("layers", 1, 10'000).value_or(1));
  d.dem.skin = s.length("skin").value_or(d.dem.skin);
  d.allow_unstable_time_step = s.boolean("allow_unstable_time_step").value_or(false);
  d.dem.gravity = {0.0, 0.0, -s.number("gravity", kPositive).value_or(-d.dem.gravity.z)};
  return d;
}

DepositionSettings read_deposition(const TomlSection& s, const Container& container) {
  s.allow_only({"method", "tolerance", "max_events", "max_redrops", "fill_height"});
  s.choice("method", {"drop_and_roll"});
  DepositionSettings d;
  d.tolerance = s.number("tolerance", {0.0, 1e-3, true, false}).value_or(d.tolerance);
  d.max_events = static_cast<std::size_t>(s.integer("max_events", 10, 1'000'000).value_or(
      static_cast<std::int64_t>(d.max_events)));
  d.max_redrops = static_cast<std::size_t>(s.integer("max_redrops", 0, 1'000'000).value_or(
      static_cast<std::int64_t>(d.max_redrops)));
  d.fill_height = s.length("fill_height").value_or(container.height());
  if (d.fill_height > container.height())
    s.fail("fill_height", fmt::format("{:.6g} m is above the container height ({:.6g} m)", d.fill_height,
                                      container.height()));
  return d;
}

PourSettings read_pour(const TomlSection& s) {
  s.allow_only({"solid_fraction", "batches", "velocity", "gap", "release_height"});
  PourSettings p;
  p.solid_fraction = s.number("solid_fraction", {0.0, 0.3, true, false}).value_or(p.solid_fraction);
  p.batches = static_cast<std::size_t>(s.integer("batches", 1, 10000).value_or(1));
  p.velocity = s.number("velocity", {0.0, 100.0, false, false}).value_or(p.velocity);
  // No gap is allowed: the gas's spheres lie inside their slab, so none starts in the bed.
  p.gap = s.length("gap", kNonNegative);
  p.release_height = s.length("release_height", kNonNegative);
  return p;
}

TappingSettings read_tapping(const TomlSection& s) {
  s.allow_only({"taps", "intensity", "frequency", "rest_time", "rest_until_quiet"});
  TappingSettings t;
  t.taps = static_cast<std::size_t>(s.integer("taps", 1, 100000).value_or(static_cast<std::int64_t>(t.taps)));
  t.intensity = s.number("intensity", {0.0, 100.0, true, false}).value_or(t.intensity);
  t.frequency = s.number("frequency", {0.0, 10000.0, true, false}).value_or(t.frequency);
  t.rest_time = s.number("rest_time", {0.0, 100.0, true, false}).value_or(t.rest_time);
  t.rest_until_quiet = s.boolean("rest_until_quiet").value_or(t.rest_until_quiet);
  return t;
}

RoddingSettings read_rodding(const TomlSection& s) {
  s.allow_only({"strokes", "rod_diameter", "speed", "depth", "floor_clearance", "penetration", "wall_clearance",
                "start_gap", "max_force", "rest_time", "rest_until_quiet"});
  RoddingSettings r;
  r.strokes = static_cast<std::size_t>(s.integer("strokes", 1, 10000).value_or(static_cast<std::int64_t>(r.strokes)));
  r.rod_diameter = s.length("rod_diameter").value_or(r.rod_diameter);
  r.speed = s.number("speed", {0.0, 100.0, true, false}).value_or(r.speed);
  r.depth = s.choice("depth", kRodDepthNames).value_or(r.depth);
  r.floor_clearance = s.length("floor_clearance", kNonNegative).value_or(r.floor_clearance);
  r.penetration = s.length("penetration", kNonNegative).value_or(r.penetration);
  r.wall_clearance = s.length("wall_clearance", kNonNegative).value_or(r.wall_clearance);
  r.start_gap = s.length("start_gap", kNonNegative).value_or(r.start_gap);
  r.max_force = s.number("max_force", kPositive).value_or(r.max_force);
  r.rest_time = s.number("rest_time", {0.0, 100.0, false, false}).value_or(r.rest_time);
  r.rest_until_quiet = s.boolean("rest_until_quiet").value_or(r.rest_until_quiet);
  return r;
}

JiggingSettings read_jigging(const TomlSection& s) {
  s.allow_only({"drops", "height", "lift_acceleration", "rest_time", "rest_until_quiet"});
  JiggingSettings j;
  j.drops = static_cast<std::size_t>(s.integer("drops", 1, 100000).value_or(static_cast<std::int64_t>(j.drops)));
  j.height = s.length("height").value_or(j.height);
  j.lift_acceleration = s.number("lift_acceleration", {0.0, 1e4, true, false}).value_or(j.lift_acceleration);
  j.rest_time = s.number("rest_time", {0.0, 100.0, true, false}).value_or(j.rest_time);
  j.rest_until_quiet = s.boolean("rest_until_quiet").value_or(j.rest_until_quiet);
  return j;
}

}  // namespace aggpack
