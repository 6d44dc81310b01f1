#include "aggpack/pipeline/run.hpp"

#include <array>
#include <chrono>
#include <cmath>
#include <span>
#include <algorithm>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <fmt/ostream.h>
#include <omp.h>

#include "aggpack/core/error.hpp"
#include "aggpack/core/rng.hpp"
#include "aggpack/core/version.hpp"
#include "aggpack/deposition/drop_and_roll.hpp"
#include "aggpack/io/atomic_file.hpp"
#include "aggpack/io/particle_file.hpp"
#include "aggpack/io/vtk.hpp"
#include "aggpack/pipeline/analyze.hpp"
#include "aggpack/pipeline/generate_sizes.hpp"
#include "aggpack/pipeline/grading_report.hpp"
#include "aggpack/pipeline/settle_stage.hpp"

namespace aggpack {

namespace {
using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Particles from a file must lie in the container; periodic sides wrap x and y. A bed
// settled by DEM presses into the floor and walls by a Hertz overlap (about 1e-4 r at rock
// stiffness, more when the stiffness is reduced): overlaps up to `tolerance` x r are kept
// as they are; a deeper one is an intrusion and is refused. Returns the largest overlap / r.
double fit_into_container(ParticleStore& particles, const Container& container, double tolerance,
                          const std::filesystem::path& file) {
  const Box& b = container.bounds;
  double largest = 0.0;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    Vec3& p = particles.position[i];
    const double r = particles.radius[i];
    p = container.wrapped(p);
    // How far the sphere reaches beyond each boundary (positive: it overlaps it); periodic
    // sides have only the floor and the top.
    const std::array<std::pair<double, const char*>, 6> reach{{{b.lo.z - (p.z - r), "the floor"},
                                                               {(p.z + r) - b.hi.z, "the top of the container"},
                                                               {b.lo.x - (p.x - r), "the wall x = x_min"},
                                                               {(p.x + r) - b.hi.x, "the wall x = x_max"},
                                                               {b.lo.y - (p.y - r), "the wall y = y_min"},
                                                               {(p.y + r) - b.hi.y, "the wall y = y_max"}}};
    const auto deepest = std::max_element(reach.begin(), container.periodic ? reach.begin() + 2 : reach.end(),
                                          [](const auto& a, const auto& c) { return a.first < c.first; });
    const auto [overlap, where] = *deepest;
    if (overlap > tolerance * r)
      throw InputError(fmt::format(
          "{}: particle {} (data row {}) at ({:.6g}, {:.6g}, {:.6g}) m, radius {:.6g} m, reaches {:.3g} m "
          "({:.3g} r) beyond {} of the container [{:.6g}, {:.6g}] x [{:.6g}, {:.6g}] x [{:.6g}, {:.6g}] m; "
          "particles.boundary_overlap_tolerance accepts up to {:g} r (a contact overlap), not an intrusion",
          file.string(), i, i + 1, p.x, p.y, p.z, r, overlap, overlap / r, where, b.lo.x, b.hi.x, b.lo.y, b.hi.y,
          b.lo.z, b.hi.z, tolerance));
    largest = std::max(largest, overlap / r);  // a sphere clear of every boundary counts as 0
  }
  return largest;
}

// Particles read from a file (with their largest overlap of the container / r), or an
// empty bed for the deposition stage to fill.
struct InitialBed {
  ParticleStore particles;
  double largest_boundary_overlap = 0.0;
};
InitialBed initial_particles(const Scenario& sc) {
  if (!sc.particles.file) return {};
  InitialBed bed{read_particle_file(*sc.particles.file, sc.particles.file_length_unit, sc.material.density), 0.0};
  bed.largest_boundary_overlap =
      fit_into_container(bed.particles, sc.container, sc.particles.boundary_overlap_tolerance, *sc.particles.file);
  return bed;
}

struct DepositionOutcome {
  nlohmann::json summary;
  std::vector<Supports> supports;
};

// Deposits `radii` on the bed as layer `layer` (0 for a single pass; each layer has its own stream).
DepositionOutcome run_deposition(const Scenario& sc, std::span<const double> radii, ParticleStore& particles,
                                 std::uint32_t layer, Progress& progress) {
  const DepositionStage& stage = *sc.deposition;
  DepositionSettings settings;
  settings.tolerance = stage.tolerance;
  settings.max_events = stage.max_events;
  settings.max_redrops = stage.max_redrops;
  settings.fill_height = stage.fill_height.value_or(sc.container.height());
  particles.reserve(particles.size() + radii.size());
  const std::uint64_t stream = static_cast<std::uint64_t>(RngPurpose::Deposition) + (std::uint64_t{layer} << 32);
  DropAndRoll deposition(particles, sc.container, radii, settings, Rng(sc.seed, stream));
  const auto t0 = Clock::now();
  progress.start_stage(layer > 0 || (sc.dynamics && sc.dynamics->layers > 1)
                           ? fmt::format("deposition, layer {}", layer + 1) : "deposition");
  // In slices, for the progress line; the same drops in the same order as in one call.
  const std::size_t slice = std::max<std::size_t>(1000, radii.size() / 100);
  for (std::size_t begin = 0; begin < radii.size(); begin += slice) {
    const std::size_t count = std::min(slice, radii.size() - begin);
    if (deposition.deposit(radii.subspan(begin, count), sc.material.density, layer) < count) break;
    progress.update({fmt::format("{} of {} particles placed", begin + count, radii.size())},
                    static_cast<double>(begin + count) / static_cast<double>(radii.size()));
  }
  const double seconds = seconds_since(t0);
  const DepositionStats& st = deposition.stats();
  nlohmann::json j;
  j["method"] = "drop_and_roll";
  j["particles_requested"] = radii.size();
  j["particles_placed"] = st.placed;
  j["particles_not_placed"] = radii.size() - st.placed;
  j["end"] = to_string(st.end);
  j["fill_height_m"] = settings.fill_height;
  j["events"] = st.events;
  j["events_per_particle"] = st.placed ? static_cast<double>(st.events) / static_cast<double>(st.placed) : 0.0;
  j["max_events_one_particle"] = st.max_events_one_sphere;
  j["redrops"] = st.redrops;
  j["ties"] = {{"on_top", st.ties_on_top}, {"on_ridge", st.ties_on_ridge}};
  j["supports"] = {{"floor", st.resting_on_floor},
                   {"three", st.resting_on_three},
                   {"touching_a_wall", st.touching_a_wall}};
  j["wall_clock_s"] = seconds;
  j["particles_per_second"] = seconds > 0 ? static_cast<double>(st.placed) / seconds : 0.0;
  return {j, deposition.supports()};
}

// The deposition summary of several layers: counts add up, the end is the last layer's.
void add_layer(nlohmann::json& total, const nlohmann::json& layer) {
  if (total.is_null()) {
    total = layer;
    return;
  }
  for (const char* key : {"particles_requested", "particles_placed", "particles_not_placed", "events", "redrops"})
    total[key] = total[key].get<std::size_t>() + layer[key].get<std::size_t>();
  for (const char* group : {"ties", "supports"})
    for (auto& [key, value] : total[group].items()) value = value.get<std::size_t>() + layer[group][key].get<std::size_t>();
  total["max_events_one_particle"] = std::max(total["max_events_one_particle"].get<std::size_t>(),
                                              layer["max_events_one_particle"].get<std::size_t>());
  total["end"] = layer["end"];
  total["wall_clock_s"] = total["wall_clock_s"].get<double>() + layer["wall_clock_s"].get<double>();
  const double seconds = total["wall_clock_s"].get<double>();
  total["events_per_particle"] = total["particles_placed"].get<std::size_t>() > 0
                                     ? total["events"].get<double>() / total["particles_placed"].get<double>()
                                     : 0.0;
  total["particles_per_second"] = seconds > 0 ? total["particles_placed"].get<double>() / seconds : 0.0;
}

// The dynamics summary of several settling runs (one per layer).
void add_settling_run(nlohmann::json& total, const nlohmann::json& run) {
  if (total.is_null()) {
    total = run;
    total.erase("layer");
    total["runs"] = nlohmann::json::array();
    total["runs_ended_by_max_time"] = std::size_t{0};
  }
  total["runs"].push_back(run);
  if (run["ended_by"] == "max_time") total["runs_ended_by_max_time"] = total["runs_ended_by_max_time"].get<std::size_t>() + 1;
  if (total["runs"].size() == 1) return;
  for (const char* key : {"steps", "neighbour_list_builds"})
    total[key] = total[key].get<std::size_t>() + run[key].get<std::size_t>();
  for (const char* key : {"simulated_time_s", "wall_clock_s"}) total[key] = total[key].get<double>() + run[key].get<double>();
  total["ended_by"] = run["ended_by"];
  total["final"] = run["final"];
  total["particles_settled"] = run["particles_settled"].get<std::size_t>() + run["particles_frozen"].get<std::size_t>();
  total["particles_frozen"] = 0;
  total["memory_bytes_per_particle"] = std::max(total["memory_bytes_per_particle"].get<double>(),
                                                run["memory_bytes_per_particle"].get<double>());
  double particle_steps = 0.0;
  for (const auto& r : total["runs"]) particle_steps += r["particle_steps_per_second"].get<double>() * r["wall_clock_s"].get<double>();
  const double seconds = total["wall_clock_s"].get<double>();
  total["particle_steps_per_second"] = seconds > 0 ? particle_steps / seconds : 0.0;
}

AnalysisRequest analysis_request(const Scenario& sc) {
  AnalysisRequest request;
  request.cube_sides = sc.analysis.box_sides;
  request.contact_tolerance = sc.analysis.contact_tolerance;
  request.slice_thickness = sc.analysis.slice_thickness;
  request.shell_thickness = sc.analysis.shell_thickness;
  return request;
}

// Every modelling choice a result depends on, said in the output.
nlohmann::json modelling_notes(const Scenario& sc, bool auto_box, const nlohmann::json& stages,
                               const std::vector<std::string>& size_notes) {
  nlohmann::json notes = nlohmann::json::array();
  if (sc.particles.file)
    notes.push_back("particle positions were read from " + sc.particles.file->string() +
                    (sc.dynamics ? "; the dynamics stage settled them from there" : "; no aggpack stage moved them"));
  if (sc.container.periodic)
    notes.push_back("periodic sides: x and y wrap, so the packing has no side-wall effect");
  if (sc.deposition) {
    const auto& d = stages.at("deposition");
    notes.push_back(fmt::format(
        "deposition: kinematic drop-and-roll, a geometric steepest descent without inertia or friction "
        "(material friction and restitution are not used by this stage); spheres dropped one at a time at "
        "uniformly random (x, y), in {} order; contact tolerance {:g} x diameter",
        sc.particles.graded ? name_of(kMixOrderNames, sc.particles.graded->order)
                            : name_of(kSizeOrderNames, sc.particles.sizes->order),
        sc.deposition->tolerance));
    if (d.at("end") != "all_placed")
      notes.push_back(fmt::format("deposition ended early ({}): {} of {} particles were placed",
                                  d.at("end").get<std::string>(), d.at("particles_placed").get<std::size_t>(),
                                  d.at("particles_requested").get<std::size_t>()));
  }
  for (const std::string& note : size_notes) notes.push_back(note);
  if (auto_box)
    notes.push_back("no analysis.box_sides given: one virtual cube of the largest admissible side was used");
  notes.push_back("virtual cubes are centred horizontally and vertically between the floor and the free surface, "
                  "at least one d_max from walls, floor and surface; the free surface is the equivalent height "
                  "V_solid / (footprint area x median solid fraction of d_max-thick slices)");
  notes.push_back(fmt::format("coordination counts sphere pairs with centre distance <= (r_i + r_j)(1 + {:g}) "
                              "for the spheres whose centres lie in the largest box",
                              sc.analysis.contact_tolerance));
  return notes;
}

// Runs the analysis, naming the scenario key when a box does not fit.
PackingReport analyze(const Scenario& sc, const ParticleStore& particles) {
  try {
    return analyze_packing(particles, sc.container, analysis_request(sc));
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: analysis.box_sides: {}", sc.file.string(), e.what()));
  }
}
}  // namespace

Scenario check_scenario(const std::filesystem::path& scenario_file, const ScenarioOverrides& overrides) {
  Scenario sc = load_scenario(scenario_file, overrides);
  if (sc.deposition) return sc;  // the boxes can only be checked against the deposited bed
  const ParticleStore particles = initial_particles(sc).particles;
  analyze_packing(particles, sc.container, analysis_request(sc));  // box placement errors surface here
  return sc;
}

RunResult run_scenario(const std::filesystem::path& scenario_file, const RunOptions& options, std::ostream& log) {
  const auto t_start = Clock::now();
  Progress silent;
  Progress& progress = options.progress ? *options.progress : silent;
  if (options.threads > 0) omp_set_num_threads(options.threads);
  const Scenario sc = load_scenario(scenario_file, options.overrides);
  std::vector<std::string> stage_names;
  if (sc.deposition) stage_names.push_back("deposition");
  if (sc.dynamics) stage_names.push_back("dynamics");
  if (options.stop_after &&
      std::find(stage_names.begin(), stage_names.end(), *options.stop_after) == stage_names.end())
    throw InputError(fmt::format("--stop-after {}: the scenario has no stage of that name (its stages: {})",
                                 *options.stop_after, stage_names.empty() ? "none" : fmt::format("{}", fmt::join(stage_names, ", "))));
  const std::size_t layers = sc.dynamics ? sc.dynamics->layers : 1;
  const bool stop_after_deposition = options.stop_after && *options.stop_after == "deposition";
  if (stop_after_deposition && layers > 1)
    throw InputError(fmt::format("--stop-after deposition: {} settles each of its {} layers before depositing "
                                 "the next, so there is no deposited bed to stop at; use dynamics.layers = 1",
                                 sc.file.string(), layers));
  const bool run_dynamics = sc.dynamics && !stop_after_deposition;

  nlohmann::json wall_clock;
  auto t0 = Clock::now();
  InitialBed initial = initial_particles(sc);
  ParticleStore particles = std::move(initial.particles);
  wall_clock["input"] = seconds_since(t0);

  nlohmann::json stages = nlohmann::json::object();
  std::vector<Supports> supports;
  GeneratedSizes sizes;
  TimeSeries series;
  nlohmann::json dynamics_summary;
  double simulated = 0.0;
  const auto settle_layer = [&](std::uint32_t layer) {
    const nlohmann::json run = settle_bed(sc, particles, layer, simulated, series, progress);
    simulated += run["simulated_time_s"].get<double>();
    add_settling_run(dynamics_summary, run);
  };
  if (sc.deposition) {
    t0 = Clock::now();
    try {
      sizes = generate_sizes(sc.particles, sc.seed);
    } catch (const InputError& e) {
      throw InputError(fmt::format("{}: {}", sc.file.string(), e.what()));
    }
    wall_clock["sizes"] = seconds_since(t0);
    std::vector<double> radii = std::move(sizes.diameters);
    for (double& r : radii) r *= 0.5;
    particles.reserve(particles.size() + radii.size());
    // One pass, or the paper's layers: equal counts in deposition order, each settled in turn.
    nlohmann::json deposited;
    for (std::size_t layer = 0; layer < layers; ++layer) {
      const std::size_t begin = radii.size() * layer / layers, end = radii.size() * (layer + 1) / layers;
      const std::span<const double> chunk(radii.data() + begin, end - begin);
      DepositionOutcome outcome =
          run_deposition(sc, chunk, particles, static_cast<std::uint32_t>(layer), progress);
      // Each layer's supports cover the whole bed; only the new spheres' are this layer's.
      supports.insert(supports.end(), outcome.supports.begin() + static_cast<std::ptrdiff_t>(supports.size()),
                      outcome.supports.end());
      add_layer(deposited, outcome.summary);
      if (layers > 1) settle_layer(static_cast<std::uint32_t>(layer));
      if (deposited["end"] != "all_placed") break;
    }
    if (layers > 1) deposited["layers"] = layers;
    wall_clock["deposition"] = deposited["wall_clock_s"];
    stages["deposition"] = std::move(deposited);
    if (layers == 1) {
      t0 = Clock::now();
      const nlohmann::json analysed = to_json(analyze(sc, particles));
      wall_clock["analysis_after_deposition"] = seconds_since(t0);
      stages["deposition"]["density"] = analysed.at("density");
      stages["deposition"]["coordination"] = analysed.at("coordination");
    }
  }
  std::optional<ParticleStore> deposited_bed;
  if (run_dynamics && layers == 1) {
    if (sc.deposition) deposited_bed = particles;
    settle_layer(0);
  }
  if (run_dynamics) {
    wall_clock["dynamics"] = dynamics_summary["wall_clock_s"];
    stages["dynamics"] = dynamics_summary;
  }

  t0 = Clock::now();
  progress.start_stage("analysis");
  progress.update({"virtual boxes"}, 0.0);
  const PackingReport report = analyze(sc, particles);
  progress.clear();
  wall_clock["analysis"] = seconds_since(t0);
  if (run_dynamics) {
    const nlohmann::json analysed = to_json(report);
    stages["dynamics"]["density"] = analysed.at("density");
    stages["dynamics"]["coordination"] = analysed.at("coordination");
  }

  nlohmann::json summary;
  summary["aggpack_version"] = kVersion;
  summary["seed"] = sc.seed;
  summary["scenario_file"] = sc.file.string();
  summary["scenario"] = to_json(sc);
  summary["particle_count"] = particles.size();
  const Box& b = sc.container.bounds;
  summary["container"] = {{"lo", {b.lo.x, b.lo.y, b.lo.z}}, {"hi", {b.hi.x, b.hi.y, b.hi.z}},
                          {"periodic", sc.container.periodic}};
  summary["stages"] = stages;
  if (sc.deposition) summary["sizes"] = sizes.report;
  std::vector<std::string> notes = sizes.notes;
  if (sc.particles.file) {
    summary["input"] = {{"file", sc.particles.file->string()},
                        {"largest_boundary_overlap_rel", initial.largest_boundary_overlap},
                        {"boundary_overlap_tolerance_rel", sc.particles.boundary_overlap_tolerance}};
    if (initial.largest_boundary_overlap > 0.0)
      notes.push_back(fmt::format("the particle file's spheres overlap the floor or walls by up to {:.3g} of their "
                                  "radius (contacts of a settled bed; accepted up to "
                                  "particles.boundary_overlap_tolerance = {:g})",
                                  initial.largest_boundary_overlap, sc.particles.boundary_overlap_tolerance));
  }
  if (run_dynamics)
    for (std::string& note : dynamics_notes(sc, stages["dynamics"])) notes.push_back(std::move(note));
  if (sc.dynamics && !run_dynamics)
    notes.push_back("--stop-after deposition: the [dynamics] stage was not run");
  summary["modelling_notes"] = modelling_notes(sc, sc.analysis.box_sides.empty(), stages, notes);
  summary.update(to_json(report));

  // Outputs only once everything has been computed: bad input leaves no files behind.
  t0 = Clock::now();
  const auto& dir = sc.output.directory;
  std::filesystem::create_directories(dir);
  if (sc.output.csv) write_file_atomically(dir / "particles.csv", particles_csv(particles));
  if (sc.output.csv && sc.deposition) write_file_atomically(dir / "supports.csv", supports_csv(supports));
  const std::string provenance = fmt::format("aggpack {}, scenario {}, seed {}", kVersion, sc.file.string(), sc.seed);
  if (run_dynamics) write_file_atomically(dir / "timeseries.csv", series.csv());
  if (sc.output.vtp) write_file_atomically(dir / "particles.vtp", particles_vtp(particles, provenance));
  wall_clock["output"] = seconds_since(t0);
  wall_clock["total"] = seconds_since(t_start);
  summary["wall_clock_s"] = wall_clock;
  write_file_atomically(dir / "summary.json", summary.dump(2) + "\n");

  if (!options.quiet) {
    fmt::print(log, "aggpack {}: {} ({} particles, seed {})\n", kVersion, sc.title, particles.size(), sc.seed);
    if (sc.particles.graded) {
      const auto& z = sizes.report;
      fmt::print(log, "  sizes: {} particles by {} sampling, d {:.3g}-{:.3g} mm, D10/D50/D90 {:.3g}/{:.3g}/{:.3g} mm, "
                      "fineness modulus {:.2f}\n",
                 z["count"].get<std::size_t>(), z["sampling"].get<std::string>(), 1e3 * z["d_min_m"].get<double>(),
                 1e3 * z["d_max_m"].get<double>(), 1e3 * z["d10_m"].get<double>(), 1e3 * z["d50_m"].get<double>(),
                 1e3 * z["d90_m"].get<double>(), z["fineness_modulus"].get<double>());
      if (z.contains("ca_fa_generated"))
        fmt::print(log, "  mix: Ca/Fa {:.4g} generated for {:.4g} requested ({} order)\n",
                   z["ca_fa_generated"].get<double>(), z["ca_fa_requested"].get<double>(), z["order"].get<std::string>());
      for (const auto& c : z["components"]) {
        fmt::print(log, "  {} ({}): {} particles, cut off {:.2f} % below {:.3g} mm and {:.2f} % above {:.3g} mm; "
                        "largest deviation from the target {:.2f} points\n",
                   c["key"].get<std::string>(), c["grading"].get<std::string>(), c["count"].get<std::size_t>(),
                   100 * c["cut_below_fraction"].get<double>(), 1e3 * c["d_lo_m"].get<double>(),
                   100 * c["cut_above_fraction"].get<double>(), 1e3 * c["d_hi_m"].get<double>(),
                   c["largest_deviation_percent"].get<double>());
        fmt::print(log, "    {:>8} {:>10} {:>9} {:>9}\n", "sieve", "opening mm", "target %", "generated %");
        for (const auto& row : c["sieves"])
          fmt::print(log, "    {:>8} {:>10.4g} {:>9.2f} {:>9.2f}\n", row["sieve"].get<std::string>(),
                     1e3 * row["opening_m"].get<double>(), row["target_percent"].get<double>(),
                     row["generated_percent"].get<double>());
        if (const std::string snapped = snapped_sieves_text(c["snapped_sieves"]); !snapped.empty())
          fmt::print(log, "    {}\n", snapped);
        if (c.contains("band"))
          fmt::print(log, "    band {}: {}\n", c["band"]["name"].get<std::string>(),
                     c["band"]["all_inside"].get<bool>() ? "inside at every sieve" : "OUTSIDE at some sieves");
      }
    }
    if (sc.deposition) {
      const auto& d = stages["deposition"];
      fmt::print(log, "  deposition: {} of {} placed ({}), {:.3g} s, {:.3g} events per particle, {} redrops, "
                      "{} ties\n",
                 d["particles_placed"].get<std::size_t>(), d["particles_requested"].get<std::size_t>(),
                 d["end"].get<std::string>(), d["wall_clock_s"].get<double>(), d["events_per_particle"].get<double>(),
                 d["redrops"].get<std::size_t>(),
                 d["ties"]["on_top"].get<std::size_t>() + d["ties"]["on_ridge"].get<std::size_t>());
    }
    if (run_dynamics) {
      const auto& d = stages["dynamics"];
      fmt::print(log, "  dynamics: {} ({}), {:.3g} s simulated in {} steps of {:.3g} s, {:.3g} s wall, "
                      "{:.3g} million particle-steps/s; overlap mean {:.2e}, max {:.2e}\n",
                 d["ended_by"].get<std::string>(), sc.dynamics->friction_model, d["simulated_time_s"].get<double>(),
                 d["steps"].get<std::size_t>(), d["time_step_s"].get<double>(), d["wall_clock_s"].get<double>(),
                 1e-6 * d["particle_steps_per_second"].get<double>(), d["final"]["mean_overlap_rel"].get<double>(),
                 d["final"]["max_overlap_rel"].get<double>());
      if (stages["deposition"].contains("density"))
        fmt::print(log, "  density after deposition {:.4f}, after dynamics {:.4f}\n",
                   stages["deposition"]["density"]["mean"].get<double>(), report.density.mean);
    }
    for (const auto& box : report.density.boxes)
      fmt::print(log, "  virtual cube {:8.4g} m: density {:.4f}\n", box.side, box.density);
    fmt::print(log, "  mean density {:.4f} (sd {:.4f}), mean coordination {:.3f} over {} spheres\n",
               report.density.mean, report.density.sd, report.coordination.mean,
               report.coordination.particles_counted);
    fmt::print(log, "  wrote {}\n", dir.string());
  }
  return {dir, summary, std::move(particles), std::move(deposited_bed), std::move(series)};
}

}  // namespace aggpack
