// The scenario with every value resolved, in SI units, as summary.json echoes it.
#include <variant>

#include "aggpack/core/overloaded.hpp"
#include "scenario_tables.hpp"

namespace aggpack {

nlohmann::json grading_source_json(const GradingSource& gs) {
  nlohmann::json out{{"key", gs.key}, {"grading", gs.grading.name}};
  for (const Sieve& s : gs.grading.sieves)
    out["sieves"].push_back({{"sieve", s.name}, {"opening_m", s.opening}, {"percent_passing", s.percent_passing}});
  if (gs.d_min) out["d_min_m"] = *gs.d_min;
  if (gs.d_max) out["d_max_m"] = *gs.d_max;
  if (gs.band) out["band"] = gs.band->name;
  return out;
}

namespace {

nlohmann::json particles_json(const ParticleSource& particles) {
  nlohmann::json p;
  if (particles.file) {
    p["from"] = particles.file->string();
    p["length_unit_m"] = particles.file_length_unit;
    p["boundary_overlap_tolerance"] = particles.boundary_overlap_tolerance;
    if (particles.file_timestep) p["timestep"] = *particles.file_timestep;
  }
  if (particles.sizes) {
    const SizeSpec& spec = *particles.sizes;
    for (const auto& c : spec.classes) {
      nlohmann::json cj{{"diameter_m", c.diameter}};
      if (c.count) cj["count"] = *c.count;
      if (c.volume_fraction) cj["volume_fraction"] = *c.volume_fraction;
      p["classes"].push_back(cj);
    }
    if (spec.total_count) p["count"] = *spec.total_count;
    if (spec.solid_volume) p["solid_volume_m3"] = *spec.solid_volume;
    p["order"] = name_of(kSizeOrderNames, spec.order);
  }
  if (const auto& g = particles.graded) {
    p["gradings"] = nlohmann::json::array({grading_source_json(g->main)});  // {x} alone is x itself under clang
    if (g->fine) {
      p["gradings"].push_back(grading_source_json(*g->fine));
      p["ca_fa"] = g->ca_fa;
    }
    p["sampling"] = name_of(kSamplingModeNames, g->sampling);
    p["order"] = name_of(kMixOrderNames, g->order);
    if (g->amount.count) p["count"] = *g->amount.count;
    if (g->amount.solid_volume) p["solid_volume_m3"] = *g->amount.solid_volume;
    if (g->fill_height) {
      p["fill_height_m"] = *g->fill_height;
      p["expected_density"] = g->expected_density;
    }
  }
  return p;
}

// [deposition], [pour] and [tapping], those given.
void add_placing_stages(nlohmann::json& j, const Scenario& sc) {
  if (sc.deposition) {
    const DepositionSettings& d = *sc.deposition;
    j["deposition"] = {{"method", "drop_and_roll"},
                       {"tolerance", d.tolerance},
                       {"max_events", d.max_events},
                       {"max_redrops", d.max_redrops},
                       {"fill_height_m", d.fill_height}};
  }
  if (sc.pour) {
    const PourSettings& pour = *sc.pour;
    j["pour"] = {{"solid_fraction", pour.solid_fraction}, {"batches", pour.batches}, {"velocity_m_s", pour.velocity}};
    if (pour.release_height) j["pour"]["release_height_m"] = *pour.release_height;
    if (pour.gap) j["pour"]["gap_m"] = *pour.gap;
  }
  if (sc.tapping) {
    const TappingSettings& t = *sc.tapping;
    j["tapping"] = {{"taps", t.taps},
                    {"intensity", t.intensity},
                    {"frequency_hz", t.frequency},
                    {"rest_time_s", t.rest_time},
                    {"rest_until_quiet", t.rest_until_quiet}};
  }
  if (sc.rodding) {
    const RoddingSettings& r = *sc.rodding;
    j["rodding"] = {{"strokes", r.strokes},
                    {"rod_diameter_m", r.rod_diameter},
                    {"speed_m_s", r.speed},
                    {"depth", std::string(name_of(kRodDepthNames, r.depth))},
                    {"floor_clearance_m", r.floor_clearance},
                    {"penetration_m", r.penetration},
                    {"wall_clearance_m", r.wall_clearance},
                    {"start_gap_m", r.start_gap},
                    {"max_force_n", r.max_force},
                    {"rest_time_s", r.rest_time},
                    {"rest_until_quiet", r.rest_until_quiet}};
  }
  if (sc.jigging) {
    const JiggingSettings& g = *sc.jigging;
    j["jigging"] = {{"drops", g.drops},
                    {"height_m", g.height},
                    {"lift_acceleration_m_s2", g.lift_acceleration},
                    {"rest_time_s", g.rest_time},
                    {"rest_until_quiet", g.rest_until_quiet}};
  }
}

nlohmann::json dynamics_json(const DynamicsStage& d, const Material& material) {
  const QuietCriterion& q = d.quiet;
  nlohmann::json j = {{"friction_model", material.contact.friction_model},
                      {"time_step_safety", d.time_step.safety},
                      {"max_time_s", q.max_time},
                      {"sample_interval_s", q.sample_interval},
                      {"quiet_window_s", q.window},
                      {"quiet_kinetic_fraction", q.kinetic_fraction},
                      {"density_tolerance", q.density_tolerance},
                      {"layers", d.layers},
                      {"gravity_m_s2", -d.dem.gravity.z}};
  if (d.time_step.fixed) j["time_step_s"] = *d.time_step.fixed;
  if (d.allow_unstable_time_step) j["allow_unstable_time_step"] = true;
  if (d.engine == DemEngine::Lammps) {
    j["engine"] = "lammps";
    j["lammps_ranks"] = d.lammps_ranks;
    j["lammps_binary"] = d.lammps_binary;
  }
  if (d.dem.skin > 0.0) j["skin_m"] = d.dem.skin;
  return j;
}

}  // namespace

nlohmann::json material_json(const Material& m) {
  const ContactParameters& c = m.contact;
  nlohmann::json j = {{"density_kg_m3", m.density},
          {"youngs_modulus_pa", c.youngs_modulus},
          {"poisson_ratio", c.poisson_ratio},
          {"wall_youngs_modulus_pa", c.wall_youngs_modulus},
          {"wall_poisson_ratio", c.wall_poisson_ratio},
          {"friction_particle", c.friction_particle},
          {"friction_wall", c.friction_wall},
          {"restitution", c.restitution},
          {"rolling_friction", c.rolling_friction}};
  // Written for the spring-dashpot model only: the summaries of the default model stay as they were.
  if (c.rolling_model == RollingModel::SpringDashpot) {
    j["rolling_model"] = name_of(kRollingModelNames, c.rolling_model);
    j["rolling_stiffness_n_m"] = c.rolling_stiffness;
    j["rolling_damping_n_s_m"] = c.rolling_damping;
  }
  if (!m.file.empty()) j["file"] = m.file.string();
  return j;
}

namespace {

// A run of several materials: each named one (its index, 1 on: 0 is [material], "default"),
// the pairs given their own coefficients, and the material of each component of [particles].
void add_materials(nlohmann::json& j, const Scenario& sc) {
  for (std::size_t k = 1; k < material_count(sc); ++k) {
    nlohmann::json m = material_json(material_of(sc, k));
    m.erase("wall_youngs_modulus_pa");
    m.erase("wall_poisson_ratio");
    m["index"] = k;
    j["materials"][material_name(sc, k)] = std::move(m);
  }
  for (const MaterialPairCoefficients& p : sc.material_pairs) {
    nlohmann::json pair = {{"materials", {material_name(sc, p.first), material_name(sc, p.second)}}};
    if (p.friction) pair["friction"] = *p.friction;
    if (p.restitution) pair["restitution"] = *p.restitution;
    if (p.rolling_friction) pair["rolling_friction"] = *p.rolling_friction;
    if (p.rolling_stiffness) pair["rolling_stiffness_n_m"] = *p.rolling_stiffness;
    if (p.rolling_damping) pair["rolling_damping_n_s_m"] = *p.rolling_damping;
    j["material_pairs"].push_back(std::move(pair));
  }
  nlohmann::json& components = j["particles"]["component_materials"] = nlohmann::json::array();
  for (const std::uint8_t m : sc.particles.component_material) components.push_back(material_name(sc, m));
}

nlohmann::json analysis_json(const AnalysisSettings& analysis) {
  nlohmann::json j = {{"box_sides_m", analysis.box_sides},
                      {"placement", "centered"},
                      {"contact_tolerance", analysis.contact_tolerance}};
  if (analysis.slice_thickness) j["slice_thickness_m"] = *analysis.slice_thickness;
  if (analysis.shell_thickness) j["shell_thickness_m"] = *analysis.shell_thickness;
  return j;
}

nlohmann::json output_json(const OutputSettings& output) {
  nlohmann::json formats = nlohmann::json::array();
  for (const auto& [format, name] : kOutputFormatNames)
    if (format_flag(output, format)) formats.push_back(name);
  nlohmann::json j = {{"directory", output.directory.string()},
                      {"formats", formats},
                      {"vtp_encoding", output.vtp_encoding == VtpEncoding::Ascii ? "ascii" : "binary"},
                      {"checkpoint", output.checkpoint},
                      {"checkpoint_every_s", output.checkpoint_every}};
  if (output.frame_interval) j["frame_interval_s"] = *output.frame_interval;
  return j;
}

}  // namespace

nlohmann::json to_json(const Protocol& protocol) {
  nlohmann::json steps = nlohmann::json::array();
  for (const Step& step : protocol.steps)
    std::visit(Overloaded{[&](const DepositStep& d) {
                            steps.push_back({{"step", "deposit"}, {"layer", d.layer}, {"layers", d.layers}});
                          },
                          [&](const PourStep& d) {
                            steps.push_back({{"step", "pour"}, {"layer", d.layer}, {"layers", d.layers}});
                          },
                          [&](const SettleStep& st) { steps.push_back({{"step", "settle"}, {"layer", st.layer}}); },
                          [&](const TapStep&) { steps.push_back({{"step", "tap"}}); },
                          [&](const RodStep&) { steps.push_back({{"step", "rod"}}); },
                          [&](const JigStep&) { steps.push_back({{"step", "jig"}}); },
                          [&](const AnalyseStep& a) { steps.push_back({{"step", "analyse"}, {"name", a.report_as}}); },
                          [&](const SnapshotStep& snap) { steps.push_back({{"step", "snapshot"}, {"name", snap.name}}); },
                          [&](const ExportLammpsStep& x) { steps.push_back({{"step", "export_lammps"}, {"name", x.name}}); },
                          [&](const ImportLammpsStep& x) {
                            nlohmann::json j{{"step", "import_lammps"}, {"file", x.file.string()}};
                            if (x.timestep) j["timestep"] = *x.timestep;
                            steps.push_back(std::move(j));
                          }},
               step.kind);
  return steps;
}

nlohmann::json to_json(const Scenario& sc) {
  nlohmann::json j;
  if (sc.protocol) j["protocol"] = to_json(*sc.protocol);
  j["title"] = sc.title;
  j["seed"] = sc.seed;
  j["file"] = sc.file.string();
  const ContainerSides sides = sc.container.periodic ? ContainerSides::Periodic : ContainerSides::Walls;
  // A box's echo is as it was before shapes (no "shape" key: box is the default).
  if (sc.container.is_cylinder())
    j["container"] = {{"shape", name_of(kContainerShapeNames, sc.container.shape)},
                      {"diameter_m", sc.container.length_x()},
                      {"height_m", sc.container.height()},
                      {"rim_m", sc.container.rim}};
  else
    j["container"] = {{"side_m", sc.container.length_x()},
                      {"height_m", sc.container.height()},
                      {"sides", name_of(kContainerSidesNames, sides)}};
  j["particles"] = particles_json(sc.particles);
  add_placing_stages(j, sc);
  if (sc.dynamics) j["dynamics"] = dynamics_json(*sc.dynamics, sc.material);
  j["material"] = material_json(sc.material);
  if (!sc.materials.empty()) add_materials(j, sc);
  j["analysis"] = analysis_json(sc.analysis);
  j["output"] = output_json(sc.output);
  for (const DemCalibrationFile& c : sc.calibrations)
    j["calibrated_by"].push_back({{"file", c.file.string()}, {"assignments", c.assignments}, {"fitted_to", c.fitted_to}});
  return j;
}

}  // namespace aggpack
