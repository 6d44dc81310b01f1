#include "aggpack/run/lammps_steps.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <unistd.h>
#include <variant>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <nlohmann/json.hpp>

#include "aggpack/core/error.hpp"
#include "aggpack/core/input_file.hpp"
#include "aggpack/core/overloaded.hpp"
#include "aggpack/core/rigid_fit.hpp"
#include "aggpack/core/version.hpp"
#include "aggpack/deposition/gas_insertion.hpp"
#include "aggpack/dynamics/contact_law_registry.hpp"
#include "aggpack/dynamics/pour.hpp"
#include "aggpack/io/atomic_file.hpp"
#include "aggpack/io/lammps_data.hpp"
#include "aggpack/io/particle_file.hpp"
#include "aggpack/lammps/process.hpp"
#include "aggpack/run/generate_sizes.hpp"
#include "aggpack/run/preflight.hpp"
#include "aggpack/run/settle_stage.hpp"
#include "aggpack/run/steps.hpp"

namespace aggpack {

namespace {

using Clock = std::chrono::steady_clock;

// The deck run by LAMMPS (lammps/process), shown on the progress line while it runs.
std::string run_lammps(const Scenario& sc, const std::filesystem::path& folder, const LammpsDeck& deck,
                       Progress& progress) {
  progress.start_stage(fmt::format("{} in LAMMPS", deck.step));
  progress.update({lammps_command_line(*sc.dynamics), folder.string()}, 0.0, Progress::TimeLeft::AtMost);
  try {
    std::string log = run_lammps(sc, folder, deck);
    progress.clear();
    return log;
  } catch (...) {
    progress.clear();
    throw;
  }
}

double smallest_radius(std::span<const double> radii) {
  double r_min = std::numeric_limits<double>::infinity();
  for (const double r : radii) r_min = std::min(r_min, r);
  return r_min;
}

// The positions of `dump` put in place of the store's first spheres (same radii, by id),
// velocities zeroed. A grain's pose is fitted to where its spheres are (fit_rigid_pose; in a
// periodic box each sphere taken to the image nearest its grain's first), and its spheres put
// back exactly where that pose holds them (wrapped into a periodic box, the centre too):
// refused when one is farther from it than a
// billionth of the grain's reach (the file's spheres are not this rigid grain's).
void take_positions(ParticleStore& particles, const ParticleStore& dump, const std::string& name, std::size_t count,
                    const Container& container) {
  if (dump.size() != count)
    throw InputError(fmt::format("{}: holds {} spheres, the bed {}", name, dump.size(), count));
  for (std::size_t i = 0; i < count; ++i) {
    const double r = dump.radius[i];
    if (std::abs(r - particles.radius[i]) > 1e-9 * particles.radius[i])
      throw InputError(fmt::format("{}: sphere id {} has radius {:.17g} m, the bed's sphere {} {:.17g} m: the file is "
                                   "not of this bed",
                                   name, i + 1, r, i + 1, particles.radius[i]));
    particles.position[i] = dump.position[i];
    particles.velocity[i] = {};
    particles.angular_velocity[i] = {};
  }
  RigidBodies& bodies = particles.bodies;
  std::vector<Vec3> places;
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const std::size_t first = bodies.first_member[b], members = bodies.member_count[b];
    if (first + members > count) continue;  // a grain beyond the file's spheres keeps its place
    places.clear();
    double reach = 0.0;
    for (std::size_t i = first; i < first + members; ++i) {
      places.push_back(dump.position[first] + container.minimum_image(dump.position[i] - dump.position[first]));
      reach = std::max(reach, norm(particles.body_offset[i]) + particles.radius[i]);
    }
    const RigidPose pose =
        fit_rigid_pose(std::span<const Vec3>(particles.body_offset).subspan(first, members), places);
    if (!(pose.largest_miss <= 1e-9 * reach))
      throw InputError(fmt::format("{}: the spheres {} to {} of grain {} are not where one rigid grain would hold them "
                                   "(one is {:.3g} m from its place, the grain reaching {:.3g} m): the file is not "
                                   "of this bed",
                                   name, first + 1, first + members, b + 1, pose.largest_miss, reach));
    // Each wrapped into a periodic box, as aggpack's own DEM leaves them at a step's end.
    bodies.position[b] = container.wrapped(pose.centre);
    bodies.orientation[b] = pose.orientation;
    bodies.velocity[b] = {};
    bodies.angular_velocity[b] = {};
    for (std::size_t i = first; i < first + members; ++i)
      particles.position[i] = container.wrapped(pose.centre + rotate(pose.orientation, particles.body_offset[i]));
  }
}

// The bed as LAMMPS left it (velocities zeroed), measured as aggpack's samples measure it
// (contacts, density), frozen below `layer`, with LAMMPS's translational kinetic energy per
// sum(m g d) of the free spheres, `energy`. The deck measures only that ratio: the energy in
// joules is that ratio times aggpack's sum(m g d) of the same spheres (the deck's divisor),
// and the rotational energy, which the deck does not measure, is NaN (an empty cell).
SettleSample measured_sample(const Scenario& sc, ParticleStore& particles, std::uint32_t layer, bool density,
                             double energy) {
  std::vector<std::uint8_t> frozen(particles.size());
  double r_min = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < particles.size(); ++i) {
    frozen[i] = particles.layer[i] < layer ? 1 : 0;
    if (!frozen[i]) r_min = std::min(r_min, particles.radius[i]);
  }
  const DemSetup setup = dem_setup(sc, r_min, 1);
  DemSystem measure(particles, sc.container, setup.model, setup.settings, frozen);
  const double weight = weight_energy(measure, particles);
  const auto lammps_energies = [&](SettleSample s) {
    s.translational_per_particle_mgd = energy;
    s.kinetic_energy.translational = energy * weight;
    s.kinetic_energy.rotational = std::numeric_limits<double>::quiet_NaN();
    return s;
  };
  if (density) {
    try {
      return lammps_energies(sample_system(
          measure, particles, weight, [&](const ParticleStore& store) { return analyse_bed(sc, store).density.mean; }));
    } catch (const InputError&) {
      // the boxes do not fit this bed: the sample has no density
    }
  }
  return lammps_energies(sample_system(measure, particles, weight, nullptr));
}

double box_density_or_nan(const Scenario& sc, const ParticleStore& particles) {
  try {
    return analyse_bed(sc, particles).density.mean;
  } catch (const InputError&) {
    return std::numeric_limits<double>::quiet_NaN();
  }
}

void append_sample(TimeSeries& series, double time, std::uint32_t layer, const SettleSample& s) {
  series.samples.push_back({time, layer, s.density, s.translational_per_particle_mgd, s.kinetic_energy.translational,
                            s.kinetic_energy.rotational, s.contacts.mean_overlap, s.contacts.max_overlap,
                            s.contacts.coordination});
}

// A settle or pour run by LAMMPS reported as aggpack's own: the end, the time, the last sample.
SettlingRun lammps_settling_run(const Scenario& sc, ParticleStore& particles, std::uint32_t layer,
                                std::uint32_t frozen_below, const SettledLine& end, double r_min, Clock::time_point t0,
                                double time_offset, TimeSeries& series) {
  const DynamicsStage& stage = *sc.dynamics;
  const DemSetup setup = dem_setup(sc, r_min, 1);
  SettleSample last = measured_sample(sc, particles, frozen_below, true, end.energy);
  last.time = end.time;
  append_sample(series, time_offset + end.time, layer, last);
  SettlingRun run;
  run.layer = layer;
  for (std::size_t i = 0; i < particles.size(); ++i) ++(particles.layer[i] < frozen_below ? run.particles_frozen
                                                                                           : run.particles_settled);
  run.ended_by = end.time < stage.quiet.max_time * (1.0 - 1e-12) ? SettleEnd::Quiet : SettleEnd::MaxTime;
  run.simulated_time = end.time;
  run.time_step = setup.settings.time_step;
  run.steps = static_cast<std::size_t>(std::llround(end.time / run.time_step));
  run.rayleigh_time = setup.rayleigh;
  run.time_step_from_scenario = stage.time_step.fixed.has_value();
  run.skin = lammps_skin(setup, r_min);
  run.last = last;
  run.wall_clock_s = std::chrono::duration<double>(Clock::now() - t0).count();
  run.particle_steps_per_second =
      run.wall_clock_s > 0 ? static_cast<double>(run.particles_settled * run.steps) / run.wall_clock_s : 0.0;
  run.threads = 1;
  run.lammps_ranks = stage.lammps_ranks;
  return run;
}

// A run's seed as its summary.json gives it: in the range of a scenario's seed, 0 to 2^63 - 1
// (an edited -1 would otherwise become 2^64 - 1).
std::uint64_t recorded_seed(const nlohmann::json& seed, const std::filesystem::path& summary_file) {
  constexpr auto kMaxSeed = static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max());
  const bool in_range = seed.is_number_unsigned()  ? seed.get<std::uint64_t>() <= kMaxSeed
                        : seed.is_number_integer() ? seed.get<std::int64_t>() >= 0
                                                   : false;
  if (!in_range)
    throw InputError(fmt::format("{}: seed {}: expected an integer from 0 to {}, as a scenario's seed",
                                 summary_file.string(), seed.dump(), std::numeric_limits<std::int64_t>::max()));
  return seed.get<std::uint64_t>();
}

// Every file of `deck` saying `note` (what the bed is, when not what its step expects): a
// comment under the deck's first line, and each data file's title line (LAMMPS skips it).
void add_note(LammpsDeck& deck, const std::string& note) {
  for (auto& [name, text] : deck.files) {
    const std::size_t first_line_end = text.find('\n');
    if (name == deck.deck_file) text.insert(first_line_end + 1, fmt::format("# {}.\n", note));
    else if (name.ends_with(".data")) text.insert(first_line_end, fmt::format(". {}.", note));
  }
}

std::filesystem::path lammps_folder(const Scenario& sc, const std::string& name) {
  return sc.output.directory / "lammps" / name;
}
}  // namespace

SettlingRun settle_in_lammps(const Scenario& sc, ParticleStore& particles, std::uint32_t layer, double time_offset,
                             TimeSeries& series, Progress& progress) {
  const auto t0 = Clock::now();
  const std::filesystem::path folder = lammps_folder(sc, fmt::format("settle_layer_{}", layer + 1));
  const std::string log = run_lammps(sc, folder, lammps_deck(sc, particles, SettleStep{layer}), progress);
  const std::filesystem::path dump = folder / LammpsDeck::kDumpFile;
  take_positions(particles, read_lammps_dump(dump, sc).particles, dump.string(), particles.size(), sc.container);
  double r_min = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < particles.size(); ++i)
    if (particles.layer[i] >= layer) r_min = std::min(r_min, particles.radius[i]);
  return lammps_settling_run(sc, particles, layer, layer, settled_line(log, folder), r_min, t0, time_offset, series);
}

PourRun pour_in_lammps(const Scenario& sc, ParticleStore& particles, std::span<const double> radii,
                       const SphereMaterials& materials, const PouredShapes& shapes, const PourStep& step,
                       double time_offset, TimeSeries& series, Progress& progress) {
  const auto t0 = Clock::now();
  const std::filesystem::path folder = lammps_folder(sc, fmt::format("pour_part_{}", step.layer + 1));
  const LammpsDeck deck = lammps_deck(sc, particles, step, radii, materials.of, shapes);
  const std::string log = run_lammps(sc, folder, deck, progress);
  const std::filesystem::path dump_file = folder / LammpsDeck::kDumpFile;
  const LammpsBed dump = read_lammps_dump(dump_file, sc);
  // The poured spheres and grains come after the bed's, in the order aggpack inserts them
  // (a grain's pose is fitted to its spheres in the dump).
  for (std::size_t k = 0; k < radii.size(); ++k)
    add_poured(particles, {}, radii[k], shapes.shape(k), {}, {}, materials.density_of(k), step.layer,
               materials.material(k));
  take_positions(particles, dump.particles, dump_file.string(), particles.size(), sc.container);

  const PourSettings& pour = *sc.pour;
  const PourSchedule schedule = pour_schedule(pour, radii.size());
  PourRun out;
  PourReport& report = out.pour;
  report = planned_pour(pour, radii);
  // Each batch's slab: its bottom as the deck printed it, its height as aggpack's.
  const std::vector<std::string> lines = tagged_lines(log, "aggpack-batch: ");
  if (lines.size() != report.batches)
    throw InputError(fmt::format("{}: the LAMMPS log has {} \"aggpack-batch:\" lines, expected {}",
                                 (folder / LammpsDeck::kLogFile).string(), lines.size(), report.batches));
  for (std::size_t k = 0; k < report.batches; ++k) {
    double bottom = 0.0;
    unsigned long index = 0;
    if (std::sscanf(lines[k].c_str(), "aggpack-batch: %lu bottom %lf", &index, &bottom) != 2)
      throw InputError(fmt::format("{}: malformed line \"{}\"", (folder / LammpsDeck::kLogFile).string(), lines[k]));
    const InsertionRegion slab =
        insertion_region(sc.container, bottom, solid_volume(schedule.batch(radii, k)), pour.solid_fraction);
    report.lowest_slab_bottom = std::min(report.lowest_slab_bottom, slab.bottom);
    report.highest_slab_top = std::max(report.highest_slab_top, slab.top);
  }
  const double r_min = smallest_radius(particles.radius);
  out.settling = lammps_settling_run(sc, particles, step.layer, 0, settled_line(log, folder), r_min, t0, time_offset,
                                     series);
  return out;
}

TapReport tap_in_lammps(const Scenario& sc, ParticleStore& particles, std::size_t tapping_index, double time_offset,
                        TimeSeries& series, Progress& progress) {
  const auto t0 = Clock::now();
  const TappingSettings& tapping = *sc.tapping;
  const std::filesystem::path folder = lammps_folder(sc, fmt::format("tap_{}", tapping_index + 1));
  const LammpsDeck deck = lammps_deck(sc, particles, TapStep{});
  const DemSetup setup = dem_setup(sc, smallest_radius(particles.radius), 1);
  TapReport report;
  report.taps = tapping.taps;
  report.intensity = tapping.intensity;
  report.frequency = tapping.frequency;
  report.amplitude = tap_amplitude(tapping, norm(sc.dynamics->dem.gravity));
  report.rest_time = tapping.rest_time;
  report.rest_until_quiet = tapping.rest_until_quiet;
  report.time_step = setup.settings.time_step;
  report.density_before = box_density_or_nan(sc, particles);
  report.time_before = time_offset;
  report.lammps_ranks = sc.dynamics->lammps_ranks;
  const std::string log = run_lammps(sc, folder, deck, progress);

  // The bed after each tap's rest, from its dump: the compaction curve, as aggpack measures it.
  const std::vector<std::string> lines = tagged_lines(log, "aggpack-tap: ");
  if (lines.size() != tapping.taps)
    throw InputError(fmt::format("{}: the LAMMPS log has {} \"aggpack-tap:\" lines, expected {}",
                                 (folder / LammpsDeck::kLogFile).string(), lines.size(), tapping.taps));
  ParticleStore after = particles;
  for (std::size_t k = 0; k < tapping.taps; ++k) {
    unsigned long tap = 0;
    double time = 0.0, energy = 0.0;
    if (std::sscanf(lines[k].c_str(), "aggpack-tap: %lu time %lf energy %lf", &tap, &time, &energy) != 3)
      throw InputError(fmt::format("{}: malformed line \"{}\"", (folder / LammpsDeck::kLogFile).string(), lines[k]));
    const std::filesystem::path dump = folder / fmt::format("tap_{}.dump", k + 1);
    take_positions(after, read_lammps_dump(dump, sc).particles, dump.string(), after.size(), sc.container);
    append_sample(series, time_offset + time, 0, measured_sample(sc, after, 0, false, energy));
    report.samples.push_back({k + 1, time_offset + time, box_density_or_nan(sc, after), energy});
  }
  const std::filesystem::path dump = folder / LammpsDeck::kDumpFile;
  take_positions(particles, read_lammps_dump(dump, sc).particles, dump.string(), particles.size(), sc.container);
  report.simulated_time = settled_line(log, folder).time;
  report.steps = static_cast<std::size_t>(std::llround(report.simulated_time / report.time_step));
  report.wall_clock_s = std::chrono::duration<double>(Clock::now() - t0).count();
  return report;
}

std::string take_positions_from_lammps(ParticleStore& particles, const std::filesystem::path& file,
                                       std::optional<std::int64_t> timestep, const Scenario& sc) {
  PackingFile read = read_packing_file(file, 1.0, sc.material.density, sc.limits.max_input_bytes(), timestep);
  if (read.format.rfind("LAMMPS", 0) != 0)
    throw InputError(fmt::format("{}: a {} file, not a LAMMPS dump or data file", file.string(), read.format));
  take_positions(particles, read.particles, file.string(), particles.size(), sc.container);
  check_imported_bed(sc, particles, file);
  return read.format;
}

namespace {

// What an export writes and reports: the deck, where its bed comes from, its spheres and those
// still to pour.
struct ExportedDeck {
  LammpsDeck deck;
  std::string source;
  std::size_t spheres = 0, poured = 0;
};

// What a finished run's summary.json says of how it ran: its scenario file (as a path from
// here), where it stopped if it was interrupted, and its overrides under the command's.
struct RecordedRun {
  std::filesystem::path scenario_file;
  std::optional<std::string> stopped;  // where an interrupted run stopped: its bed is not a final one
  ScenarioOverrides overrides;
};

RecordedRun read_recorded_run(const std::filesystem::path& summary_file, const ScenarioOverrides& overrides) {
  RecordedRun recorded;
  recorded.overrides = overrides;
  try {
    const auto summary =
        nlohmann::json::parse(read_input_text(summary_file, "the run's summary", kDefaultMaxInputFileBytes));
    recorded.scenario_file = summary.value("scenario_file", std::string());
    // A relative path is the run's: from the folder it was started in, not this one.
    const std::filesystem::path started_in = summary.value("working_directory", std::string());
    if (!recorded.scenario_file.empty() && !started_in.empty())
      recorded.scenario_file = started_in / recorded.scenario_file;
    if (summary.value("interrupted", false))
      recorded.stopped = summary.at("interruption").value("stopped", std::string("at an unrecorded point"));
    if (!recorded.overrides.seed && summary.contains("seed"))
      recorded.overrides.seed = recorded_seed(summary.at("seed"), summary_file);
    // The run's own overrides first, in their order; the command's --set after them win.
    if (summary.contains("scenario_overrides")) {
      const auto run_sets = summary.at("scenario_overrides").get<std::vector<std::string>>();
      recorded.overrides.set.insert(recorded.overrides.set.begin(), run_sets.begin(), run_sets.end());
    }
  } catch (const nlohmann::json::exception& e) {
    throw InputError(fmt::format("{}: not a summary.json aggpack wrote: {}", summary_file.string(), e.what()));
  }
  return recorded;
}

// A finished run: its scenario (with the overrides it ran with) and its final bed, for a
// settle step or, with --tap, a tap step.
ExportedDeck export_run_folder(const std::filesystem::path& folder, const ScenarioOverrides& overrides, bool tap) {
  const std::filesystem::path summary_file = folder / "summary.json";
  const std::filesystem::path bed_file = folder / "particles.csv";
  for (const auto& f : {summary_file, bed_file})
    if (!std::filesystem::exists(f))
      throw InputError(fmt::format("{}: a run's folder holds {}; this one has none (is it the output folder of a "
                                   "finished aggpack run?)",
                                   folder.string(), f.filename().string()));
  const RecordedRun recorded = read_recorded_run(summary_file, overrides);
  const std::filesystem::path& scenario_file = recorded.scenario_file;
  if (scenario_file.empty() || !std::filesystem::exists(scenario_file))
    throw InputError(fmt::format("{}: its scenario_file \"{}\" is gone; export the bed with "
                                 "export-lammps SCENARIO, or run the scenario again",
                                 summary_file.string(), scenario_file.string()));
  const Scenario sc = load_scenario(scenario_file, recorded.overrides);
  if (!sc.dynamics)
    throw InputError(fmt::format("{}: the scenario has no [dynamics]: the deck takes its law, time step and "
                                 "stopping rule from there",
                                 scenario_file.string()));
  // particles.csv holds a grain's spheres, not the grain (its template and mass properties).
  if (sc.particles.has_grains())
    throw InputError(fmt::format("{}: a run with grains: its particles.csv holds their spheres, not the grains; hand "
                                 "the bed to LAMMPS from the scenario instead (an export_lammps step before the DEM "
                                 "step, or dynamics.engine = \"lammps\")",
                                 folder.string()));
  if (tap && !sc.tapping)
    throw InputError(fmt::format("{}: --tap: the scenario has no [tapping] table for the taps",
                                 scenario_file.string()));
  PackingFile read = read_packing_file(bed_file, 1.0, sc.material.density, sc.limits.max_input_bytes());
  assign_file_materials(read.particles, read.materials, sc, bed_file.string());  // a run of several materials'
  ParticleStore bed = std::move(read.particles);
  for (auto& l : bed.layer) l = 0;
  ExportedDeck exported;
  exported.deck = lammps_deck(sc, bed, tap ? LammpsStep{TapStep{}} : LammpsStep{SettleStep{0}});
  if (recorded.stopped) {
    // particles.csv is the bed mid-step (a settle, a pour, a tap): say so wherever it goes.
    const std::string bed_was =
        fmt::format("the bed of the interrupted run in {}, as it stood {}", folder.string(), *recorded.stopped);
    add_note(exported.deck, "Not a final bed: " + bed_was);
    exported.source = bed_was + ", not a final bed";
  } else {
    exported.source = fmt::format("the final bed of the run in {}", folder.string());
  }
  exported.spheres = bed.size();
  return exported;
}

// The index of the protocol's first DEM step (a settle, pour or tap step): the one a
// scenario's export hands to LAMMPS.
std::size_t first_dem_step(const Scenario& sc, const Protocol& protocol) {
  std::size_t k = 0;
  const auto is_dem = [](const Step& s) {
    return std::holds_alternative<SettleStep>(s.kind) || std::holds_alternative<PourStep>(s.kind) ||
           std::holds_alternative<TapStep>(s.kind);
  };
  while (k < protocol.steps.size() && !is_dem(protocol.steps[k])) ++k;
  if (k == protocol.steps.size())
    throw InputError(fmt::format("{}: the protocol has no DEM step to export (a settle, pour or tap step)",
                                 sc.file.string()));
  return k;
}

// The bed as it stands before step k: the steps before it run here, but the scenario's own
// exports (they would write into its output folder), and no final analysis.
RunReport run_steps_before(const Scenario& sc, const Protocol& protocol, std::size_t k) {
  RunControls controls;
  controls.protocol.emplace();
  for (std::size_t j = 0; j < k; ++j)
    if (!std::holds_alternative<ExportLammpsStep>(protocol.steps[j].kind))
      controls.protocol->steps.push_back(protocol.steps[j]);
  controls.final_analysis = false;
  Progress silent;
  return run(sc, controls, silent);
}

// A scenario: its first DEM step, on the bed the steps before it leave.
ExportedDeck export_scenario_step(const std::filesystem::path& scenario_file, const ScenarioOverrides& overrides,
                                  bool tap) {
  if (tap)
    throw InputError(fmt::format("{}: --tap applies to a run's folder; for a scenario the step exported is its "
                                 "first DEM step (a tap step when that comes first)",
                                 scenario_file.string()));
  const Scenario sc = load_scenario(scenario_file, overrides);
  if (sc.particles.bed_from_caller())
    throw InputError(fmt::format("{}: particles.from = \"-\": a bed given by the library's caller at run time; "
                                 "export-lammps makes the bed from the scenario: name a particle file or give sizes "
                                 "(or export a finished run's folder)",
                                 scenario_file.string()));
  const Protocol protocol = scenario_protocol(sc);
  const std::size_t k = first_dem_step(sc, protocol);
  const RunReport report = run_steps_before(sc, protocol, k);
  const StepKind& kind = protocol.steps[k].kind;
  RunGrains::PourPart part;
  std::span<const std::uint8_t> pour_materials;
  std::vector<double> radii;
  std::vector<std::uint8_t> materials;
  RunGrains grains;
  LammpsStep step;
  if (const auto* p = std::get_if<PourStep>(&kind)) {
    // The part of the scenario's sizes this pour step lets in (a grain by its reach, with its shape).
    const GeneratedSizes sizes = generate_sizes(sc.particles, sc.seed);
    for (const double d : sizes.diameters) radii.push_back(0.5 * d);
    materials = sphere_materials(sc.particles, sizes);
    grains = make_run_grains(sc.particles, sizes, sc.seed);
    const std::size_t begin = radii.size() * p->layer / p->layers, end = radii.size() * (p->layer + 1) / p->layers;
    part = grains.pour_part(std::span<const double>(radii).subspan(begin, end - begin), begin);
    if (!materials.empty()) pour_materials = std::span<const std::uint8_t>(materials).subspan(begin, end - begin);
    step = *p;
  } else if (const auto* s = std::get_if<SettleStep>(&kind)) {
    step = *s;
  } else {
    step = TapStep{};
  }
  ExportedDeck exported;
  exported.deck = lammps_deck(sc, report.particles, step, part.radii, pour_materials,
                              grains.empty() ? PouredShapes{} : PouredShapes{part.shapes});
  exported.poured = part.radii.size();
  exported.source = fmt::format("step {} of {} of {}", k + 1, protocol.steps.size(), sc.file.string());
  exported.spheres = report.particles.size();
  return exported;
}

}  // namespace

std::string export_lammps(const std::filesystem::path& scenario_or_run, const ScenarioOverrides& overrides,
                          const std::filesystem::path& out, bool tap, std::ostream& log) {
  check_output_directory(out, false);
  const ExportedDeck exported = std::filesystem::is_directory(scenario_or_run)
                                    ? export_run_folder(scenario_or_run, overrides, tap)
                                    : export_scenario_step(scenario_or_run, overrides, tap);
  const LammpsDeck& deck = exported.deck;
  check_output_directory(out, true);
  write_lammps_deck(out, deck);
  // A pour with grains is one batch, in bed.data with the bed (lammps_deck).
  const bool batch_files = std::any_of(deck.files.begin(), deck.files.end(),
                                       [](const auto& f) { return f.first.starts_with("pour_batch_"); });
  const std::string poured =
      exported.poured == 0 ? std::string()
      : batch_files        ? fmt::format(" and {} to pour in pour_batch_*.data", exported.poured)
                           : fmt::format(" and {} particles to pour (grains and spheres, in one batch, in the same "
                                         "file)",
                                         exported.poured);
  fmt::print(log, "aggpack: exported {} ({}): {} spheres in {}{}, the deck in {}; run it with: cd {} && lmp -in {}\n",
             exported.source, deck.step, exported.spheres, (out / LammpsDeck::kDataFile).string(), poured,
             (out / deck.deck_file).string(), out.string(), deck.deck_file);
  return deck.step;
}

RunResult import_lammps(const std::filesystem::path& file, std::optional<std::int64_t> timestep,
                        const std::filesystem::path& scenario_file, const RunOptions& options, std::ostream& log) {
  Scenario sc = load_scenario(scenario_file, options.overrides);
  // A dump holds spheres, not the grains they make up (templates, mass properties): a bed of
  // grains comes back within its run, where its grains are known.
  if (sc.particles.has_grains())
    throw InputError(fmt::format("{}: a component has a shape (grains), and import-lammps reads spheres only: take "
                                 "LAMMPS's bed of grains back within the run (an import_lammps step after the "
                                 "export_lammps step, or dynamics.engine = \"lammps\")",
                                 scenario_file.string()));
  // The scenario gives the container, the material and the analysis; the bed is the file's.
  ParticleSource source;
  source.file = std::filesystem::absolute(file);
  source.file_timestep = timestep;
  sc.particles = source;
  sc.deposition.reset();
  sc.pour.reset();
  sc.dynamics.reset();
  sc.tapping.reset();
  sc.protocol.reset();
  return run_prepared_scenario(std::move(sc), options, log);
}

}  // namespace aggpack
