#include "run/run_session.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <variant>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/lammps/process.hpp"
#include "aggpack/run/calibration_file.hpp"
#include "aggpack/run/output_folder.hpp"
#include "aggpack/run/preflight.hpp"

namespace aggpack {

namespace {
using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// The steps the run takes: the controls', else the scenario's, cut after --stop-after's stage.
Protocol run_protocol(const Scenario& sc, const RunControls& controls) {
  Protocol protocol = controls.protocol.value_or(scenario_protocol(sc));
  if (controls.stop_after) protocol = stop_after(protocol, *controls.stop_after, sc);
  return protocol;
}

// The drop sequence's radii (none for a particle file).
std::vector<double> drop_radii(const InitialBed& bed) {
  std::vector<double> radii;
  if (bed.sizes)
    for (const double d : bed.sizes->diameters) radii.push_back(0.5 * d);
  return radii;
}

// Grains of several spheres (a component's `shape`) are poured: the drop and roll places
// spheres. LAMMPS takes a pour with grains in one batch (its fix rigid/small takes its bodies
// once), and settles none with the parts below frozen (its deck would integrate them).
void check_grain_protocol(const Scenario& sc, const Protocol& protocol) {
  if (!sc.particles.has_grains()) return;
  const auto fail = [&](std::string_view what) {
    throw InputError(fmt::format("{}: a component has a shape (grains of several spheres), and {}", sc.file.string(), what));
  };
  const bool lammps_engine = sc.dynamics && sc.dynamics->engine == DemEngine::Lammps;
  const bool several_batches = sc.pour && sc.pour->batches > 1;  // LAMMPS cannot take that with grains
  for (const Step& step : protocol.steps) {
    if (std::holds_alternative<DepositStep>(step.kind))
      fail("the drop-and-roll deposition places spheres only: pour grains ([pour]) instead of depositing them");
    const auto* exported = std::get_if<ExportLammpsStep>(&step.kind);
    const auto* settle = exported ? std::get_if<SettleStep>(&exported->next) : std::get_if<SettleStep>(&step.kind);
    if (settle && settle->layer > 0 && (lammps_engine || exported))
      fail("a settle step of a later part holds the parts below it still, and LAMMPS's fix rigid/small would move "
           "their grains: settle it in aggpack's DEM (no dynamics.engine = \"lammps\", no export_lammps step)");
    const bool pour_to_lammps = (lammps_engine && std::holds_alternative<PourStep>(step.kind)) ||
                                (exported && std::holds_alternative<PourStep>(exported->next));
    if (pour_to_lammps && several_batches)
      fail("pour.batches: LAMMPS's fix rigid/small takes its grains once, when it is defined, so a pour with grains "
           "goes to LAMMPS in one batch; expected pour.batches = 1, or aggpack's DEM");
  }
}

// The frames' slack: a sample meant to fall on a multiple of frame_interval is not missed by a rounding.
constexpr double kFrameSlack = 1e-6;
}  // namespace

namespace {

// The spheres of particles.from's file, each of its material (the file's material column, else
// particles.material).
ParticleStore read_file_bed(const Scenario& sc, std::string& format) {
  // A particle file is one component, all of one material.
  const std::uint8_t material = sc.particles.material_of_component(0);
  PackingFile file = read_packing_file(*sc.particles.file, sc.particles.file_length_unit,
                                       material_of(sc, material).density, sc.limits.max_input_bytes(),
                                       sc.particles.file_timestep);
  std::fill(file.particles.material.begin(), file.particles.material.end(), material);
  if (!file.materials.empty() && sc.particles.component_material.front() != 0)
    throw InputError(fmt::format("{}: particles.material: the file {} names each sphere's material (its material "
                                 "column): expected no particles.material",
                                 sc.file.string(), sc.particles.file->string()));
  assign_file_materials(file.particles, file.materials, sc, sc.particles.file->string());
  format = std::move(file.format);
  return std::move(file.particles);
}

// The caller's starting bed (particles.from = "-"), checked as a file's would be: its spheres'
// positions, radii and velocities (angular velocities start at zero, as a file's spheres'); each
// sphere's material its own (an index of the scenario's materials), or particles.material's for
// a bed all of material 0; masses from the materials.
ParticleStore given_bed(const Scenario& sc, const ParticleStore* given, const std::string& name) {
  if (!given)
    throw InputError(fmt::format("{}: particles.from = \"{}\" takes the starting bed from the library's caller "
                                 "(Python: aggpack.run(scenario, bed=...)), and none was given; expected a particle "
                                 "file's path",
                                 sc.file.string(), kBedFromCaller));
  if (!given->bodies.empty())
    throw InputError(fmt::format("{}: {} holds grains; a starting bed is of spheres (grains are generated from "
                                 "sizes and poured)",
                                 sc.file.string(), name));
  const std::size_t n = given->position.size();
  if (given->radius.size() != n || given->velocity.size() != n || given->material.size() != n)
    throw std::invalid_argument("the starting bed's arrays differ in length");
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& p = given->position[i];
    const Vec3& v = given->velocity[i];
    const double r = given->radius[i];
    if (!std::isfinite(p.x + p.y + p.z) || !std::isfinite(v.x + v.y + v.z) || !(r > 0.0) || !std::isfinite(r))
      throw InputError(fmt::format("{}: sphere {} of {}: position ({}, {}, {}) m, velocity ({}, {}, {}) m/s, radius "
                                   "{} m; expected finite numbers and a positive radius",
                                   sc.file.string(), i, name, p.x, p.y, p.z, v.x, v.y, v.z, r));
  }
  ParticleStore bed;
  bed.reserve(n);
  const std::uint8_t material = sc.particles.material_of_component(0);
  const bool all_default = std::all_of(given->material.begin(), given->material.end(), [](auto m) { return m == 0; });
  for (std::size_t i = 0; i < given->size(); ++i) {
    const std::uint8_t own = all_default ? material : given->material[i];
    if (own >= material_count(sc))
      throw InputError(fmt::format("{}: sphere {} of {} is of material {}, and the scenario has {} (indices 0 to {})",
                                   sc.file.string(), i, name, own, material_count(sc), material_count(sc) - 1));
    bed.add(given->position[i], given->radius[i], material_of(sc, own).density);
    bed.velocity[i] = given->velocity[i];
    bed.material[i] = own;
  }
  if (!all_default && material != 0)
    throw InputError(fmt::format("{}: particles.material: {} gives each sphere's material: expected no "
                                 "particles.material",
                                 sc.file.string(), name));
  return bed;
}

}  // namespace

InitialBed initial_bed(const Scenario& sc, const ParticleStore* starting_bed) {
  if (!sc.particles.file) check_amount(sc, expected_amount(sc.particles), false);
  check_frames(sc);
  check_lammps_available(sc);
  InitialBed bed;
  if (starting_bed && !sc.particles.bed_from_caller())
    throw InputError(fmt::format("{}: a starting bed was given, and the scenario's particles are {}: expected "
                                 "[particles] from = \"{}\" for the bed given",
                                 sc.file.string(),
                                 sc.particles.file ? "read from " + sc.particles.file->string() : "generated",
                                 kBedFromCaller));
  if (sc.particles.file) {
    const std::string name = sc.particles.bed_from_caller()
                                 ? fmt::format("the starting bed given (particles.from = \"{}\")", kBedFromCaller)
                                 : sc.particles.file->string();
    if (sc.particles.bed_from_caller()) {
      bed.particles = given_bed(sc, starting_bed, name);
      bed.file_format = fmt::format("given by the caller ({} spheres)", bed.particles.size());
    } else {
      bed.particles = read_file_bed(sc, bed.file_format);
    }
    if (!(static_cast<double>(bed.particles.size()) <= sc.limits.max_particles))
      throw InputError(fmt::format("{}: {} particles, more than limits.max_particles = {:.3g}", name,
                                   bed.particles.size(), sc.limits.max_particles));
    bed.largest_boundary_overlap =
        fit_into_container(bed.particles, sc.container, sc.particles.boundary_overlap_tolerance, name);
    check_sizes(sc, bed.particles.radius);
    check_protocol_beds(sc, bed.particles.radius, {});
    bed.largest_pair_overlap = check_particle_overlaps(bed.particles, sc.container, sc.particles.overlap_tolerance,
                                                       sc.particles.soft_contacts, name, sc.limits.max_grid_cells);
    return bed;
  }
  try {
    bed.sizes = generate_sizes(sc.particles, sc.seed);
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", sc.file.string(), e.what()));
  }
  check_amount(sc, drawn_amount(sc.particles, *bed.sizes), true);
  std::vector<double> radii;
  radii.reserve(bed.sizes->diameters.size());
  for (const double d : bed.sizes->diameters) radii.push_back(0.5 * d);
  check_sizes(sc, radii);
  // With grains, once they are made (checked_grains): an import's file holds their spheres.
  if (!sc.particles.has_grains()) check_protocol_beds(sc, {}, radii);
  return bed;
}

RunGrains checked_grains(const Scenario& sc, const Protocol& protocol, const InitialBed& bed,
                         const LibraryWatch& watch) {
  check_grain_protocol(sc, protocol);
  RunGrains grains;
  if (!bed.sizes) return grains;
  std::vector<const GrainShapeSpec*> specs;
  for (const auto& shape : sc.particles.component_shape)
    if (shape) specs.push_back(&*shape);
  check_library_cost(specs, sc.limits.max_template_minutes, fmt::format("{}: particles: shape", sc.file.string()),
                     "limits.max_template_minutes");
  try {
    grains = make_run_grains(sc.particles, *bed.sizes, sc.seed, watch);
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", sc.file.string(), e.what()));
  }
  if (grains.empty()) return grains;
  // The virtual boxes' room from the walls and the bed's surface is one such diameter.
  const std::vector<double> radii = drop_radii(bed);
  const RunGrains::PourPart all = grains.pour_part(radii, 0);
  double solid = 0.0;  // each grain's union, each sphere's ball
  for (std::size_t k = 0; k < all.radii.size(); ++k) {
    const double r = all.radii[k];
    solid += all.shapes[k] ? all.shapes[k]->volume * r * r * r : 4.0 / 3.0 * std::numbers::pi * r * r * r;
  }
  check_sizes(sc, all.radii, solid);
  check_protocol_beds(sc, {}, radii, &grains);
  return grains;
}

RunSession::RunSession(const Scenario& sc, const RunControls& controls, Progress& progress)
    : scenario_(sc), controls_(controls), progress_(progress), protocol_(run_protocol(sc, controls)),
      context_{.report = report_, .progress = progress, .threads = controls.threads, .stop = controls.stop} {
  check_thread_count(controls.threads);
  if (controls.starting_bed && (controls.checkpoints || controls.resume_from))
    throw InputError(fmt::format("{}: a run from a starting bed given in memory takes no checkpoints: a resume "
                                 "would not have the bed",
                                 sc.file.string()));
  report_.scenario = sc;
  const auto t0 = Clock::now();
  InitialBed initial = initial_bed(sc, controls.starting_bed);
  report_.particles = std::move(initial.particles);
  report_.largest_boundary_overlap = initial.largest_boundary_overlap;
  report_.largest_pair_overlap = initial.largest_pair_overlap.depth_over_radius;
  report_.input_format = initial.file_format;
  const double prepared_s = seconds_since(t0);  // reading the file, or drawing the sizes
  report_.wall_clock_s["input"] = initial.sizes ? 0.0 : prepared_s;
  if (initial.sizes) report_.wall_clock_s["sizes"] = prepared_s;
  context_.radii = drop_radii(initial);
  if (initial.sizes) context_.sphere_materials = sphere_materials(sc.particles, *initial.sizes);
  const auto t_grains = Clock::now();
  // The templates' fit can take minutes: shown, and stopped where asked.
  context_.grains = checked_grains(sc, protocol_, initial, templates_shown_on(progress, controls.stop));
  progress.clear();
  if (!context_.grains.empty()) {
    report_.wall_clock_s["grains"] = seconds_since(t_grains);
    report_.grain_libraries = libraries_json(context_.grains, initial.sizes->report.components);
    report_.grain_shape_component = context_.grains.shape_component;
  }
  context_.material_densities = material_densities(sc);
  std::string calibrated;  // the values its calibration files gave the scenario
  for (const DemCalibrationFile& c : sc.calibrations)
    for (const std::string& assignment : c.assignments) calibrated += assignment + '\n';
  const std::uint64_t fingerprint = input_fingerprint(report_.particles, context_.radii, calibrated);
  const Checkpoint* resume = controls.resume_from;
  if (resume && resume->inputs_fingerprint != fingerprint)
    throw InputError(fmt::format("{}: the run's starting bed or calibration is not the one its checkpoint began from: "
                                 "a particle, grading or calibration file the scenario reads has changed since; run "
                                 "the scenario again",
                                 sc.file.string()));
  // The calibration the predictions will read at the end, read now: a bad file fails before the work.
  if (sc.models_calibration) (void)read_calibration(*sc.models_calibration);
  if (initial.sizes) report_.sizes = std::move(initial.sizes);
  // A resumed run's state decoded and checked before the folder is touched.
  if (resume) completed_ = restore(*resume);
  if (controls.before_work) controls.before_work();
  if (controls.on_frame && sc.output.frame_interval) {
    frame_taker_ = [this](double time, const ParticleStore& bed) { take_frames(time, bed); };
    context_.at_sample = &frame_taker_;
  }
  if (controls.checkpoints) {
    Checkpoint header = controls.checkpoints->header;
    header.inputs_fingerprint = fingerprint;
    checkpointer_.emplace(controls.checkpoints->directory, controls.checkpoints->every_seconds, std::move(header),
                          controls.stop, [this](std::ostream& out) { encode_run_state(out, report_, context_); });
    context_.safe_point = &*checkpointer_;
  }
  if (!resume && checkpointer_)  // resume can always start here
    checkpointer_->write(fmt::format("before step 1 of {}", protocol_.steps.size()), nullptr);
}

// The frames: at the first sample, then at the first sample at or after each multiple k x
// frame_interval of the series' time.
void RunSession::take_frames(double time, const ParticleStore& bed) {
  const double interval = *scenario_.output.frame_interval;
  if (time < (static_cast<double>(report_.next_frame_multiple) - kFrameSlack) * interval) return;
  // The DEM lets spheres cross periodic sides; a frame shows them in the box, as the final
  // bed and the snapshots do (so that a frame of the final bed is recognised as it).
  std::optional<ParticleStore> wrapped;
  if (scenario_.container.periodic) {
    wrapped = bed;
    for (Vec3& p : wrapped->position) p = scenario_.container.wrapped(p);
  }
  const ParticleStore& shown = wrapped ? *wrapped : bed;
  FrameRecord frame{frame_file_name(report_.frames.size() + 1), time, bed_fingerprint(shown)};
  controls_.on_frame(frame.file, time, shown, report_);
  report_.frames.push_back(std::move(frame));
  report_.next_frame_multiple = static_cast<std::uint64_t>(std::floor(time / interval + kFrameSlack)) + 1;
}

void RunSession::run_steps() {
  const std::size_t total = protocol_.steps.size();
  try {
    for (; completed_ < total; ++completed_) {
      if (checkpointer_) checkpointer_->set_steps_completed(completed_);
      // A step resumed in progress goes on from its own safe point.
      if (!context_.resume_state)
        at_safe_point(context_.safe_point, controls_.stop, fmt::format("before step {} of {}", completed_ + 1, total),
                      nullptr);
      context_.in_step = true;
      std::visit([&](const auto& kind) { run_step(kind, context_); }, protocol_.steps[completed_].kind);
      context_.in_step = false;
      context_.resume_state = nullptr;
    }
    if (checkpointer_) checkpointer_->set_steps_completed(total);
    // No step is left to continue the DEM: its memory goes, and no checkpoint from here holds it.
    context_.dem.drop();
    report_.simulated_time = context_.simulated_time;
    const Checkpoint* resume = controls_.resume_from;
    const bool resumed_with_every_step_done = resume && resume->steps_completed == total;  // that checkpoint stands
    if (checkpointer_ && controls_.checkpoint_before_final_analysis && !resumed_with_every_step_done)
      checkpointer_->write("before the final analysis", nullptr);
    at_safe_point(context_.safe_point, controls_.stop, "before the final analysis", nullptr);
  } catch (const Interrupted& stop) {
    progress_.clear();
    report_.interrupted = Interruption{stop.signal_number(), stop.where(), completed_, total,
                                       checkpointer_ ? checkpointer_->last_written() : std::nullopt};
  }
  if (checkpointer_) {
    report_.wall_clock_s["checkpoints"] += checkpointer_->seconds_spent();
    report_.checkpoint_error = checkpointer_->error();
  }
}

RunReport RunSession::finish() {
  if (report_.interrupted || !controls_.final_analysis) return std::move(report_);
  report_.dynamics_skipped = scenario_.dynamics && !report_.dynamics;
  const auto t0 = Clock::now();
  progress_.start_stage("analysis");
  progress_.update({"virtual boxes"}, 0.0);
  try {
    report_.final = analyse_bed(scenario_, report_.particles);
  } catch (const InputError& e) {
    progress_.clear();
    if (report_.simulated_time > 0.0) throw BedNotAnalysed(e.what(), std::move(report_.particles), report_.simulated_time);
    throw;
  }
  progress_.clear();
  report_.wall_clock_s["analysis"] = seconds_since(t0);
  return std::move(report_);
}

// Puts a resumed run where its checkpoint was taken: the reports and beds of the steps done
// (none when it was taken before the first), and the state of the step in progress for that
// step to take up. Returns the steps done.
std::size_t RunSession::restore(const Checkpoint& checkpoint) {
  const Protocol& protocol = protocol_;
  RunReport& report = report_;
  RunContext& context = context_;
  const std::size_t total = protocol.steps.size();
  if (checkpoint.steps_completed > total)
    throw DamagedCheckpoint(fmt::format("it has {} steps done of a protocol of {}", checkpoint.steps_completed, total));
  // A run state from the first step on (none before it); a step state only inside a step of
  // aggpack's DEM, the only steps with safe points that save one.
  const bool started = checkpoint.steps_completed > 0 || !checkpoint.step_state.empty();
  if (started == checkpoint.run_state.empty())
    throw DamagedCheckpoint(fmt::format("a run state {} steps done", started ? "missing with" : "with no"));
  if (!checkpoint.step_state.empty()) {
    const auto in_dem_step = [&] {
      const StepKind& kind = protocol.steps[checkpoint.steps_completed].kind;
      return report.scenario.dynamics && report.scenario.dynamics->engine == DemEngine::Aggpack &&
             (std::holds_alternative<SettleStep>(kind) || std::holds_alternative<PourStep>(kind) ||
              std::holds_alternative<TapStep>(kind) || std::holds_alternative<RodStep>(kind) ||
              std::holds_alternative<JigStep>(kind));
    };
    const bool dem = checkpoint.steps_completed < total && in_dem_step();
    if (!dem) throw DamagedCheckpoint(fmt::format("a step state for step {}, not a DEM step", checkpoint.steps_completed + 1));
  }
  if (!checkpoint.run_state.empty()) decode_run_state(checkpoint.run_state, report, context);
  if (!checkpoint.step_state.empty()) context.resume_state = &checkpoint.step_state;
  report.resumed_from = checkpoint.where;
  return checkpoint.steps_completed;
}

}  // namespace aggpack
