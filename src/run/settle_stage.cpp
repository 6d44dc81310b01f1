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
#include "aggpack/deposition/gas_insertion.hpp"
#include "aggpack/dynamics/settle.hpp"
#include "aggpack/run/analyze.hpp"
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


DemSetup dem_setup(const Scenario& sc, double r_min, int threads) {
  const DynamicsStage& stage = *sc.dynamics;
  if (!std::isfinite(r_min))
    throw InputError(fmt::format("{}: [dynamics]: there are no particles to settle", sc.file.string()));
  DemSetup setup{[&] {
                   try {
                     return make_contact_model(sc.material.contact);
                   } catch (const InputError& e) {
                     throw InputError(fmt::format("{}: [material]: {}", sc.file.string(), e.what()));
                   }
                 }(),
                 stage.dem, stable_time_scale(sc.material.contact, r_min, sc.material.density)};
  setup.settings.time_step = stage.time_step.step(setup.rayleigh);
  setup.settings.threads = threads;
  return setup;
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
  const double rayleigh = stable_time_scale(sc.material.contact, r_min, sc.material.density);
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

// A step's state at a safe point, for a checkpoint: its kind (checked when it is read back),
// the DEM's state, its loop's, and the wall clock it has taken so far.
template <class Loop>
void save_step_state(std::ostream& out, std::string_view kind, const DemSystem& dem, const Loop& loop,
                     Clock::time_point t0) {
  {
    cereal::BinaryOutputArchive ar(out);
    const double elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
    ar(std::string(kind), loop, elapsed);
  }
  dem.save_state(out);
}
// Restores what save_step_state() saved into `dem` and `loop`; returns the start time that
// makes the step's wall clock count what it took before too. DamagedCheckpoint when the bytes
// do not decode, or not to a state of this step (the loop is checked by the step itself).
template <class Loop>
Clock::time_point restore_step_state(std::string_view kind, const std::string& state, DemSystem& dem, Loop& loop) {
  std::string saved_kind;
  double elapsed = 0.0;
  std::size_t dem_state_at = 0;
  try {
    CheckedInputArchive ar(state);
    ar(saved_kind);
    if (saved_kind != kind)
      throw DamagedCheckpoint(
          fmt::format("the checkpoint holds a {} step where the protocol has a {} step", saved_kind, kind));
    ar(loop, elapsed);
    dem_state_at = ar.position();
  } catch (const cereal::Exception& e) {
    throw DamagedCheckpoint(fmt::format("its {} step: {}", kind, e.what()));
  }
  try {
    dem.restore_state(std::string_view(state).substr(dem_state_at));
  } catch (const InputError& e) {
    throw DamagedCheckpoint(fmt::format("its {} step: {}", kind, e.what()));
  }
  // At most a billion seconds: its count of clock ticks must fit the clock.
  if (!(elapsed >= 0.0 && elapsed <= 1e9))
    throw DamagedCheckpoint(fmt::format("its {} step: {} s of wall clock", kind, elapsed));
  return Clock::now() - std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(elapsed));
}

// A settling loop restored from a checkpoint: it began before the system's time and step now,
// and has sampled (its quiet window holds the samples so far).
void check_restored(const SettleLoop& loop, const DemSystem& dem, std::string_view kind) {
  if (!(loop.start >= 0.0 && loop.start <= dem.time()) || loop.start_steps > dem.steps() || loop.window.empty())
    throw DamagedCheckpoint(fmt::format("its {} step: its settling loop does not fit its DEM state", kind));
}

std::string where_simulated(std::string_view phase, double simulated) {
  return fmt::format("while {} at {:.4f} s simulated", phase, simulated);
}

// A pour's loop between samples: the batch falling (or, once all are in, the settling).
struct PourLoop {
  std::size_t batch = 0;     // the batch in flight
  double next = 0.0;         // s, when the next batch comes
  Rng rng{0, 0};
  PourReport report;
  double weight = 0.0;
  bool settling = false;     // all batches in: the bed falls until quiet
  SettleLoop settle;
  double poured_at = 0.0;    // s, when the last batch came
  std::size_t pour_steps = 0;
  std::size_t block_steps_left = 0;  // of the sample interval in progress (0: at a sample)
  template <class Archive>
  void serialize(Archive& ar) {
    ar(batch, next, raw_value(rng), raw_value(report), weight, settling, settle, poured_at, pour_steps,
       block_steps_left);
  }
};

// A tapping's loop: inside tap `tap` (its steps not all run yet), or in the rest after it.
struct TapLoop {
  std::size_t tap = 1;
  std::size_t tap_steps_left = 0;    // of the tap in progress (0: in the rest)
  double rest_end = 0.0;
  std::size_t rest_steps_left = 0;   // of the rest's sample interval in progress (0: at a sample)
  std::optional<double> quiet_since;
  SettleSample last;
  TapReport report;
  template <class Archive>
  void serialize(Archive& ar) {
    ar(tap, tap_steps_left, rest_end, rest_steps_left, quiet_since, last, report);
  }
};

SettlingRun settling_run(const DemSystem& dem, const DemSetup& setup, const Scenario& sc, std::uint32_t layer,
                         const SettleResult& result, std::size_t steps, double simulated, Clock::time_point t0,
                         const ParticleStore& particles) {
  const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  SettlingRun run;
  run.layer = layer;
  run.particles_settled = dem.free_count();
  run.particles_frozen = particles.size() - dem.free_count();
  run.ended_by = result.end;
  run.simulated_time = simulated;
  run.steps = steps;
  run.time_step = setup.settings.time_step;
  run.rayleigh_time = setup.rayleigh;
  run.time_step_from_scenario = sc.dynamics->time_step.fixed.has_value();
  run.skin = dem.skin();
  run.neighbour_list_builds = dem.rebuilds();
  run.last = result.last;
  run.wall_clock_s = seconds;
  run.particle_steps_per_second =
      seconds > 0 ? static_cast<double>(dem.free_count()) * static_cast<double>(steps) / seconds : 0.0;
  run.threads = dem.threads();
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

  auto t0 = Clock::now();
  DemSystem dem(particles, sc.container, setup.model, setup.settings, std::move(frozen));
  std::optional<SettleLoop> resumed;
  if (controls.resume_state) {
    t0 = restore_step_state("settle", *controls.resume_state, dem, resumed.emplace());
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
                      [&](std::ostream& out) { save_step_state(out, "settle", dem, loop, t0); });
      },
      resumed ? &*resumed : nullptr);
  dem.finish();
  return settling_run(dem, setup, sc, layer, result, result.steps, result.simulated_time, t0, particles);
} catch (const DemBlowUp& e) {
  throw blow_up_error(sc, particles, fmt::format("while settling, {}", e.what()), std::string_view());
}

PourRun pour_bed(const Scenario& sc, ParticleStore& particles, std::span<const double> radii, std::uint32_t part,
                 double time_offset, const StageControls& controls, TimeSeries& series, Progress& progress) try {
  const PourSettings& pour = *sc.pour;
  const DynamicsStage& stage = *sc.dynamics;
  double r_min = std::numeric_limits<double>::infinity(), r_max = 0.0;
  for (const double r : particles.radius) r_min = std::min(r_min, r);
  for (const double r : radii) r_min = std::min(r_min, r), r_max = std::max(r_max, r);
  DemSetup setup = dem_setup(sc, r_min, controls.threads);
  // The skin is chosen for the smallest sphere still to come, not the smallest in the bed.
  if (!(setup.settings.skin > 0.0)) setup.settings.skin = 0.1 * (2.0 * r_min);

  // Resumed, the store holds the batches poured so far: the DEM state is restored over them.
  auto t0 = Clock::now();
  DemSystem dem(particles, sc.container, setup.model, setup.settings);
  PourLoop loop;
  PourReport& report = loop.report;
  const bool resumed = controls.resume_state != nullptr;
  PourReport planned;  // what the scenario makes of this pour
  planned.poured = radii.size();
  planned.batches = std::min<std::size_t>(pour.batches, std::max<std::size_t>(1, radii.size()));
  planned.solid_fraction = pour.solid_fraction;
  planned.velocity = pour.velocity;
  planned.gap = pour.gap.value_or(2.0 * r_max);
  planned.lowest_slab_bottom = std::numeric_limits<double>::infinity();
  if (resumed) {
    t0 = restore_step_state("pour", *controls.resume_state, dem, loop);
    // Restored: the same pour, within its batches, its numbers finite, its random stream live.
    if (report.poured != planned.poured || report.batches != planned.batches ||
        report.solid_fraction != planned.solid_fraction || report.velocity != planned.velocity ||
        report.gap != planned.gap || loop.batch >= report.batches || !std::isfinite(loop.next) ||
        !std::isfinite(loop.weight) || !std::isfinite(loop.poured_at) || loop.pour_steps > dem.steps() ||
        loop.rng.stuck())
      throw DamagedCheckpoint("its pour step: its loop is not this pour's");
    if (loop.settling) check_restored(loop.settle, dem, "pour");
  } else {
    loop.rng = pour_stream(sc.seed, part);
    report = planned;
  }
  progress.start_stage(part > 0 ? fmt::format("pour, part {}", part + 1) : "pour");
  SampleRecorder recorder(sc, part, series, progress, dem, particles,
                          {top_above_floor(dem, particles, sc.container), pour.velocity, 0.0}, std::string(kPourCauses),
                          controls.at_sample);
  const double g = norm(setup.settings.gravity);
  const std::size_t steps_per_sample = stage.quiet.steps_per_sample(setup.settings.time_step);
  const auto top_of_bed = [&] {
    double top = sc.container.bounds.lo.z;
    for (std::size_t i = 0; i < particles.size(); ++i) top = std::max(top, particles.position[i].z + particles.radius[i]);
    return top;
  };
  const auto safe_point = [&](const std::string& where) {
    at_safe_point(controls.safe_point, controls.stop, where, [&](std::ostream& out) { save_step_state(out, "pour", dem, loop, t0); });
  };

  // A resumed pour continues where its batch was falling, or where the bed was settling.
  bool batch_in = resumed;
  if (!loop.settling) {
    for (; loop.batch < report.batches; ++loop.batch) {
      if (!batch_in) {
        const std::size_t b = loop.batch;
        const std::size_t begin = radii.size() * b / report.batches, end = radii.size() * (b + 1) / report.batches;
        const std::span<const double> batch = radii.subspan(begin, end - begin);
        double solid = 0.0;
        for (const double r : batch) solid += 4.0 / 3.0 * std::numbers::pi * r * r * r;
        const auto t_insert = Clock::now();
        const InsertionRegion slab =
            insertion_region(sc.container, top_of_bed() + report.gap, solid, pour.solid_fraction);
        std::vector<Vec3> at;
        try {
          at = random_gas(sc.container, slab, batch, loop.rng);
        } catch (const InputError& e) {
          throw InputError(fmt::format("{}: pour.solid_fraction: {}", sc.file.string(), e.what()));
        }
        for (std::size_t k = 0; k < batch.size(); ++k) {
          particles.add(at[k], batch[k], sc.material.density, part);
          particles.velocity.back() = {0.0, 0.0, -pour.velocity};
        }
        report.insertion_wall_clock_s += std::chrono::duration<double>(Clock::now() - t_insert).count();
        report.lowest_slab_bottom = std::min(report.lowest_slab_bottom, slab.bottom);
        report.highest_slab_top = std::max(report.highest_slab_top, slab.top);
        recorder.budget().height =
            std::max(recorder.budget().height, report.highest_slab_top - sc.container.bounds.lo.z);
        dem.admit_new_particles();
        loop.weight = weight_energy(dem, particles);
        // The next batch comes once this one has fallen through its slab's height in free
        // fall (as LAMMPS's fix pour times its insertions), or at max_time; after the last,
        // that time is when the pour has reached the bed.
        const double height = slab.top - slab.bottom;
        const double fall = (std::sqrt(pour.velocity * pour.velocity + 2.0 * g * height) - pour.velocity) / g;
        loop.next = dem.time() + fall;
        if (b + 1 == report.batches) break;
      }
      batch_in = false;
      while (loop.block_steps_left > 0 || dem.time() < std::min(loop.next, stage.quiet.max_time)) {
        const std::string phase = fmt::format("pouring, {} of {} in", particles.size(), radii.size());
        if (loop.block_steps_left == 0) loop.block_steps_left = steps_per_sample;
        run_block(dem, loop.block_steps_left, [&] { safe_point(where_simulated(phase, dem.time())); });
        const SettleSample s = sample_system(dem, particles, loop.weight, nullptr);  // no density: the bed is still being built
        recorder(time_offset + s.time, s, phase);
        safe_point(where_simulated(phase, s.time));
      }
    }
    loop.poured_at = dem.time();
    loop.pour_steps = dem.steps();
  }
  QuietCriterion rest = stage.quiet;
  rest.max_time = std::max(rest.sample_interval, stage.quiet.max_time - loop.poured_at);
  const double poured_at = loop.poured_at;
  const SettleResult result = settle(
      dem, particles, rest, box_density(sc),
      [&](const SettleSample& s) {
        SettleSample shifted = s;
        shifted.time += poured_at;
        recorder(time_offset + shifted.time, shifted, "settling");
      },
      [&](const SettleLoop& settling) {
        loop.settling = true;
        loop.settle = settling;
        safe_point(where_simulated("settling", dem.time()));
      },
      loop.settling ? &loop.settle : nullptr);
  dem.finish();
  // Cut by max_time before its last batch has fallen its slab: a gas, not a bed.
  if (result.end == SettleEnd::MaxTime && dem.time() < loop.next)
    throw InputError(fmt::format(
        "{}: dynamics.max_time: the pour ended at {:.4g} s, before its last batch could fall its slab (by {:.4g} s): "
        "its spheres never reached the bed, and its density would be that of a falling gas; expected a max_time "
        "of at least {:.3g} s and the time to settle",
        sc.file.string(), dem.time(), loop.next, 2.0 * loop.next));
  SettleResult whole = result;
  whole.last.time += poured_at;
  PourRun out;
  out.pour = report;
  out.settling = settling_run(dem, setup, sc, part, whole, loop.pour_steps + result.steps,
                              poured_at + result.simulated_time, t0, particles);
  return out;
} catch (const DemBlowUp& e) {
  throw blow_up_error(sc, particles, fmt::format("while pouring, {}", e.what()), kPourCauses);
}

TapReport tap_bed(const Scenario& sc, ParticleStore& particles, double time_offset, const StageControls& controls,
                  TimeSeries& series, Progress& progress) try {
  const TappingSettings& tapping = *sc.tapping;
  const DynamicsStage& stage = *sc.dynamics;
  double r_min = std::numeric_limits<double>::infinity();
  for (const double r : particles.radius) r_min = std::min(r_min, r);
  const DemSetup setup = dem_setup(sc, r_min, controls.threads);
  const double g = norm(setup.settings.gravity);
  const double omega = 2.0 * std::numbers::pi * tapping.frequency;
  const DensityProbe density = box_density(sc);

  auto t0 = Clock::now();
  DemSystem dem(particles, sc.container, setup.model, setup.settings);
  TapLoop loop;
  TapReport& report = loop.report;
  const bool resumed = controls.resume_state != nullptr;
  if (resumed) {
    t0 = restore_step_state("tap", *controls.resume_state, dem, loop);
    // Restored: the same tapping, in the rest after tap `tap` (the samples of the taps before).
    const double dt = setup.settings.time_step, until_rest_end = loop.rest_end - dem.time();
    if (report.taps != tapping.taps || report.intensity != tapping.intensity ||
        report.frequency != tapping.frequency || report.rest_time != tapping.rest_time ||
        report.rest_until_quiet != tapping.rest_until_quiet || report.time_step != dt || loop.tap < 1 ||
        loop.tap > tapping.taps || report.samples.size() != loop.tap - 1 ||
        // Inside a tap (its steps still to run, at most one tap's), or in the rest after it.
        !(loop.tap_steps_left > 0 ? static_cast<double>(loop.tap_steps_left) <= 0.5 / tapping.frequency / dt + 2.0
                                  : until_rest_end >= -dt && until_rest_end <= tapping.rest_time + dt) ||
        static_cast<double>(loop.rest_steps_left) > tapping.rest_time / dt + 2.0 ||
        (loop.quiet_since && !std::isfinite(*loop.quiet_since)))
      throw DamagedCheckpoint("its tap step: its loop is not this tapping's");
  } else {
    report.taps = tapping.taps;
    report.intensity = tapping.intensity;
    report.frequency = tapping.frequency;
    report.amplitude = tapping.intensity * g / (omega * omega);
    report.rest_time = tapping.rest_time;
    report.rest_until_quiet = tapping.rest_until_quiet;
    report.time_step = setup.settings.time_step;
    report.density_before = density(particles);
    report.time_before = time_offset;
  }
  progress.start_stage("tapping");
  SampleRecorder recorder(sc, 0, series, progress, dem, particles,
                          {top_above_floor(dem, particles, sc.container) + report.amplitude, report.amplitude * omega,
                           report.amplitude},
                          std::string(kTapCauses), controls.at_sample);
  const double weight = weight_energy(dem, particles);
  const double dt = setup.settings.time_step;
  const std::size_t steps_per_sample = stage.quiet.steps_per_sample(dt);
  // A sample of the rest (no density: it is measured once per tap), then a safe point.
  const auto sample = [&](const std::string& phase) {
    loop.last = sample_system(dem, particles, weight, nullptr);
    recorder(time_offset + loop.last.time, loop.last, phase);
  };
  const auto safe_point = [&](const std::string& phase) {
    at_safe_point(controls.safe_point, controls.stop, where_simulated(phase, dem.time()),
                  [&](std::ostream& out) { save_step_state(out, "tap", dem, loop, t0); });
  };
  // A resumed tapping continues inside the tap, or in the rest, where it stopped.
  bool resuming = resumed;
  for (; loop.tap <= tapping.taps; ++loop.tap) {
    const std::string phase = fmt::format("tap {} of {}", loop.tap, tapping.taps);
    if (!resuming) {
      const ContainerMotion tap{dem.time(), report.amplitude, omega, 0.5};
      dem.set_container_motion(tap);
      // The tap runs to the step after its end, so the container is at rest again.
      loop.tap_steps_left = static_cast<std::size_t>(std::ceil((tap.end() - dem.time()) / dt)) + 1;
    }
    if (!resuming || loop.tap_steps_left > 0) {
      run_block(dem, loop.tap_steps_left, [&] { safe_point(phase); });
      loop.rest_end = dem.time() + tapping.rest_time;
      loop.quiet_since.reset();  // the first sample of the current quiet spell
      sample(phase);
      safe_point(phase);
    }
    resuming = false;
    while (loop.rest_steps_left > 0 || dem.time() < loop.rest_end - 0.5 * dt) {
      if (loop.rest_steps_left == 0)
        loop.rest_steps_left =
            std::min(steps_per_sample, static_cast<std::size_t>(std::llround((loop.rest_end - dem.time()) / dt)));
      run_block(dem, loop.rest_steps_left, [&] { safe_point(phase); });
      sample(phase);
      if (tapping.rest_until_quiet) {
        if (loop.last.translational_per_particle_mgd > stage.quiet.kinetic_fraction) loop.quiet_since.reset();
        else if (!loop.quiet_since) loop.quiet_since = loop.last.time;
        if (loop.quiet_since && loop.last.time - *loop.quiet_since >= stage.quiet.window) break;
      }
      safe_point(phase);
    }
    report.samples.push_back(
        {loop.tap, time_offset + dem.time(), density(particles), loop.last.translational_per_particle_mgd});
  }
  dem.finish();
  report.simulated_time = dem.time();
  report.steps = dem.steps();
  report.wall_clock_s = std::chrono::duration<double>(Clock::now() - t0).count();
  return report;
} catch (const DemBlowUp& e) {
  throw blow_up_error(sc, particles, fmt::format("while tapping, {}", e.what()), kTapCauses);
}

std::vector<std::string> dynamics_notes(const Scenario& sc, const SettlingReport& report) {
  const DynamicsStage& stage = *sc.dynamics;
  const ContactParameters& m = sc.material.contact;
  // The stage's time step and source are its first run's, the overlaps its last run's.
  const SettlingRun &first = report.runs.front(), &last = report.runs.back();
  std::vector<std::string> notes;
  notes.push_back(contact_law(sc.material.contact.friction_model).describe(sc.material.contact));
  notes.push_back(fmt::format(
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
