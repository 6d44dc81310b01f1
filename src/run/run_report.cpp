#include "aggpack/run/run_report.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <limits>
#include <type_traits>
#include <variant>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "aggpack/run/calibration_file.hpp"
#include "aggpack/analysis/bulk_density.hpp"
#include "aggpack/core/units.hpp"
#include "aggpack/core/version.hpp"
#include "aggpack/run/checkpoint.hpp"
#include "aggpack/run/grading_report.hpp"
#include "aggpack/run/run_grains.hpp"

namespace aggpack {

std::uint64_t bed_fingerprint(const ParticleStore& bed) {
  return input_fingerprint(bed, {});  // the positions' and radii's bytes, as a checkpoint's input is told
}

std::string frame_file_name(std::size_t number) { return fmt::format("frames/frame_{:05}.vtp", number); }

namespace {

// What a bed's particles are, in words: "spheres", "grains", or "grains and spheres".
std::string_view kinds_of_particles(const ParticleStore& bed) {
  if (bed.bodies.empty()) return "spheres";
  const bool any_sphere = std::any_of(bed.body.begin(), bed.body.end(), [](std::uint32_t b) { return b == kNoBody; });
  return any_sphere ? "grains and spheres" : "grains";
}

// Each component's grains as the bed's measure them, beside what was asked (and, with a lab
// measure, what the templates gave): the shape is a modelling choice the console shows.
std::string grain_lines(const RunReport& r) {
  if (r.grain_libraries.is_null() || r.particles.bodies.empty()) return {};
  std::string out;
  auto o = std::back_inserter(out);
  for (const nlohmann::json& c : bed_grains_json(r.grain_libraries, r.particles, r.grain_shape_component)) {
    const nlohmann::json& bed = c["bed"];
    fmt::format_to(o, "  grains of {} ({}, {} spheres each): {} in the bed, elongation I/L {:.3f} (asked {:.3f}), "
                      "flatness S/I {:.3f} (asked {:.3f})\n",
                   c.value("key", fmt::format("component {}", c["component"].get<int>())),
                   c["family"].get<std::string>(), c["spheres"].get<int>(), bed["grains"].get<int>(),
                   bed["mean_elongation"].is_number() ? bed["mean_elongation"].get<double>() : std::numeric_limits<double>::quiet_NaN(),
                   c["elongation"]["mean"].get<double>(),
                   bed["mean_flatness"].is_number() ? bed["mean_flatness"].get<double>() : std::numeric_limits<double>::quiet_NaN(),
                   c["flatness"]["mean"].get<double>());
    if (!c.contains("target")) continue;
    const nlohmann::json& target = c["target"];
    const std::string measure = target["measure"].get<std::string>();
    std::string bed_key = measure.starts_with("flakiness") ? "flakiness_index_percent"
                          : measure.starts_with("shape")   ? "shape_index_percent"
                                                           : "";
    if (bed_key.empty()) {  // flat and elongated: the bed measures 2, 3 and 5 to 1
      const double ratio = target.value("ratio", 3.0);
      if (ratio == 2.0 || ratio == 3.0 || ratio == 5.0) bed_key = fmt::format("flat_elongated_{:g}_to_1_percent", ratio);
    }
    const std::string in_bed = !bed_key.empty() && bed.contains(bed_key) && bed[bed_key].is_number()
                                   ? fmt::format("{:.1f} %", bed[bed_key].get<double>())
                                   : "not measured";
    fmt::format_to(o, "    {}: {} in the bed, target {:g} % (the templates {:.1f} %)\n", measure, in_bed,
                   target["percent"].get<double>(), c["templates_percent"].get<double>());
  }
  return out;
}

}  // namespace

namespace {

// The grains' density for the bulk density: the material's, or of several materials the
// bed's mass over its solid volume.
double particle_density(const Scenario& sc, const ParticleStore& bed) {
  if (material_count(sc) == 1) return sc.material.density;
  double mass = 0.0, volume = 0.0;
  for (std::size_t i = 0; i < bed.size(); ++i) {
    mass += bed.mass[i];
    volume += 4.0 / 3.0 * std::numbers::pi * bed.radius[i] * bed.radius[i] * bed.radius[i];
  }
  return volume > 0.0 ? mass / volume : sc.material.density;
}

// An analysis as a stage's density and coordination keys.
void add_analysis(nlohmann::json& stage, const PackingReport& analysis) {
  stage["density"] = to_json(analysis.density);
  stage["coordination"] = to_json(analysis.coordination);
}

// A density, or "not measured" for the NaN of an analysis that was not made (an interrupted run's).
std::string density_text(double density) {
  return std::isnan(density) ? std::string("not measured") : fmt::format("{:.4f}", density);
}

// The kinds of the console summary's step lines.
enum class StepLine { deposit, pour, settle, tap, rod, jig, hand_over };

// The step lines in the order the steps ran (a protocol's own order; the stages' default
// order without one, and after it anything a protocol's steps did not account for).
std::vector<StepLine> step_line_order(const RunReport& r) {
  std::vector<StepLine> order;
  if (r.scenario.protocol) {
    for (const Step& step : r.scenario.protocol->steps)
      std::visit(
          [&](const auto& kind) {
            using Kind = std::decay_t<decltype(kind)>;
            if constexpr (std::is_same_v<Kind, DepositStep>) order.push_back(StepLine::deposit);
            if constexpr (std::is_same_v<Kind, PourStep>) order.insert(order.end(), {StepLine::pour, StepLine::settle});
            if constexpr (std::is_same_v<Kind, SettleStep>) order.push_back(StepLine::settle);
            if constexpr (std::is_same_v<Kind, TapStep>) order.push_back(StepLine::tap);
            if constexpr (std::is_same_v<Kind, RodStep>) order.push_back(StepLine::rod);
            if constexpr (std::is_same_v<Kind, JigStep>) order.push_back(StepLine::jig);
            if constexpr (std::is_same_v<Kind, ExportLammpsStep> || std::is_same_v<Kind, ImportLammpsStep>)
              order.push_back(StepLine::hand_over);
          },
          step.kind);
  }
  order.push_back(StepLine::deposit);
  order.insert(order.end(), r.pours.size(), StepLine::pour);
  order.push_back(StepLine::settle);
  order.insert(order.end(), r.tappings.size(), StepLine::tap);
  order.insert(order.end(), r.roddings.size(), StepLine::rod);
  order.insert(order.end(), r.jiggings.size(), StepLine::jig);
  order.insert(order.end(), r.lammps_exchanges.size(), StepLine::hand_over);
  return order;
}

std::string deposition_line(const DepositionReport& d) {
  return fmt::format("  deposition: {} of {} placed ({}), {:.3g} s, {:.3g} events per particle, {} redrops, {} ties\n",
                     d.stats.placed, d.requested, to_string(d.stats.end), d.wall_clock_s,
                     d.stats.placed ? static_cast<double>(d.stats.events) / static_cast<double>(d.stats.placed) : 0.0,
                     d.stats.redrops, d.stats.ties_on_top + d.stats.ties_on_ridge);
}

std::string pour_line(const PourReport& p, const Scenario& sc) {
  return fmt::format("  pour: {} particles inserted as a gas at solid fraction {:g} in {} batch{}, from {} to {} above "
                     "the floor\n",
                     p.poured, p.solid_fraction, p.batches, p.batches == 1 ? "" : "es",
                     length_text(p.lowest_slab_bottom - sc.container.bounds.lo.z, sc.written_length_unit),
                     length_text(p.highest_slab_top - sc.container.bounds.lo.z, sc.written_length_unit));
}

// Every settling run of the run in one line, and the density it added to a deposited bed.
std::string dynamics_lines(const RunReport& r) {
  const SettlingReport& d = *r.dynamics;
  const SettlingRun& last = d.runs.back();
  std::string out = fmt::format("  dynamics: {} ({}), {:.3g} s simulated in {} steps of {:.3g} s, {:.3g} s wall, "
                                "{:.3g} million particle-steps/s; overlap mean {:.2e}, max {:.2e}\n",
                                settle_end_name(last.ended_by), r.scenario.material.contact.friction_model,
                                d.simulated_time(), d.steps(), d.runs.front().time_step, d.wall_clock_s(),
                                1e-6 * d.particle_steps_per_second(), last.last.contacts.mean_overlap,
                                last.last.contacts.max_overlap);
  if (r.analyses.contains("deposition"))
    out += fmt::format("  density after deposition {:.4f}, after dynamics {}\n", r.density_after_deposition(),
                       density_text(r.density_after_dynamics()));
  return out;
}


std::string hand_over_line(const LammpsExchange& x) {
  if (x.direction == "import")
    return fmt::format("  import_lammps: {} spheres' positions from {} ({})\n", x.spheres, x.path, x.what);
  return fmt::format("  export_lammps: {} spheres and a deck ({}) in {}; run it there with lmp\n", x.spheres, x.what,
                     x.path);
}

// The steps' lines of the console summary, in the order the steps ran. Each kind's records
// are taken in turn; the lines that add up several steps (deposition, dynamics) stand at the
// first step of their kind.
std::string step_lines(const RunReport& r) {
  std::string out;
  bool deposition_told = false, dynamics_told = false;
  std::size_t next_pour = 0, next_tap = 0, next_rod = 0, next_jig = 0, next_exchange = 0;
  for (const StepLine line : step_line_order(r)) switch (line) {
      case StepLine::deposit:
        if (r.deposition && !deposition_told) out += deposition_line(*r.deposition), deposition_told = true;
        break;
      case StepLine::pour:
        if (next_pour < r.pours.size()) out += pour_line(r.pours[next_pour++], r.scenario);
        break;
      case StepLine::settle:
        if (r.dynamics && !dynamics_told) out += dynamics_lines(r), dynamics_told = true;
        break;
      case StepLine::tap:
        if (next_tap < r.tappings.size()) out += console_line(r.tappings[next_tap++]);
        break;
      case StepLine::rod:
        if (next_rod < r.roddings.size()) out += console_line(r.roddings[next_rod++]);
        break;
      case StepLine::jig:
        if (next_jig < r.jiggings.size()) out += console_line(r.jiggings[next_jig++]);
        break;
      case StepLine::hand_over:
        if (next_exchange < r.lammps_exchanges.size()) out += hand_over_line(r.lammps_exchanges[next_exchange++]);
        break;
    }
  return out;
}

}  // namespace

// Every modelling choice a result depends on, said in the output.
std::optional<RunReport::RestState> RunReport::rest_state() const {
  const bool moved = dynamics || !pours.empty() || !tappings.empty() || !roddings.empty() || !jiggings.empty();
  if (!moved || series.samples.empty() || !scenario.dynamics) return std::nullopt;
  RestState rest;
  rest.translational_energy_per_particle_mgd = series.samples.back().translational_per_particle_mgd;
  rest.quiet_below = scenario.dynamics->quiet.kinetic_fraction;
  rest.settled = rest.translational_energy_per_particle_mgd <= rest.quiet_below;
  return rest;
}

namespace {

// What a pour step's numbers depend on.
std::string pour_note(const PourReport& p, const Scenario& sc) {
  return fmt::format(
        "pour: {} particles inserted as a random non-overlapping gas at solid fraction {:g} in {} batch{} (slabs of "
        "the container's footprint from {:.4g} m to {:.4g} m above the floor, {:.3g} m above the bed's top; the next "
        "batch once the last has had the time to fall its slab's height), released at {:g} m/s downward, then fallen and settled by "
        "the DEM until quiet: the packing depends on these choices (drop height, fraction, batches) as a poured lab "
        "sample depends on how it is poured",
        p.poured, p.solid_fraction, p.batches, p.batches == 1 ? "" : "es", p.lowest_slab_bottom - sc.container.bounds.lo.z,
        p.highest_slab_top - sc.container.bounds.lo.z, p.gap, p.velocity);
}


// How far a particle file's spheres overlap the container and each other, where they do.
std::vector<std::string> particle_file_notes(const RunReport& r) {
  const Scenario& sc = r.scenario;
  std::vector<std::string> notes;
  if (sc.particles.file && r.largest_boundary_overlap > 0.0)
    notes.push_back(fmt::format("the particle file's spheres overlap the floor or walls by up to {:.3g} of their "
                                "radius (contacts of a settled bed; accepted up to "
                                "particles.boundary_overlap_tolerance = {:g})",
                                r.largest_boundary_overlap, sc.particles.boundary_overlap_tolerance));
  if (sc.particles.file && r.largest_pair_overlap > 1e-3)
    notes.push_back(fmt::format("the particle file's spheres overlap each other by up to {:.3g} of the smaller radius "
                                "({}; accepted up to {}): the volume they share is counted twice in the densities",
                                r.largest_pair_overlap,
                                sc.particles.soft_contacts ? "a soft-contact DEM bed, particles.soft_contacts"
                                                           : "contacts of a settled bed",
                                sc.particles.soft_contacts ? std::string("one centre inside the other sphere")
                                                           : fmt::format("particles.overlap_tolerance = {:g}",
                                                                         sc.particles.overlap_tolerance)));
  return notes;
}

}  // namespace

std::vector<std::string> RunReport::modelling_notes() const {
  const RunReport& r = *this;
  const Scenario& sc = r.scenario;
  std::vector<std::string> notes;
  const bool from_lammps = r.input_format.starts_with("LAMMPS");
  if (sc.particles.bed_from_caller())
    notes.push_back("particle positions were given by the caller (particles.from = \"-\"): " + r.input_format +
                    (r.dynamics ? "; the dynamics stage settled them from there" : "; no aggpack stage moved them"));
  else if (sc.particles.file)
    notes.push_back("particle positions were read from " + sc.particles.file->string() +
                    (from_lammps ? " (" + r.input_format + ")" : std::string()) +
                    (r.dynamics ? "; the dynamics stage settled them from there" : "; no aggpack stage moved them"));
  for (const LammpsExchange& x : r.lammps_exchanges)
    notes.push_back(x.direction == "import"
                        ? fmt::format("import_lammps: the positions of the bed's {} spheres were read from {} ({}), "
                                      "their velocities set to zero; the steps after it start from there",
                                      x.spheres, x.path, x.what)
                        : fmt::format("export_lammps: the bed of {} spheres and a LAMMPS deck of the next DEM step ({}) "
                                      "were written into {}; aggpack's own results below do not depend on it",
                                      x.spheres, x.what, x.path));
  for (const DemCalibrationFile& c : sc.calibrations)
    notes.push_back(fmt::format("calibrated: {} (in place of the scenario's values): {}. A density predicted with them "
                                "is validated only on measurements the calibration did not see",
                                fmt::join(c.assignments, ", "), c.fitted_to));
  if (sc.container.periodic) notes.push_back("periodic sides: x and y wrap, so the packing has no side-wall effect");
  if (r.deposition) {
    notes.push_back(fmt::format(
        "deposition: kinematic drop-and-roll, a geometric steepest descent without inertia or friction "
        "(material friction and restitution are not used by this stage); spheres dropped one at a time at "
        "uniformly random (x, y), in {} order; contact tolerance {:g} x diameter",
        sc.particles.graded ? name_of(kMixOrderNames, sc.particles.graded->order)
                            : name_of(kSizeOrderNames, sc.particles.sizes->order),
        sc.deposition->tolerance));
    const DepositionReport& d = *r.deposition;
    if (d.stats.end != DepositionEnd::AllPlaced)
      notes.push_back(fmt::format("deposition ended early ({}): {} of {} particles were placed", to_string(d.stats.end),
                                  d.stats.placed, d.requested));
  }
  for (const PourReport& p : r.pours) notes.push_back(pour_note(p, sc));
  for (const TapReport& t : r.tappings) notes.push_back(modelling_note(t));
  for (const RoddingReport& t : r.roddings) notes.push_back(modelling_note(t));
  for (const JigReport& t : r.jiggings) notes.push_back(modelling_note(t));
  const auto continues = [](const auto& step) { return step.continues_dem_system; };
  if (std::any_of(r.tappings.begin(), r.tappings.end(), continues) ||
      std::any_of(r.roddings.begin(), r.roddings.end(), continues) ||
      std::any_of(r.jiggings.begin(), r.jiggings.end(), continues) ||
      (r.dynamics && std::any_of(r.dynamics->runs.begin(), r.dynamics->runs.end(), continues)))
    notes.push_back("dynamics: consecutive DEM steps (a pour, its taps, a settling) continued one DEM system, contact "
                    "history and all, as LAMMPS keeps one system through an input deck (continues_dem_system in "
                    "their stages); a deposition or an import between two of them starts a new one");
  if (r.sizes)
    for (const std::string& note : r.sizes->notes) notes.push_back(note);
  for (std::string& note : particle_file_notes(r)) notes.push_back(std::move(note));
  if (sc.dynamics && sc.dynamics->allow_unstable_time_step)
    notes.push_back(fmt::format("dynamics.allow_unstable_time_step = true: the time step may exceed {:g} of the "
                                "Rayleigh time, where Hertz contacts are no longer resolved; the settled density "
                                "may be wrong", TimeStepRule::kStableFraction));
  if (r.dynamics)
    for (std::string& note : dynamics_notes(sc, *r.dynamics)) notes.push_back(std::move(note));
  if (r.dynamics_skipped) notes.push_back("--stop-after deposition: the [dynamics] stage was not run");
  if (const auto rest = r.rest_state(); rest && !rest->settled)
    notes.push_back(fmt::format("not settled: the DEM's last sample had a translational kinetic energy of {:.2e} "
                                "m g d per particle, above the quiet criterion's {:.0e}: the densities are those of a "
                                "bed still moving; raise dynamics.max_time for a bed at rest",
                                rest->translational_energy_per_particle_mgd, rest->quiet_below));
  if (sc.analysis.box_sides.empty())
    notes.push_back("no analysis.box_sides given: one virtual cube of the largest admissible side was used");
  notes.push_back("virtual cubes are centred horizontally and vertically between the floor and the free surface, "
                  "at least one d_max from walls, floor and surface; the free surface is the equivalent height "
                  "V_solid / (footprint area x median solid fraction of d_max-thick slices)");
  notes.push_back(fmt::format("coordination counts sphere pairs with centre distance <= (r_i + r_j)(1 + {:g}) "
                              "for the spheres whose centres lie in the largest box",
                              sc.analysis.contact_tolerance));
  return notes;
}

Predictions RunReport::predictions() const {
  // A particle file's spheres are the distribution; generated ones, the scenario's target.
  std::vector<double> diameters;
  if (scenario.particles.file)
    for (const double r : particles.radius) diameters.push_back(2.0 * r);
  const ModelParameters parameters = scenario.models_calibration ? read_calibration(*scenario.models_calibration)
                                                                 : default_model_parameters(!tappings.empty());
  return predict_scenario(scenario, parameters, diameters);
}

double RunReport::density_after_deposition() const {
  const auto a = analyses.find("deposition");
  return a != analyses.end() ? a->second.report.density.mean : std::numeric_limits<double>::quiet_NaN();
}

double RunReport::density_after_dynamics() const {
  // An interrupted run made no final analysis: its `final` holds no measurement.
  return dynamics && !interrupted ? final.density.mean : std::numeric_limits<double>::quiet_NaN();
}

double RunReport::final_density() const {
  return interrupted ? std::numeric_limits<double>::quiet_NaN() : final.density.mean;
}

std::string RunReport::last_dem_stage() const {
  // A protocol's own order: its last DEM step of a kind that ran. Without one, the stages'
  // default order (pour or deposition, settling, tapping).
  if (scenario.protocol)
    for (auto step = scenario.protocol->steps.rbegin(); step != scenario.protocol->steps.rend(); ++step) {
      if (std::holds_alternative<TapStep>(step->kind) && !tappings.empty()) return "tapping";
      if (std::holds_alternative<RodStep>(step->kind) && !roddings.empty()) return "rodding";
      if (std::holds_alternative<JigStep>(step->kind) && !jiggings.empty()) return "jigging";
      if (std::holds_alternative<PourStep>(step->kind) && !pours.empty()) return "pour";
      if (std::holds_alternative<SettleStep>(step->kind) && dynamics) return "DEM settling";
    }
  return !tappings.empty() ? "tapping" : !pours.empty() ? "pour" : "DEM settling";
}

namespace {

// Each stage's report (summary.json's "stages"), its wall clock added to `wall_clock`.
nlohmann::json stages_json(const RunReport& r, nlohmann::json& wall_clock) {
  nlohmann::json stages = nlohmann::json::object();
  for (const auto& [key, seconds] : r.wall_clock_s) wall_clock[key] = seconds;
  if (r.deposition) {
    stages["deposition"] = to_json(*r.deposition);
    wall_clock["deposition"] = r.deposition->wall_clock_s;
  }
  if (!r.tappings.empty()) {
    nlohmann::json all = nlohmann::json::array();
    for (const TapReport& t : r.tappings) all.push_back(to_json(t));
    stages["tapping"] = r.tappings.size() == 1 ? all.front() : nlohmann::json{{"steps", all}};
    double seconds = 0.0;
    for (const TapReport& t : r.tappings) seconds += t.wall_clock_s;
    wall_clock["tapping"] = seconds;
  }
  // Rodding and jigging: one step's report, or every step's under "steps".
  const auto add_steps = [&](const char* name, const auto& reports) {
    if (reports.empty()) return;
    nlohmann::json all = nlohmann::json::array();
    double seconds = 0.0;
    for (const auto& t : reports) {
      all.push_back(to_json(t));
      seconds += t.wall_clock_s;
    }
    stages[name] = reports.size() == 1 ? all.front() : nlohmann::json{{"steps", all}};
    wall_clock[name] = seconds;
  };
  add_steps("rodding", r.roddings);
  add_steps("jigging", r.jiggings);
  if (!r.pours.empty()) {
    nlohmann::json all = nlohmann::json::array();
    for (const PourReport& p : r.pours) all.push_back(to_json(p));
    stages["pour"] = r.pours.size() == 1 ? all.front() : nlohmann::json{{"steps", all}};
  }
  for (const auto& [name, analysis] : r.analyses) {
    add_analysis(stages[name], analysis.report);
    wall_clock["analysis_after_" + name] = analysis.wall_clock_s;
  }
  if (r.dynamics) {
    stages["dynamics"] = to_json(*r.dynamics);
    if (!r.interrupted) add_analysis(stages["dynamics"], r.final);
    wall_clock["dynamics"] = r.dynamics->wall_clock_s();
  }
  return stages;
}

// Where a particle file's bed came from (or the caller's), and how far its spheres overlap.
nlohmann::json input_json(const RunReport& r) {
  const Scenario& sc = r.scenario;
  nlohmann::json input = {{"file", sc.particles.file->string()},
                          {"largest_boundary_overlap_rel", r.largest_boundary_overlap},
                          {"boundary_overlap_tolerance_rel", sc.particles.boundary_overlap_tolerance}};
  if (r.input_format.starts_with("LAMMPS") || sc.particles.bed_from_caller()) input["format"] = r.input_format;
  if (r.largest_pair_overlap > 1e-6) {
    input["largest_pair_overlap_rel"] = r.largest_pair_overlap;
    input["soft_contacts"] = sc.particles.soft_contacts;
  }
  return input;
}

// Where an interrupted run stopped and how to continue it.
nlohmann::json interruption_json(const Interruption& stop) {
  nlohmann::json j = {{"signal", stop.signal_number},
                      {"stopped", stop.where},
                      {"steps_completed", stop.steps_completed},
                      {"steps_total", stop.steps_total},
                      {"note", "the stages listed are the steps that ended before the stop; particles.csv "
                               "and timeseries.csv hold the bed and the samples as they stood"}};
  j["checkpoint"] = stop.checkpoint ? nlohmann::json{{"file", kCheckpointFile},
                                                     {"taken", *stop.checkpoint},
                                                     {"resume", "aggpack resume <this folder>"}}
                                    : nlohmann::json(nullptr);
  return j;
}

}  // namespace

nlohmann::json RunReport::summary_json(double output_seconds, double total_seconds) const {
  const Scenario& sc = scenario;
  nlohmann::json summary;
  summary["aggpack_version"] = kVersion;
  summary["seed"] = sc.seed;
  summary["scenario_file"] = sc.file.string();
  if (!working_directory.empty()) summary["working_directory"] = working_directory;
  // What the file alone does not say (export-lammps RUN_DIR reads the scenario again with them);
  // output.* assignments choose files and checkpoints, not results, and are left out.
  std::vector<std::string> overrides;
  for (const std::string& set : sc.overrides)
    if (!set.starts_with("output.")) overrides.push_back(set);
  if (!overrides.empty()) summary["scenario_overrides"] = overrides;
  summary["scenario"] = to_json(sc);
  summary["particle_count"] = particles.size();
  const Box& b = sc.container.bounds;
  summary["container"] = {{"lo", {b.lo.x, b.lo.y, b.lo.z}}, {"hi", {b.hi.x, b.hi.y, b.hi.z}},
                          {"periodic", sc.container.periodic}};
  if (sc.container.is_cylinder()) {  // a box's keys are as they were before shapes
    summary["container"]["shape"] = name_of(kContainerShapeNames, sc.container.shape);
    summary["container"]["diameter_m"] = 2.0 * sc.container.radius();
    summary["container"]["rim_m"] = sc.container.rim;
  }
  if (final.measure) summary["measure"] = to_json(*final.measure);
  nlohmann::json wall_clock = nlohmann::json::object();
  summary["stages"] = stages_json(*this, wall_clock);
  if (sizes) summary["sizes"] = to_json(sizes->report);
  if (sc.particles.file) summary["input"] = input_json(*this);
  if (!lammps_exchanges.empty()) {
    nlohmann::json all = nlohmann::json::array();
    for (const LammpsExchange& x : lammps_exchanges)
      all.push_back({{"direction", x.direction}, {"path", x.path}, {"what", x.what}, {"spheres", x.spheres}});
    summary["lammps_exchanges"] = all;
  }
  const Predictions predicted = predictions();
  summary["predictions"] = to_json(predicted);
  // Which numbers are the bed's and which a model's, and from what.
  summary["density_sources"] = {
      {"density", "simulated: the bed's solid fraction in virtual boxes (stages.*.density likewise)"},
      {"bulk_density", "simulated: density x the grains' particle density"},
      {"predictions", fmt::format("predicted by analytic models, nothing simulated: CPM's K {:g} ({}), beta {:g} ({})",
                                  predicted.parameters.compaction_index, predicted.parameters.compaction_source,
                                  predicted.parameters.beta, predicted.parameters.beta_source)}};
  if (final.measure)
    summary["density_sources"]["measure"] = "simulated: the lab measure's content, as the test weighs it";
  if (const auto rest = rest_state()) {
    summary["settled"] = rest->settled;
    summary["final_translational_energy_per_particle_mgd"] = rest->translational_energy_per_particle_mgd;
    summary["quiet_translational_energy_per_particle_mgd"] = rest->quiet_below;
  }
  if (!grain_libraries.is_null()) {
    summary["grains"] = {{"count", particles.bodies.size()},
                         {"components", bed_grains_json(grain_libraries, particles, grain_shape_component)},
                         {"checkpoints", "as for spheres: each grain's rigid body is in the checkpoint, and resume goes on to the same bytes"},
                         {"files", "grains.csv (one row per grain), particles.csv's grain column (its spheres)"}};
  }
  summary["modelling_notes"] = modelling_notes();
  if (resumed_from) summary["resumed_from_checkpoint"] = *resumed_from;
  if (checkpoint_error) summary["checkpoint_error"] = *checkpoint_error;
  if (interrupted) {
    // No final analysis: the bed in particles.csv is where the run stood when it stopped.
    summary["interrupted"] = true;
    summary["interruption"] = interruption_json(*interrupted);
  } else {
    summary.update(to_json(final));
    // The engineer's quantities beside the packing density (ASTM C29), from material.density.
    const BulkDensity bulk = bulk_density(final.density.mean, particle_density(sc, particles));
    summary["bulk_density"] = {{"voids_content_percent", bulk.voids_percent},
                               {"kg_m3", bulk.kg_per_m3},
                               {"lb_ft3", bulk.lb_per_ft3},
                               {"particle_density_kg_m3", bulk.particle_density},
                               {"of", "density.mean"}};
  }
  wall_clock["output"] = output_seconds;
  wall_clock["total"] = total_seconds;
  summary["wall_clock_s"] = wall_clock;
  return summary;
}

std::string RunReport::console_summary(const std::filesystem::path& written_to) const {
  const Scenario& sc = scenario;
  std::string out =
      particles.bodies.empty()
          ? fmt::format("aggpack {}: {} ({} particles, seed {})\n", kVersion, sc.title, particles.size(), sc.seed)
          : fmt::format("aggpack {}: {} ({} grains and {} spheres of their own; {} spheres in all, seed {})\n",
                        kVersion, sc.title, particles.bodies.size(),
                        std::count(particles.body.begin(), particles.body.end(), kNoBody), particles.size(), sc.seed);
  auto o = std::back_inserter(out);
  if (sizes && sc.particles.graded) {
    const SizesReport& z = sizes->report;
    const GradingReport& all = z.whole;
    fmt::format_to(o, "  sizes: {} particles by {} sampling, d {:.3g}-{:.3g} mm, D10/D50/D90 {:.3g}/{:.3g}/{:.3g} mm, "
                      "fineness modulus {:.2f}\n",
                   z.count, name_of(kSamplingModeNames, *z.sampling), 1e3 * all.d_min, 1e3 * all.d_max, 1e3 * all.d10,
                   1e3 * all.d50, 1e3 * all.d90, all.fineness_modulus);
    if (z.order)
      fmt::format_to(o, "  mix: Ca/Fa {:.4g} generated for {:.4g} requested ({} order)\n", z.ca_fa_generated,
                     z.ca_fa_requested, name_of(kMixOrderNames, *z.order));
    for (const SizesComponent& c : z.components) {
      fmt::format_to(o, "  {} ({}): {} particles, cut off {:.2f} % below {:.3g} mm and {:.2f} % above {:.3g} mm; "
                        "largest deviation from the target {:.2f} points\n",
                     c.key, c.grading, c.generated.count, 100 * c.cut.cut_below, 1e3 * c.cut.d_lo,
                     100 * c.cut.cut_above, 1e3 * c.cut.d_hi, c.generated.largest_deviation);
      fmt::format_to(o, "    {:>8} {:>10} {:>9} {:>9}\n", "sieve", "opening mm", "target %", "generated %");
      for (const GradingReportRow& row : c.generated.rows)
        fmt::format_to(o, "    {:>8} {:>10.4g} {:>9.2f} {:>9.2f}\n", row.sieve.name, 1e3 * row.sieve.opening,
                       row.sieve.percent_passing, row.generated);
      if (const std::string snapped = snapped_sieves_text(c.cut.grading.snapped); !snapped.empty())
        fmt::format_to(o, "    {}\n", snapped);
      if (c.band)
        fmt::format_to(o, "    band {}: {}\n", c.band->name,
                       check_against_band(c.cut.grading, *c.band).all_inside() ? "inside at every sieve"
                                                                             : "OUTSIDE at some sieves");
    }
  }
  out += grain_lines(*this);
  out += step_lines(*this);
  for (const auto& box : final.density.boxes)
    fmt::format_to(o, "  virtual cube {}: density {:.4f}\n", length_text(box.side, sc.written_length_unit), box.density);
  if (interrupted) {  // no final analysis: nothing measured to print, nothing to carry to a bulk density
    fmt::format_to(o, "  mean density not measured: interrupted by signal {} {} ({} of {} steps done), before the "
                      "final analysis\n",
                   interrupted->signal_number, interrupted->where, interrupted->steps_completed,
                   interrupted->steps_total);
    fmt::format_to(o, "  wrote {}\n", written_to.string());
    return out;
  }
  const auto rest = rest_state();
  fmt::format_to(o, "  mean density {:.4f} (sd {:.4f}){}, mean coordination {:.3f} over {} {}\n", final.density.mean,
                 final.density.sd, rest && !rest->settled ? " NOT SETTLED" : "", final.coordination.mean,
                 final.coordination.particles_counted, kinds_of_particles(particles));
  const double grains = particle_density(sc, particles);
  fmt::format_to(o, "  {} (particle density {:g} kg/m3)\n", describe(bulk_density(final.density.mean, grains)), grains);
  if (const auto& m = final.measure)
    fmt::format_to(o, "  measure {} across, struck off at {}: packing density {:.4f} (exact cut at the rim; {:.4f} "
                      "counting the {} particles centred below it whole), {}\n",
                   length_text(m->diameter, sc.written_length_unit), length_text(m->rim, sc.written_length_unit),
                   m->packing_density, m->packing_density_whole_particles, m->particles,
                   describe(bulk_density(m->packing_density, grains)));
  if (rest && !rest->settled)
    fmt::format_to(o, "  not settled: the DEM ended with a kinetic energy of {:.2e} m g d per particle, above the "
                      "quiet criterion's {:.0e}; the density is that of a bed still moving (raise dynamics.max_time)\n",
                   rest->translational_energy_per_particle_mgd, rest->quiet_below);
  fmt::format_to(o, "{}", describe(predictions()));
  fmt::format_to(o, "  wrote {}\n", written_to.string());
  return out;
}

}  // namespace aggpack
