#include "aggpack/run/run.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <optional>
#include <set>
#include <unordered_map>
#include <variant>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <fmt/ranges.h>

#include "aggpack/run/calibration_file.hpp"
#include "aggpack/analysis/coordination.hpp"
#include "aggpack/core/error.hpp"
#include "aggpack/core/version.hpp"
#include "aggpack/io/atomic_file.hpp"
#include "aggpack/io/particle_file.hpp"
#include "aggpack/run/run_grains.hpp"
#include "aggpack/io/vtk.hpp"
#include "aggpack/lammps/process.hpp"
#include "aggpack/run/lammps_steps.hpp"
#include "aggpack/run/output_folder.hpp"
#include "aggpack/run/preflight.hpp"
#include "aggpack/run/steps.hpp"
#include "run/run_session.hpp"

namespace aggpack {

namespace {
using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

}  // namespace

Scenario check_scenario(const std::filesystem::path& scenario_file, const ScenarioOverrides& overrides,
                        const LibraryWatch& watch) {
  Scenario sc = load_scenario(scenario_file, overrides);
  check_loaded_scenario(sc, nullptr, watch);
  return sc;
}

void check_loaded_scenario(const Scenario& sc, const ParticleStore* starting_bed, const LibraryWatch& watch) {
  check_output_directory(sc.output.directory, false);
  check_scenario_inputs(sc, starting_bed, watch);
}

void check_scenario_inputs(const Scenario& sc, const ParticleStore* starting_bed, const LibraryWatch& watch) {
  const InitialBed bed = initial_bed(sc, starting_bed);
  (void)checked_grains(sc, scenario_protocol(sc), bed, watch);  // their templates made: seconds to minutes
  if (sc.deposition || sc.pour) return;  // the boxes can only be placed in the bed once made
  analyse_bed(sc, bed.particles);        // box placement errors surface here
}

RunReport run(const Scenario& sc, const RunControls& controls, Progress& progress) {
  RunSession session(sc, controls, progress);  // every check before work, the bed to start from
  session.run_steps();
  return session.finish();
}

namespace {

// The snapshot steps' names in the order the protocol takes them.
std::vector<std::string> snapshot_names_in_order(const RunReport& report) {
  std::vector<std::string> names;
  for (const Step& step : scenario_protocol(report.scenario).steps)
    if (const auto* snapshot = std::get_if<SnapshotStep>(&step.kind))
      if (report.snapshots.contains(snapshot->name) && report.snapshot_times.contains(snapshot->name))
        names.push_back(snapshot->name);
  return names;
}

// The component of each sphere of a bed with grains: a member's, its grain's template's; a free
// sphere's, that of the drawn size it has among the components without a shape (the drop
// sequence's order is not the store's once grains are in).
std::vector<std::int32_t> sphere_components(const ParticleStore& bed, const GeneratedSizes& sizes,
                                            const std::vector<std::uint32_t>& shape_component) {
  std::unordered_map<double, std::int32_t> of_diameter;
  std::set<std::int32_t> grain_components;
  for (const std::uint32_t c : shape_component) grain_components.insert(static_cast<std::int32_t>(c));
  for (std::size_t i = 0; i < sizes.diameters.size(); ++i)
    if (!grain_components.contains(sizes.component[i])) of_diameter.emplace(sizes.diameters[i], sizes.component[i]);
  std::vector<std::int32_t> component(bed.size(), -1);
  for (std::size_t i = 0; i < bed.size(); ++i) {
    if (bed.body[i] != kNoBody) {
      component[i] = static_cast<std::int32_t>(shape_component.at(bed.bodies.shape[bed.body[i]]));
    } else if (const auto at = of_diameter.find(2.0 * bed.radius[i]); at != of_diameter.end()) {
      component[i] = at->second;
    }
  }
  return component;
}

// A bed as VTP, with each sphere's contacts and, for generated sizes, the part of the size
// specification it came from (bed index i is the drop sequence's i: every stage adds spheres
// in its order, which the radii confirm).
std::string bed_vtp(const RunReport& report, const ParticleStore& bed, std::string_view provenance) {
  const Scenario& sc = report.scenario;
  std::vector<std::int32_t> coordination;
  coordination.reserve(bed.size());
  for (const int k : contact_counts(bed, sc.container, sc.analysis.contact_tolerance))
    coordination.push_back(static_cast<std::int32_t>(k));
  std::span<const std::int32_t> component;
  std::vector<std::int32_t> grain_bed_component;  // a bed with grains: each sphere's, by its grain or size
  if (report.sizes && !bed.bodies.empty()) {
    grain_bed_component = sphere_components(bed, *report.sizes, report.grain_shape_component);
    component = grain_bed_component;
  } else if (report.sizes && bed.size() <= report.sizes->component.size()) {
    const std::vector<double>& d = report.sizes->diameters;
    bool same_order = true;
    for (std::size_t i = 0; i < bed.size() && same_order; ++i) same_order = bed.radius[i] == 0.5 * d[i];
    if (same_order) component = std::span(report.sizes->component).first(bed.size());
  }
  std::vector<std::int32_t> material;  // a run of several materials only
  if (material_count(sc) > 1) material.assign(bed.material.begin(), bed.material.end());
  std::vector<std::int32_t> grain;  // a run with grains only: each sphere's, as particles.csv's column
  if (!bed.bodies.empty())
    for (const std::uint32_t b : bed.body) grain.push_back(b == kNoBody ? 0 : static_cast<std::int32_t>(b) + 1);
  return particles_vtp(bed, provenance, sc.output.vtp_encoding, {coordination, component, material, grain});
}

// The frames of the DEM (written as they were taken), the snapshots and the final bed as one
// series, for ParaView to animate (particles.pvd), each snapshot's bed written as VTP.
void write_vtp_series(const RunReport& report, const std::string& provenance,
                      const std::function<void(const std::string&, const std::string&)>& write) {
  // In the order of their times (at one time: the frames, then the snapshots in the protocol's
  // order, then the final bed). One bed at one time is listed once: a frame that is a
  // snapshot's bed as the snapshot, and a final bed that is the last frame's or snapshot's not
  // again (a protocol that ends with a snapshot, or whose last frame is the final bed).
  enum class Kind { Frame, Snapshot, Final };
  struct Entry {
    PvdFrame frame;
    std::uint64_t fingerprint;
    Kind kind;
  };
  std::vector<Entry> entries;
  for (std::size_t f = 0; f < report.frames.size(); ++f)
    entries.push_back({{report.frames[f].time, report.frames[f].file, fmt::format("frame {}", f + 1)},
                       report.frames[f].fingerprint, Kind::Frame});
  const std::vector<std::string> snapshots = snapshot_names_in_order(report);
  for (const std::string& name : snapshots) {
    const std::string file = "particles_" + name + ".vtp";
    const ParticleStore& bed = report.snapshots.at(name);
    write(file, bed_vtp(report, bed, provenance));
    entries.push_back(
        {{report.snapshot_times.at(name), file, "snapshot " + name}, bed_fingerprint(bed), Kind::Snapshot});
  }
  if (!entries.empty()) {
    entries.push_back({{report.simulated_time, "particles.vtp", "the final bed"}, bed_fingerprint(report.particles),
                       Kind::Final});
    std::stable_sort(entries.begin(), entries.end(),
                     [](const Entry& a, const Entry& b) { return a.frame.time < b.frame.time; });
    const auto same = [](const Entry& a, const Entry& b) {
      return a.frame.time == b.frame.time && a.fingerprint == b.fingerprint;
    };
    std::vector<PvdFrame> frames;
    for (std::size_t e = 0; e < entries.size(); ++e) {
      const Entry& entry = entries[e];
      if (entry.kind == Kind::Frame && e + 1 < entries.size() && entries[e + 1].kind == Kind::Snapshot &&
          same(entry, entries[e + 1]))
        continue;
      if (entry.kind == Kind::Final && e > 0 && same(entry, entries[e - 1])) continue;
      frames.push_back(entry.frame);
    }
    write("particles.pvd", particles_pvd(frames, provenance));
  }
}

}  // namespace

nlohmann::json write_outputs(const RunReport& report, const std::filesystem::path& dir, double seconds_so_far,
                             const std::vector<std::string>& written_while_running) {
  const auto t0 = Clock::now();
  const Scenario& sc = report.scenario;
  check_output_directory(dir, true);  // InputError naming it when it cannot be made
  // Every file written is listed in the folder's manifest, with the checkpoint, the frames and
  // the LAMMPS decks the run wrote as it went, so that a later run into this folder replaces them all.
  std::vector<std::string> written = written_while_running;
  if (std::filesystem::is_regular_file(dir / kCheckpointFile)) written.emplace_back(kCheckpointFile);
  const auto write = [&](const std::string& name, const std::string& content) {
    write_file_atomically(dir / name, content);
    written.push_back(name);
  };
  // A run of several materials names each sphere's in particles.csv.
  std::vector<std::string> material_names;
  if (material_count(sc) > 1)
    for (std::size_t k = 0; k < material_count(sc); ++k) material_names.push_back(material_name(sc, k));
  if (report.interrupted) {  // the bed and the samples as they stood, and what was done
    write("particles.csv", particles_csv(report.particles, material_names));
    if (!report.series.samples.empty()) write("timeseries.csv", report.series.csv());
    const double output_seconds = seconds_since(t0);
    nlohmann::json summary = report.summary_json(output_seconds, seconds_so_far + output_seconds);
    summary["scenario"]["output"]["directory"] = dir.string();  // where these files are
    write("summary.json", summary.dump(2) + "\n");
    write_manifest(dir, written);
    return summary;
  }
  if (sc.output.csv) write("particles.csv", particles_csv(report.particles, material_names));
  if (sc.output.csv && !report.particles.bodies.empty()) {
    const std::vector<GrainMeasure> measures = measure_bodies(report.particles);
    const std::vector<SieveInterval> sieves =
        report.sizes ? grain_sieve_intervals(report.particles, measures, report.grain_shape_component, report.sizes->report)
                     : std::vector<SieveInterval>{};
    const std::vector<int> coordination =
        grain_contact_counts(report.particles, sc.container, sc.analysis.contact_tolerance);
    write("grains.csv", grains_csv(report.particles, measures, sieves, coordination));
  }
  if (sc.output.csv && sc.deposition) write("supports.csv", supports_csv(report.supports));
  if (report.dynamics || !report.tappings.empty() || !report.roddings.empty() || !report.jiggings.empty())
    write("timeseries.csv", report.series.csv());
  // One header, then every step's rows.
  const auto rows_of = [](const auto& reports) {
    std::string all;
    for (const auto& step : reports) {
      const std::string rows = step.csv();
      all += all.empty() ? rows : rows.substr(rows.find('\n') + 1);
    }
    return all;
  };
  if (!report.roddings.empty()) write("rod_strokes.csv", rows_of(report.roddings));
  if (!report.jiggings.empty()) write("jig_drops.csv", rows_of(report.jiggings));
  if (!report.tappings.empty()) {
    std::string taps;  // one header, then every tap step's rows
    for (const TapReport& t : report.tappings) {
      const std::string rows = t.csv();
      taps += taps.empty() ? rows : rows.substr(rows.find('\n') + 1);
    }
    write("taps.csv", taps);
  }
  for (const auto& [name, bed] : report.snapshots) write("particles_" + name + ".csv", particles_csv(bed, material_names));
  const std::string provenance = fmt::format("aggpack {}, scenario {}, seed {}", kVersion, sc.file.string(), sc.seed);
  if (sc.output.vtp) {
    write("particles.vtp", bed_vtp(report, report.particles, provenance));
    write_vtp_series(report, provenance, write);
  }
  const double output_seconds = seconds_since(t0);
  nlohmann::json summary = report.summary_json(output_seconds, seconds_so_far + output_seconds);
  // Where these files are: the scenario's folder, or the one a report is written into later.
  summary["scenario"]["output"]["directory"] = dir.string();
  write("summary.json", summary.dump(2) + "\n");
  write_manifest(dir, written);
  return summary;
}

namespace {

bool runs_dem(const Scenario& sc) { return sc.dynamics || sc.pour || sc.tapping; }

// The output folder as a run holds it: what it has listed in the manifest so far, and the
// files in the run's folders (frames/, lammps/) that are not its own (a user's, beside an
// --overwrite run or an exported deck; the manifest never lists them).
struct HeldFolder {
  std::filesystem::path directory;
  std::vector<std::string> listed;
  std::set<std::string> not_ours;

  // The files this run has written into the run's folders so far.
  [[nodiscard]] std::vector<std::string> written_in_run_folders() const {
    std::vector<std::string> files;
    for (const std::string& path : files_in_run_folders(directory))
      if (!not_ours.contains(path)) files.push_back(path);
    return files;
  }
  void list(const std::string& file) {
    if (std::find(listed.begin(), listed.end(), file) != listed.end()) return;
    listed.push_back(file);
    write_manifest(directory, listed);
  }
};

// The output folder made ready for the run, once the input has passed its checks. A new run
// removes an earlier run's outputs (the folder never mixes two runs' files), refuses a frames
// folder no aggpack run wrote, and starts the manifest with the checkpoint. A resumed run
// removes nothing: the interrupted run's outputs stay until this run writes its own (a
// checkpoint that cannot be continued then loses nothing).
HeldFolder take_over_folder(const Scenario& sc, bool resumed, const RunOptions& options, std::ostream& log) {
  check_output_directory(sc.output.directory, true);
  HeldFolder held{sc.output.directory, {}, {}};
  if (resumed) {
    held.listed = manifest_files(held.directory);
    for (const std::string& path : files_in_run_folders(held.directory))
      if (std::find(held.listed.begin(), held.listed.end(), path) == held.listed.end()) held.not_ours.insert(path);
    return held;
  }
  // Frames no aggpack run wrote (--overwrite leaves them there) are not written among; refused
  // before anything is removed.
  const std::vector<std::string> others = output_folder_contents(held.directory).others;
  if (sc.output.frame_interval &&
      std::any_of(others.begin(), others.end(),
                  [](const std::string& path) { return path.starts_with(std::string(kFramesFolder) + "/"); }))
    throw InputError(fmt::format("{}: '{}' is there and no aggpack run wrote it; output.frame_interval writes the "
                                 "run's frames into it: move it, or give another output folder",
                                 held.directory.string(), kFramesFolder));
  const std::vector<std::string> removed = remove_earlier_run(held.directory);
  held.not_ours = files_in_run_folders(held.directory);
  held.listed = {kCheckpointFile};  // from the start, for a run that is killed
  write_manifest(held.directory, held.listed);
  if (!removed.empty() && !options.quiet)
    fmt::print(log, "aggpack: removed the files of the earlier run in {}: {}\n", held.directory.string(),
               fmt::join(removed, ", "));
  return held;
}

// A bed that a DEM made and the final analysis refused (a virtual cube that does not fit it):
// kept in the folder, this run's one output (with a resumed run's checkpoint and the LAMMPS
// runs' files) in the manifest, to be measured again rather than made again. Returns the
// refusal, saying where the bed is.
InputError keep_unanalysed_bed(const Scenario& sc, const BedNotAnalysed& refused, bool resumed, const HeldFolder& held) {
  std::error_code ec;
  if (!resumed) {
    std::filesystem::remove(sc.output.directory / kCheckpointFile, ec);
    for (const std::string& path : held.written_in_run_folders())
      if (path.starts_with(std::string(kFramesFolder) + "/")) std::filesystem::remove(sc.output.directory / path, ec);
    std::filesystem::remove(sc.output.directory / kFramesFolder, ec);  // when empty
  }
  const std::filesystem::path kept = sc.output.directory / kUnanalysedBedFile;
  write_file_atomically(kept, particles_csv(refused.bed()));
  std::vector<std::string> files = held.written_in_run_folders();
  files.emplace_back(kUnanalysedBedFile);
  if (std::filesystem::exists(sc.output.directory / kCheckpointFile)) files.emplace_back(kCheckpointFile);
  write_manifest(sc.output.directory, files);
  return InputError(fmt::format("{}. The bed ({:.3g} s of DEM) is kept in {}: measure it with `aggpack analyze {} "
                                "--cube SIDE` (sides in m), or run again with smaller analysis.box_sides",
                                refused.what(), refused.simulated_time(), kept.string(), kept.string()));
}

// A new run refused after it took the folder over leaves nothing of its own but the LAMMPS
// runs' files (their logs say why LAMMPS failed), listed in the manifest.
void leave_refused_run(const HeldFolder& held) {
  std::error_code ec;
  std::filesystem::remove(held.directory / kCheckpointFile, ec);
  std::vector<std::string> kept;
  for (const std::string& path : held.written_in_run_folders()) {
    if (path.starts_with(std::string(kFramesFolder) + "/")) std::filesystem::remove(held.directory / path, ec);
    else kept.push_back(path);
  }
  std::filesystem::remove(held.directory / kFramesFolder, ec);  // when empty
  if (kept.empty()) std::filesystem::remove(held.directory / kManifestFile, ec);
  else write_manifest(held.directory, kept);
}

// run_scenario's and resume_run's common part: runs `sc` into its output folder, with
// checkpoints of `header` there unless the scenario turns them off.
RunResult run_into_folder(const Scenario& sc, Checkpoint header, const Checkpoint* resume, const RunOptions& options,
                          std::ostream& log, Clock::time_point t_start) {
  Progress silent;
  Progress& progress = options.progress ? *options.progress : silent;
  check_output_directory(sc.output.directory, false);
  // A resumed run's folder is its own; any other must hold nothing but an earlier run's files.
  if (!resume) check_output_folder_contents(sc.output.directory, options.overwrite);
  // The folder is made and probed once the input has passed its checks, before any work, not
  // after hours of it; a run that fails later removes the folder again if it made it empty.
  const bool existed = std::filesystem::exists(sc.output.directory);
  const auto remove_if_made_empty = [&] {
    std::error_code ec;
    if (!existed && std::filesystem::is_empty(sc.output.directory, ec) && !ec)
      std::filesystem::remove(sc.output.directory, ec);
  };
  RunControls controls;
  controls.threads = options.threads;
  controls.stop_after = header.stop_after;
  // Where a relative scenario_file lies, for export-lammps RUN_DIR (a resumed run: where it began).
  const std::string working_directory =
      header.working_directory.empty() ? std::filesystem::current_path().string() : header.working_directory;
  std::optional<HeldFolder> held;  // once the run has begun: the folder taken over
  controls.before_work = [&] { held = take_over_folder(sc, resume != nullptr, options, log); };
  controls.stop = options.stop;
  controls.resume_from = resume;
  // Each frame of the DEM into frames/, as it comes (none is kept in memory).
  const std::string provenance =
      fmt::format("aggpack {}, scenario {}, seed {}", kVersion, sc.file.string(), sc.seed);
  controls.on_frame = [&](const std::string& file, double /*time*/, const ParticleStore& bed, const RunReport& so_far) {
    std::filesystem::create_directories(sc.output.directory / kFramesFolder);
    write_file_atomically(sc.output.directory / file, bed_vtp(so_far, bed, provenance));
    held->list(file);  // the manifest describes the folder even if the run is killed now
  };
  controls.checkpoint_before_final_analysis = options.keep_dem_checkpoint && runs_dem(sc);
  if (sc.output.checkpoint)
    controls.checkpoints = RunControls::Checkpoints{sc.output.directory, sc.output.checkpoint_every, std::move(header)};
  RunResult result{sc.output.directory, {}, {}, 0.0};
  try {
    result.report = run(sc, controls, progress);
  } catch (const BedNotAnalysed& refused) {
    throw keep_unanalysed_bed(sc, refused, resume != nullptr, *held);
  } catch (...) {
    // A refused run leaves nothing: not the checkpoint it took on its way. A resumed run's
    // folder stays as it was (the checkpoint is the user's way back to the work done before);
    // so does the folder of a run refused before it began (an earlier run's files, its checkpoint).
    if (!resume && held) leave_refused_run(*held);
    remove_if_made_empty();
    throw;
  }
  result.report.working_directory = working_directory;
  // Outputs only once everything has been computed: bad input leaves no files behind.
  result.summary = write_outputs(result.report, result.output_directory, seconds_since(t_start),
                                 held ? held->written_in_run_folders() : std::vector<std::string>{});
  result.wall_clock_s = seconds_since(t_start);
  if (const auto& stop = result.report.interrupted) {
    fmt::print(log, "aggpack: interrupted by signal {} {} ({} of {} steps done); the bed as it stood and summary.json "
                    "(\"interrupted\": true) are in {}\n",
               stop->signal_number, stop->where, stop->steps_completed, stop->steps_total,
               result.output_directory.string());
    if (stop->checkpoint)
      fmt::print(log, "aggpack: checkpoint taken {}; continue with: aggpack resume {}\n", *stop->checkpoint,
                 result.output_directory.string());
    return result;
  }
  if (result.report.checkpoint_error && !options.quiet)
    fmt::print(log, "aggpack: warning: {}\n", *result.report.checkpoint_error);
  // A finished run's checkpoint would only mislead a later resume (unless a campaign keeps it).
  std::error_code ec;
  if (!controls.checkpoint_before_final_analysis && std::filesystem::remove(result.output_directory / kCheckpointFile, ec))
    drop_from_manifest(result.output_directory, kCheckpointFile);
  if (!options.quiet) fmt::print(log, "{}", result.report.console_summary(result.output_directory));
  return result;
}

}  // namespace

RunResult run_scenario(const std::filesystem::path& scenario_file, const RunOptions& options, std::ostream& log) {
  return run_scenario_text(read_scenario_text(scenario_file), scenario_file, options, log);
}

RunResult run_scenario_text(const std::string& text, const std::filesystem::path& scenario_file,
                            const RunOptions& options, std::ostream& log) {
  const auto t_start = Clock::now();
  const Scenario sc = parse_scenario(text, scenario_file, options.overrides);
  Checkpoint header;
  header.version = kVersion;
  header.scenario_file = scenario_file.string();
  header.working_directory = std::filesystem::current_path().string();
  header.scenario_text = text;
  header.overrides = options.overrides;
  header.stop_after = options.stop_after;
  return run_into_folder(sc, std::move(header), nullptr, options, log, t_start);
}

RunResult run_prepared_scenario(Scenario scenario, const RunOptions& options, std::ostream& log) {
  const auto t_start = Clock::now();
  scenario.output.checkpoint = false;
  return run_into_folder(scenario, Checkpoint{}, nullptr, options, log, t_start);
}

RunResult resume_run(const std::filesystem::path& run_directory, const RunOptions& options, std::ostream& log) {
  const auto t_start = Clock::now();
  const Checkpoint checkpoint = read_checkpoint(run_directory);
  Checkpoint header = checkpoint;
  header.overrides.output_directory = run_directory;
  for (const std::string& set : options.overrides.set) {
    if (!set.starts_with("output.checkpoint"))
      throw InputError(fmt::format("resume: --set {}: a resumed run keeps its scenario; only output.checkpoint and "
                                   "output.checkpoint_every may change",
                                   set));
    header.overrides.set.push_back(set);
  }
  const Scenario sc = parse_scenario(header.scenario_text, resumed_scenario_path(header), header.overrides);
  if (!options.quiet)
    fmt::print(log, "aggpack: resuming {} from its checkpoint, taken {} ({} steps done)\n", run_directory.string(),
               checkpoint.where, checkpoint.steps_completed);
  try {
    return run_into_folder(sc, std::move(header), &checkpoint, options, log, t_start);
  } catch (const DamagedCheckpoint& e) {
    throw damaged_checkpoint(run_directory / kCheckpointFile, e.what());
  }
}

}  // namespace aggpack
