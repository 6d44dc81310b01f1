#include "aggpack/run/settle_stage.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>

#include <fmt/format.h>

#include "aggpack/analysis/density.hpp"
#include "aggpack/core/error.hpp"
#include "aggpack/dynamics/contact_law_registry.hpp"
#include "aggpack/dynamics/pour.hpp"
#include "aggpack/dynamics/settle.hpp"
#include "aggpack/dynamics/jig.hpp"
#include "aggpack/dynamics/rod.hpp"
#include "aggpack/dynamics/tap.hpp"
#include "aggpack/run/analyze.hpp"
#include "aggpack/run/carried_dem.hpp"
#include "aggpack/run/checkpoint.hpp"
#include "run/report_archive.hpp"

namespace aggpack {

std::string TimeSeries::csv() const {
  // The energies with every digit (shortest round trip): the per-m g d one and the joules are
  // one quantity, and their ratio is checkable only unrounded. A quantity not measured is empty.
  const auto energy = [](double v) { return std::isnan(v) ? std::string() : fmt::format("{}", v); };
  std::string body;
  for (const TimeSample& s : samples)
    fmt::format_to(std::back_inserter(body), "{:.9g},{},{},{},{},{},{:.6g},{:.6g},{:.5g}\n", s.time, s.layer,
                   std::isnan(s.density) ? std::string() : fmt::format("{:.6f}", s.density),
                   energy(s.translational_per_particle_mgd), energy(s.translational_energy),
                   energy(s.rotational_energy), s.mean_overlap, s.max_overlap, s.coordination);
  return "time_s,layer,density,translational_energy_per_particle_mgd,translational_energy_j,rotational_energy_j,"
         "mean_overlap_rel,max_overlap_rel,coordination\n" +
         body;
}


namespace {

using Clock = std::chrono::steady_clock;

DensityProbe box_density(const Scenario& sc) {
  AnalysisRequest request;
  request.cube_sides = sc.analysis.box_sides;
  return [&sc, request](const ParticleStore& store) {
    try {
      const BedGeometry bed = measure_bed(store, sc.container);
      return measure_density(store, sc.container, virtual_boxes(sc.container, bed, request)).mean;
    } catch (const InputError&) {
      return std::numeric_limits<double>::quiet_NaN();  // the boxes do not fit the bed yet
    }
  };
}

// The error that stops a run whose bed blew up (`what`: when and how), naming the settings that
// are the likely cause: the time step against the Rayleigh time, and the stage's own `causes`.
InputError blow_up_error(const Scenario& sc, const ParticleStore& particles, std::string_view what,
                         std::string_view causes) {
  double r_min = std::numeric_limits<double>::infinity();
  for (const double r : particles.radius) r_min = std::min(r_min, r);
  const double rayleigh = stable_time_scale(sc, r_min);
  const double step = sc.dynamics->time_step.step(rayleigh);
  return InputError(fmt::format(
      "{}: the DEM blew up {}; the likely cause is the time step ({:.3g} s, {:.3g} times the smallest sphere's Rayleigh "
      "time{}){}",
      sc.file.string(), what, step, step / rayleigh,
      sc.dynamics->allow_unstable_time_step ? ", above the stable limit by dynamics.allow_unstable_time_step" : "",
      causes.empty() ? std::string() : fmt::format(", or {}", causes)));
}
constexpr std::string_view kPourCauses = "the pour (pour.velocity, pour.gap, pour.solid_fraction: a fall too fast "
                                         "for the stiffness)";
constexpr std::string_view kTapCauses = "the tap (tapping.intensity and tapping.frequency: the amplitude)";
constexpr std::string_view kRodCauses = "the rod (rodding.speed: a rod driven faster than the bed can make way)";
constexpr std::string_view kJigCauses = "the drop (jigging.height: the impact speed sqrt(2 g h))";

// The highest point of the free spheres above the floor, m.
double top_above_floor(const DemSystem& dem, const ParticleStore& particles, const Container& container) {
  double top = 0.0;
  for (std::size_t i = 0; i < particles.size(); ++i)
    if (!dem.is_frozen(i)) top = std::max(top, particles.position[i].z + particles.radius[i] - container.bounds.lo.z);
  return top;
}

// Appends each sample to the series and shows it on the progress line; stops a bed that has
// blown up at once (find_blow_up), naming the settings that are the likely cause, rather than
// letting it fail later somewhere else.
class SampleRecorder {
 public:
  // `budget` is what the stage can give the bed; `causes` names the stage's own settings that
  // could make it blow up (the time step's are named for every stage).
  SampleRecorder(const Scenario& sc, std::uint32_t layer, TimeSeries& series, Progress& progress, const DemSystem& dem,
                 const ParticleStore& particles, EnergyBudget budget, std::string causes,
                 const SampleObserver* at_sample)
      : sc_(sc), stage_(*sc.dynamics), layer_(layer), series_(series), progress_(progress), forecast_(stage_.quiet),
        dem_(dem), particles_(particles), budget_(budget), causes_(std::move(causes)), at_sample_(at_sample) {}
  // The pour raises the budget's height as its batches come in higher.
  EnergyBudget& budget() { return budget_; }
  // `time` is the series' time of the sample; `phase` names what the DEM is doing.
  void operator()(double time, const SettleSample& s, const std::string& phase) {
    if (const auto what = find_blow_up(dem_, particles_, sc_.container, s, budget_)) blew_up(phase, time, *what);
    series_.samples.push_back({time, layer_, s.density, s.translational_per_particle_mgd,
                               s.kinetic_energy.translational, s.kinetic_energy.rotational, s.contacts.mean_overlap,
                               s.contacts.max_overlap, s.contacts.coordination});
    // The store is the bed at this sample: DemSystem::run() writes it back at its end.
    if (at_sample_ && *at_sample_) (*at_sample_)(time, particles_);
    forecast_.add(s);
    // The forecast is a fit over the samples so far: only worth it for a line that will show.
    if (!progress_.due()) return;
    const std::optional<double> end = forecast_.expected_end();
    const QuietCriterion& criterion = stage_.quiet;
    progress_.update({phase, fmt::format("{:.3f} s simulated", s.time),
                      fmt::format("density {}", std::isnan(s.density) ? std::string("-") : fmt::format("{:.4f}", s.density)),
                      fmt::format("kinetic energy {:.1e} m g d (quiet below {:.0e})", s.translational_per_particle_mgd,
                                  criterion.kinetic_fraction),
                      fmt::format("max_time {:g} s", criterion.max_time)},
                     s.time / end.value_or(criterion.max_time),
                     end ? Progress::TimeLeft::Estimate : Progress::TimeLeft::AtMost);
  }
  // Stops the run: the bed blew up while `phase` at `time` (the series' time), as `what` says.
  [[noreturn]] void blew_up(std::string_view phase, double time, std::string_view what) const {
    throw blow_up_error(sc_, particles_, fmt::format("while {} at {:.4g} s simulated: {}", phase, time, what), causes_);
  }

 private:
  const Scenario& sc_;
  const DynamicsStage& stage_;
  std::uint32_t layer_;
  TimeSeries& series_;
  Progress& progress_;
  QuietForecast forecast_;
  const DemSystem& dem_;
  const ParticleStore& particles_;
  EnergyBudget budget_;
  std::string causes_;
  const SampleObserver* at_sample_;
};

// A DEM step's system: the run's carried one when it can go on (StageControls::carried),
// else a new one; and what the step's checkpoints hold beside its loop: the list builds the
// system had before the step (a new system's first build is the step's own) and the wall
// clock the step has taken.
class StepDem {
 public:
  StepDem(const StageControls& controls, ParticleStore& particles, const Container& container,
          const DemSetup& setup, std::vector<std::uint8_t> frozen = {})
      : t0_(Clock::now()) {
    if (controls.carried) {
      const CarriedDem::ForStep carried =
          controls.carried->system_for(particles, container, setup.model, setup.settings, std::move(frozen));
      system_ = &carried.system;
      continued_ = carried.continued;
      builds_before_ = carried.continued ? carried.system.rebuilds() : 0;
      fewer_before_ = carried.continued ? carried.system.steps_on_fewer_threads() : 0;
    } else {
      own_ = std::make_unique<DemSystem>(particles, container, setup.model, setup.settings, std::move(frozen));
      system_ = own_.get();
    }
  }
  [[nodiscard]] DemSystem& system() const { return *system_; }
  [[nodiscard]] std::size_t builds() const { return system_->rebuilds() - builds_before_; }
  [[nodiscard]] bool continued() const { return continued_; }
  // Of this step's steps (a machine figure: counted from the resume on, for a resumed step).
  [[nodiscard]] std::size_t steps_on_fewer_threads() const {
    return system_->steps_on_fewer_threads() - fewer_before_;
  }
  [[nodiscard]] double seconds() const { return std::chrono::duration<double>(Clock::now() - t0_).count(); }

  // The step's state at a safe point, for a checkpoint: its kind (checked when it is read
  // back), its loop, its wall clock and builds so far, and the DEM's state.
  template <class Loop>
  void save(std::ostream& out, std::string_view kind, const Loop& loop) const {
    {
      cereal::BinaryOutputArchive ar(out);
      ar(std::string(kind), loop, seconds(), builds_before_, continued_);
    }
    system_->save_state(out);
  }
  // Restores what save() saved into the system and `loop`. DamagedCheckpoint when the bytes do
  // not decode, or not to a state of this step (the loop is checked by the step itself).
  template <class Loop>
  void restore(std::string_view kind, const std::string& state, Loop& loop) {
    std::string saved_kind;
    double elapsed = 0.0;
    std::size_t dem_state_at = 0;
    try {
      CheckedInputArchive ar(state);
      ar(saved_kind);
      if (saved_kind != kind)
        throw DamagedCheckpoint(
            fmt::format("the checkpoint holds a {} step where the protocol has a {} step", saved_kind, kind));
      ar(loop, elapsed, builds_before_, continued_);
      dem_state_at = ar.position();
    } catch (const cereal::Exception& e) {
      throw DamagedCheckpoint(fmt::format("its {} step: {}", kind, e.what()));
    }
    try {
      system_->restore_state(std::string_view(state).substr(dem_state_at));
    } catch (const InputError& e) {
      throw DamagedCheckpoint(fmt::format("its {} step: {}", kind, e.what()));
    }
    // At most a billion seconds: its count of clock ticks must fit the clock.
    if (!(elapsed >= 0.0 && elapsed <= 1e9))
      throw DamagedCheckpoint(fmt::format("its {} step: {} s of wall clock", kind, elapsed));
    if (builds_before_ > system_->rebuilds())
      throw DamagedCheckpoint(fmt::format("its {} step: more list builds before it than in all", kind));
    // The step's wall clock counts what it took before the checkpoint too.
    t0_ = Clock::now() - std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(elapsed));
  }

 private:
  Clock::time_point t0_;
  std::unique_ptr<DemSystem> own_;
  DemSystem* system_ = nullptr;
  std::size_t builds_before_ = 0;
  std::size_t fewer_before_ = 0;  // the carried system's governor's count, when the step began
  bool continued_ = false;  // the system went on from the step before (a resumed step: it did then)
};

// A settling loop restored from a checkpoint: it began before the system's time and step now,
// and has sampled (its quiet window holds the samples so far).
void check_restored(const SettleLoop& loop, const DemSystem& dem, std::string_view kind) {
  if (!(loop.start >= 0.0 && loop.start <= dem.time()) || loop.start_steps > dem.steps() || loop.window.empty())
    throw DamagedCheckpoint(fmt::format("its {} step: its settling loop does not fit its DEM state", kind));
}

std::string where_simulated(std::string_view phase, double simulated) {
  return fmt::format("while {} at {:.4f} s simulated", phase, simulated);
}

SettlingRun settling_run(const StepDem& step, const DemSetup& setup, const Scenario& sc, std::uint32_t layer,
                         const SettleResult& result, const ParticleStore& particles) {
  const DemSystem& dem = step.system();
  const std::size_t steps = result.steps;
  const double seconds = step.seconds();
  SettlingRun run;
  run.layer = layer;
  run.particles_settled = dem.free_count();
  run.particles_frozen = particles.size() - dem.free_count();
  run.ended_by = result.end;
  run.simulated_time = result.simulated_time;
  run.steps = steps;
  run.time_step = setup.settings.time_step;
  run.rayleigh_time = setup.rayleigh;
  run.time_step_from_scenario = sc.dynamics->time_step.fixed.has_value();
  run.skin = dem.skin();
  run.neighbour_list_builds = step.builds();
  run.continues_dem_system = step.continued();
  run.last = result.last;
  run.wall_clock_s = seconds;
  run.particle_steps_per_second =
      seconds > 0 ? static_cast<double>(dem.free_count()) * static_cast<double>(steps) / seconds : 0.0;
  run.threads = dem.threads();
  run.steps_on_fewer_threads = step.steps_on_fewer_threads();
  run.memory_bytes_per_particle =
      static_cast<double>(dem.memory_bytes()) / static_cast<double>(std::max<std::size_t>(1, particles.size()));
  return run;
}

}  // namespace

SettlingRun settle_bed(const Scenario& sc, ParticleStore& particles, std::uint32_t layer, double time_offset,
                       const StageControls& controls, TimeSeries& series, Progress& progress) try {
  const DynamicsStage& stage = *sc.dynamics;
  // The layers below this one stay where they are (the paper's layer-by-layer method).
  std::vector<std::uint8_t> frozen(particles.size());
  for (std::size_t i = 0; i < particles.size(); ++i) frozen[i] = particles.layer[i] < layer ? 1 : 0;
  double r_min = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < particles.size(); ++i)
    if (!frozen[i]) r_min = std::min(r_min, particles.radius[i]);
  const DemSetup setup = dem_setup(sc, r_min, controls.threads);

  StepDem step(controls, particles, sc.container, setup, std::move(frozen));
  DemSystem& dem = step.system();
  std::optional<SettleLoop> resumed;
  if (controls.resume_state) {
    step.restore("settle", *controls.resume_state, resumed.emplace());
    check_restored(*resumed, dem, "settle");
  }
  progress.start_stage(layer > 0 || stage.layers > 1 ? fmt::format("dynamics, layer {}", layer + 1) : "dynamics");
  SampleRecorder recorder(sc, layer, series, progress, dem, particles,
                          {top_above_floor(dem, particles, sc.container), 0.0, 0.0}, std::string(),
                          controls.at_sample);
  const SettleResult result = settle(
      dem, particles, stage.quiet, box_density(sc),
      [&](const SettleSample& s) { recorder(time_offset + s.time, s, "settling"); },
      [&](const SettleLoop& loop) {
        at_safe_point(controls.safe_point, controls.stop, where_simulated("settling", dem.time() - loop.start),
                      [&](std::ostream& out) { step.save(out, "settle", loop); });
      },
      resumed ? &*resumed : nullptr);
  dem.finish();
  return settling_run(step, setup, sc, layer, result, particles);
} catch (const DemBlowUp& e) {
  throw blow_up_error(sc, particles, fmt::format("while settling, {}", e.what()), std::string_view());
}

PourRun pour_bed(const Scenario& sc, ParticleStore& particles, std::span<const double> radii,
                 const SphereMaterials& materials, const PouredShapes& shapes, std::uint32_t part,
                 double time_offset, const StageControls& controls, TimeSeries& series, Progress& progress) try {
  const PourSettings& settings = *sc.pour;
  const DynamicsStage& stage = *sc.dynamics;
  // The smallest sphere, a grain's smallest member among them (its radius at reach 1, scaled).
  double r_min = std::numeric_limits<double>::infinity();
  for (const double r : particles.radius) r_min = std::min(r_min, r);
  for (std::size_t k = 0; k < radii.size(); ++k) {
    const RigidBodyShape* shape = shapes.shape(k);
    if (!shape) r_min = std::min(r_min, radii[k]);
    else
      for (const double member : shape->member_radii) r_min = std::min(r_min, radii[k] * member);
  }
  DemSetup setup = dem_setup(sc, r_min, controls.threads);
  // The skin is chosen for the smallest sphere still to come, not the smallest in the bed.
  if (!(setup.settings.skin > 0.0)) setup.settings.skin = DemSystem::default_skin(r_min);

  // Resumed, the store holds the batches poured so far: the DEM state is restored over them.
  StepDem step(controls, particles, sc.container, setup);
  DemSystem& dem = step.system();
  PourLoop loop = begin_pour(dem, settings, radii, pour_stream(sc.seed, part));
  const PourReport planned = loop.report;  // what the scenario makes of this pour
  const bool resumed = controls.resume_state != nullptr;
  if (resumed) {
    step.restore("pour", *controls.resume_state, loop);
    // Restored: the same pour, within its batches, its numbers finite, its random stream live.
    if (!fits(loop, planned, dem)) throw DamagedCheckpoint("its pour step: its loop is not this pour's");
    if (loop.settling) check_restored(loop.settle, dem, "pour");
  }
  progress.start_stage(part > 0 ? fmt::format("pour, part {}", part + 1) : "pour");
  SampleRecorder recorder(sc, part, series, progress, dem, particles,
                          {top_above_floor(dem, particles, sc.container), settings.velocity, 0.0},
                          std::string(kPourCauses), controls.at_sample);
  PourHooks hooks;
  hooks.on_sample = [&](const SettleSample& s, std::string_view phase) {
    // The batches come in ever higher: what gravity can give grows with them.
    recorder.budget().height =
        std::max(recorder.budget().height, loop.report.highest_slab_top - sc.container.bounds.lo.z);
    recorder(time_offset + s.time, s, std::string(phase));
  };
  hooks.at_safe_point = [&](std::string_view phase) {
    at_safe_point(controls.safe_point, controls.stop, where_simulated(phase, dem.time() - loop.start),
                  [&](std::ostream& out) { step.save(out, "pour", loop); });
  };
  hooks.density = box_density(sc);
  SettleResult result;
  try {
    result = pour(dem, particles, sc.container, radii, settings, part, materials, shapes, stage.quiet, loop, resumed,
                  hooks);
  } catch (const PourInsertionError& e) {
    throw InputError(fmt::format("{}: pour.solid_fraction: {}", sc.file.string(), e.what()));
  }
  dem.finish();
  // Cut by max_time before its last batch has fallen its slab: a gas, not a bed.
  const double poured_for = dem.time() - loop.start;
  if (result.end == SettleEnd::MaxTime && poured_for < loop.next)
    throw InputError(fmt::format(
        "{}: dynamics.max_time: the pour ended at {:.4g} s, before its last batch could fall its slab (by {:.4g} s): "
        "its spheres never reached the bed, and its density would be that of a falling gas; expected a max_time "
        "of at least {:.3g} s and the time to settle",
        sc.file.string(), poured_for, loop.next, 2.0 * loop.next));
  PourRun out;
  out.pour = loop.report;
  out.settling = settling_run(step, setup, sc, part, result, particles);
  return out;
} catch (const DemBlowUp& e) {
  throw blow_up_error(sc, particles, fmt::format("while pouring, {}", e.what()), kPourCauses);
}

TapReport tap_bed(const Scenario& sc, ParticleStore& particles, double time_offset, const StageControls& controls,
                  TimeSeries& series, Progress& progress) try {
  const TappingSettings& settings = *sc.tapping;
  double r_min = std::numeric_limits<double>::infinity();
  for (const double r : particles.radius) r_min = std::min(r_min, r);
  const DemSetup setup = dem_setup(sc, r_min, controls.threads);
  const DensityProbe density = box_density(sc);

  StepDem step(controls, particles, sc.container, setup);
  DemSystem& dem = step.system();
  const bool resumed = controls.resume_state != nullptr;
  TapLoop loop;
  if (resumed) {
    step.restore("tap", *controls.resume_state, loop);
    // Restored: the same tapping, in the rest after tap `tap` (the samples of the taps before).
    if (!fits(loop, settings, dem)) throw DamagedCheckpoint("its tap step: its loop is not this tapping's");
  } else {
    loop = begin_tapping(dem, settings, density(particles));
  }
  progress.start_stage("tapping");
  const double amplitude = loop.report.amplitude, omega = 2.0 * std::numbers::pi * settings.frequency;
  SampleRecorder recorder(sc, 0, series, progress, dem, particles,
                          {top_above_floor(dem, particles, sc.container) + amplitude, amplitude * omega, amplitude},
                          std::string(kTapCauses), controls.at_sample);
  TapHooks hooks;
  hooks.on_sample = [&](const SettleSample& s, std::string_view phase) {
    recorder(time_offset + s.time, s, std::string(phase));
  };
  hooks.at_safe_point = [&](std::string_view phase) {
    at_safe_point(controls.safe_point, controls.stop, where_simulated(phase, dem.time() - loop.start),
                  [&](std::ostream& out) { step.save(out, "tap", loop); });
  };
  hooks.density = density;
  tap(dem, particles, settings, sc.dynamics->quiet, loop, resumed, hooks);
  dem.finish();
  TapReport report = loop.report;
  report.time_before = time_offset;
  for (TapSample& s : report.samples) s.time = time_offset + s.time;
  report.wall_clock_s = step.seconds();
  report.continues_dem_system = step.continued();
  return report;
} catch (const DemBlowUp& e) {
  throw blow_up_error(sc, particles, fmt::format("while tapping, {}", e.what()), kTapCauses);
}

// The hooks of a compaction step (rodding, jigging): samples to the recorder, safe points to
// the checkpoint as `kind`'s loop, the box density.
template <class Loop>
TapHooks compaction_hooks(const Scenario& sc, const StageControls& controls, StepDem& step, SampleRecorder& recorder,
                          const Loop& loop, double time_offset, std::string_view kind) {
  TapHooks hooks;
  hooks.on_sample = [&recorder, time_offset](const SettleSample& s, std::string_view phase) {
    recorder(time_offset + s.time, s, std::string(phase));
  };
  hooks.at_safe_point = [&controls, &step, &loop, kind](std::string_view phase) {
    at_safe_point(controls.safe_point, controls.stop, where_simulated(phase, step.system().time() - loop.start),
                  [&](std::ostream& out) { step.save(out, kind, loop); });
  };
  hooks.density = box_density(sc);
  return hooks;
}

double smallest_radius(const ParticleStore& particles) {
  double r_min = std::numeric_limits<double>::infinity();
  for (const double r : particles.radius) r_min = std::min(r_min, r);
  return r_min;
}

RoddingReport rod_bed(const Scenario& sc, ParticleStore& particles, double time_offset, const StageControls& controls,
                      TimeSeries& series, Progress& progress) try {
  const RoddingSettings& settings = *sc.rodding;
  const DemSetup setup = dem_setup(sc, smallest_radius(particles), controls.threads);
  StepDem step(controls, particles, sc.container, setup);
  DemSystem& dem = step.system();
  RodLoop loop;
  if (controls.resume_state) {
    step.restore("rod", *controls.resume_state, loop);
    if (!fits(loop, settings, dem)) throw DamagedCheckpoint("its rod step: its loop is not this rodding's");
  } else {
    // The top layer is the highest layer index in the bed; the layer below it, every lower one.
    std::uint32_t top_layer = 0;
    for (const std::uint32_t layer : particles.layer) top_layer = std::max(top_layer, layer);
    const RodTargets targets{sc.container.bounds.lo.z, layer_top(particles, top_layer, sc.container.bounds.lo.z)};
    try {
      loop = begin_rodding(dem, sc.container, settings, targets, box_density(sc)(particles));
    } catch (const std::invalid_argument& e) {
      throw InputError(fmt::format("{}: [rodding]: {}", sc.file.string(), e.what()));
    }
  }
  progress.start_stage("rodding");
  SampleRecorder recorder(sc, 0, series, progress, dem, particles,
                          {top_above_floor(dem, particles, sc.container), settings.speed, 0.0},
                          std::string(kRodCauses), controls.at_sample);
  const TapHooks hooks = compaction_hooks(sc, controls, step, recorder, loop, time_offset, "rod");
  rod(dem, particles, settings, sc.dynamics->quiet, loop, hooks);
  dem.finish();
  RoddingReport report = loop.report;
  report.time_before = time_offset;
  report.wall_clock_s = step.seconds();
  report.continues_dem_system = step.continued();
  return report;
} catch (const DemBlowUp& e) {
  throw blow_up_error(sc, particles, fmt::format("while rodding, {}", e.what()), kRodCauses);
}

JigReport jig_bed(const Scenario& sc, ParticleStore& particles, double time_offset, const StageControls& controls,
                  TimeSeries& series, Progress& progress) try {
  const JiggingSettings& settings = *sc.jigging;
  const DemSetup setup = dem_setup(sc, smallest_radius(particles), controls.threads);
  StepDem step(controls, particles, sc.container, setup);
  DemSystem& dem = step.system();
  const bool resumed = controls.resume_state != nullptr;
  JigLoop loop;
  if (resumed) {
    step.restore("jig", *controls.resume_state, loop);
    if (!fits(loop, settings, dem)) throw DamagedCheckpoint("its jig step: its loop is not this jigging's");
  } else {
    loop = begin_jigging(dem, settings, box_density(sc)(particles));
  }
  progress.start_stage("jigging");
  SampleRecorder recorder(sc, 0, series, progress, dem, particles,
                          {top_above_floor(dem, particles, sc.container) + settings.height, loop.report.impact_speed,
                           settings.height},
                          std::string(kJigCauses), controls.at_sample);
  const TapHooks hooks = compaction_hooks(sc, controls, step, recorder, loop, time_offset, "jig");
  jig(dem, particles, settings, sc.dynamics->quiet, loop, resumed, hooks);
  dem.finish();
  JigReport report = loop.report;
  report.time_before = time_offset;
  for (TapSample& s : report.samples) s.time = time_offset + s.time;
  report.wall_clock_s = step.seconds();
  report.continues_dem_system = step.continued();
  return report;
} catch (const DemBlowUp& e) {
  throw blow_up_error(sc, particles, fmt::format("while jigging, {}", e.what()), kJigCauses);
}

// A run of several materials: each one's values, and how a pair's coefficients are made.
std::string materials_note(const Scenario& sc) {
  std::string text = fmt::format("dynamics: {} materials, each sphere of its component's (particles.csv's material "
                                 "column):", material_count(sc));
  for (std::size_t k = 0; k < material_count(sc); ++k) {
    const Material& m = material_of(sc, k);
    const ContactParameters& c = m.contact;
    text += fmt::format(" {} (density {:g} kg/m3, E {:.3g} GPa, nu {:g}, mu {:g}, mu_wall {:g}, e {:g}, mu_r {:g}{});",
                        material_name(sc, k), m.density, 1e-9 * c.youngs_modulus, c.poisson_ratio, c.friction_particle,
                        c.friction_wall, c.restitution, c.rolling_friction,
                        c.rolling_model == RollingModel::SpringDashpot
                            ? fmt::format(", k_roll {:g} N/m, gamma_roll {:g} N s/m", c.rolling_stiffness,
                                          c.rolling_damping)
                            : std::string());
  }
  text += " a contact of two materials takes E* and G* from both (Hertz, Mindlin) and the geometric mean of their mu, "
          "e, mu_r (and rolling spring)";
  for (const MaterialPairCoefficients& p : sc.material_pairs)
    text += fmt::format(", except {}-{}, given in [[material_pairs]]", material_name(sc, p.first),
                        material_name(sc, p.second));
  return text + "; a sphere against a wall takes its own material's mu_wall, e and mu_r";
}

std::vector<std::string> dynamics_notes(const Scenario& sc, const SettlingReport& report) {
  const DynamicsStage& stage = *sc.dynamics;
  const ContactParameters& m = sc.material.contact;
  // The stage's time step and source are its first run's, the overlaps its last run's.
  const SettlingRun &first = report.runs.front(), &last = report.runs.back();
  std::vector<std::string> notes;
  notes.push_back(contact_law(sc.material.contact.friction_model).describe(sc.material.contact));
  if (material_count(sc) > 1) notes.push_back(materials_note(sc));
  if (material_count(sc) == 1) notes.push_back(fmt::format(
      "dynamics: Young's modulus {:.3g} GPa (walls {:.3g} GPa), Poisson ratio {:g}{}; mean overlap {:.2e} and "
      "maximum overlap {:.2e} of r_i + r_j at the end",
      1e-9 * m.youngs_modulus, 1e-9 * m.wall_youngs_modulus, m.poisson_ratio,
      m.youngs_modulus < 20e9 ? " (below the 30-70 GPa of natural aggregate: where the spheres stand for rock "
                                "this is a reduced stiffness, which allows a longer time step and overlaps more)"
                              : "",
      last.last.contacts.mean_overlap, last.last.contacts.max_overlap));
  notes.push_back(fmt::format("dynamics: time step {:.3g} s ({}), Rayleigh time of the smallest sphere {:.3g} s",
                              first.time_step,
                              first.time_step_from_scenario ? "scenario" : "time_step_safety x Rayleigh time",
                              first.rayleigh_time));
  if (stage.engine == DemEngine::Lammps)
    notes.push_back(fmt::format(
        "dynamics: the settle, pour and tap steps ran in LAMMPS ({}{}), each from a deck aggpack wrote "
        "(<output>/lammps/): the same law, time step, skin, walls and gravity, a pour's batches of aggpack's own "
        "random gas, a tap's container moved as aggpack's; {}; the stopping rule is the quiet criterion's energy "
        "condition (without its density condition) or max_time; the spheres' velocities were set to zero on import",
        stage.lammps_ranks > 1 ? fmt::format("mpirun -np {} ", stage.lammps_ranks) : "", stage.lammps_binary,
        contact_law(sc.material.contact.friction_model).lammps_differences));
  if (stage.layers > 1)
    notes.push_back(fmt::format("dynamics: layer by layer ({} layers, equal particle counts in deposition order): "
                                "each layer is deposited, then settled with the layers below frozen",
                                stage.layers));
  const std::size_t cut = report.runs_ended_by_max_time();
  if (cut > 0)
    notes.push_back(fmt::format("dynamics: {} settling run{} reached max_time = {:g} s before the bed was quiet; "
                                "the bed may still be moving",
                                cut, cut == 1 ? "" : "s", stage.quiet.max_time));
  return notes;
}

}  // namespace aggpack
