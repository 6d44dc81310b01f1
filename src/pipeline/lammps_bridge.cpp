#include "aggpack/pipeline/lammps_bridge.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <variant>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <unistd.h>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "aggpack/core/error.hpp"
#include "aggpack/core/version.hpp"
#include "aggpack/dynamics/contact_law_registry.hpp"
#include "aggpack/core/input_file.hpp"
#include "aggpack/io/atomic_file.hpp"
#include "aggpack/pipeline/steps.hpp"
#include "aggpack/io/lammps_data.hpp"
#include "aggpack/pipeline/preflight.hpp"
#include "aggpack/pipeline/settle_stage.hpp"

namespace aggpack {

namespace {
// The Verlet skin: the scenario's, else DemSystem's default, 0.1 of the smallest diameter.
double lammps_skin(const DemSetup& setup, double r_min) {
  return setup.settings.skin > 0.0 ? setup.settings.skin : 0.1 * 2.0 * r_min;
}
}  // namespace

LammpsDeck lammps_settle_deck(const Scenario& sc, const ParticleStore& bed, std::uint32_t layer) {
  if (!sc.dynamics) throw InputError(fmt::format("{}: a settle step needs [dynamics]", sc.file.string()));
  const DynamicsStage& stage = *sc.dynamics;
  const ContactParameters& material = sc.material.contact;
  const ContactLawEntry& law = contact_law(material.friction_model);
  std::vector<std::uint8_t> frozen(bed.size());
  double r_min = std::numeric_limits<double>::infinity(), weight = 0.0;
  const double g = norm(stage.dem.gravity);
  for (std::size_t i = 0; i < bed.size(); ++i) {
    frozen[i] = bed.layer[i] < layer ? 1 : 0;
    if (frozen[i]) continue;
    r_min = std::min(r_min, bed.radius[i]);
    weight += bed.mass[i] * g * 2.0 * bed.radius[i];
  }
  const DemSetup setup = dem_setup(sc, r_min, 1);
  const double dt = setup.settings.time_step;
  const double skin = lammps_skin(setup, r_min);
  const QuietCriterion& quiet = stage.quiet;
  const std::size_t steps_per_sample = quiet.steps_per_sample(dt);
  // Quiet once the samples below the threshold span the window: window / interval + 1 of them.
  const auto quiet_samples = static_cast<long long>(std::ceil(quiet.window / quiet.sample_interval * (1.0 - 1e-9))) + 1;
  const Container& c = sc.container;
  const bool any_frozen = std::any_of(frozen.begin(), frozen.end(), [](std::uint8_t f) { return f != 0; });

  LammpsDeck out;
  out.data = lammps_data(bed, c, sc.material.density, c.bounds.hi.z, frozen);
  fmt::memory_buffer d;
  auto o = std::back_inserter(d);
  fmt::format_to(o, "# aggpack {}: the settle step (layer {}) of {}, seed {}, handed to LAMMPS.\n", kVersion, layer + 1,
                 sc.file.string(), sc.seed);
  fmt::format_to(o, "# Run it unchanged: lmp -in {0}   or   mpirun -np N lmp -in {0}\n", LammpsDeck::kDeckFile);
  fmt::format_to(o, "# Then: aggpack import-lammps {} --scenario <the scenario> --out <folder>\n", LammpsDeck::kDumpFile);
  fmt::format_to(o, "# aggpack's law: {}\n", law.describe(material));
  fmt::format_to(o, "# Differences of definition: {}\n", law.lammps_differences);
  fmt::format_to(o,
                 "# Stopping rule: aggpack's quiet criterion without its density condition (usually met long before\n"
                 "# the energy one): translational kinetic energy of the moving spheres / sum(m g d) below {:g} at\n"
                 "# every sample (every {:g} s) over {:g} s, or {:g} s simulated. Samples start after the first\n"
                 "# interval (aggpack's also at 0 s).\n",
                 quiet.kinetic_fraction, quiet.sample_interval, quiet.window, quiet.max_time);
  if (any_frozen) fmt::format_to(o, "# The spheres of the layers below (atom type 2) are held still, as in aggpack.\n");
  fmt::format_to(o, "units si\natom_style sphere\nboundary {0} {0} fm\nnewton off\ncomm_modify vel yes\nread_data {1}\n",
                 c.periodic ? "p" : "f", LammpsDeck::kDataFile);
  fmt::format_to(o, "group mobile type 1\n");
  fmt::format_to(o, "pair_style granular\npair_coeff * * {}\n", law.lammps_keywords(material, false));
  const std::string wall = law.lammps_keywords(material, true);
  if (!c.periodic) {
    fmt::format_to(o, "fix wall_x mobile wall/gran granular {} xplane {:.17g} {:.17g}\n", wall, c.bounds.lo.x,
                   c.bounds.hi.x);
    fmt::format_to(o, "fix wall_y mobile wall/gran granular {} yplane {:.17g} {:.17g}\n", wall, c.bounds.lo.y,
                   c.bounds.hi.y);
  }
  fmt::format_to(o, "fix floor mobile wall/gran granular {} zplane {:.17g} NULL\n", wall, c.bounds.lo.z);
  fmt::format_to(o, "fix integrate mobile nve/sphere\n");
  if (g > 0.0)
    fmt::format_to(o, "fix gravity mobile gravity {:.17g} vector {:.17g} {:.17g} {:.17g}\n", g, stage.dem.gravity.x / g,
                   stage.dem.gravity.y / g, stage.dem.gravity.z / g);
  fmt::format_to(o, "neighbor {:.17g} bin\nneigh_modify delay 0 every 1 check yes\ntimestep {:.17g}\n", skin, dt);
  fmt::format_to(o, "compute translational mobile ke\nvariable energy equal c_translational/{:.17g}\n",
                 weight > 0.0 ? weight : 1.0);
  fmt::format_to(o, "variable quiet_samples equal 0\nthermo_style custom step time v_energy\nthermo {}\n",
                 100 * steps_per_sample);
  // One setup, then the samples without LAMMPS's per-run setup (nothing changes between them).
  fmt::format_to(o, "run 0 post no\nlabel sample\nrun {} pre no post no\n", steps_per_sample);
  fmt::format_to(o,
                 "if \"${{energy}} < {:.17g}\" then \"variable quiet_samples equal $(v_quiet_samples+1)\" "
                 "else \"variable quiet_samples equal 0\"\n",
                 quiet.kinetic_fraction);
  fmt::format_to(o, "if \"${{quiet_samples}} >= {}\" then \"jump SELF settled\"\n", quiet_samples);
  fmt::format_to(o, "if \"$(time) >= {:.17g}\" then \"jump SELF settled\"\n", quiet.max_time * (1.0 - 1e-12));
  fmt::format_to(o, "jump SELF sample\nlabel settled\n");
  fmt::format_to(o, "print \"aggpack-settled: time $(time) energy ${{energy}} quiet_samples ${{quiet_samples}}\"\n");
  fmt::format_to(o, "write_dump all custom {} id type x y z radius vx vy vz modify format float %.17g sort id\n",
                 LammpsDeck::kDumpFile);
  out.deck = fmt::to_string(d);
  return out;
}

namespace {
// The first executable called `name` on PATH (or `name` itself when it holds a slash).
std::optional<std::filesystem::path> on_path(const std::string& name) {
  if (name.find('/') != std::string::npos)
    return ::access(name.c_str(), X_OK) == 0 ? std::optional<std::filesystem::path>(name) : std::nullopt;
  const char* path = std::getenv("PATH");
  std::string_view dirs = path ? path : "/usr/bin:/bin";
  while (!dirs.empty()) {
    const std::size_t colon = dirs.find(':');
    const std::filesystem::path candidate = std::filesystem::path(dirs.substr(0, colon)) / name;
    if (::access(candidate.c_str(), X_OK) == 0) return candidate;
    dirs = colon == std::string_view::npos ? std::string_view() : dirs.substr(colon + 1);
  }
  return std::nullopt;
}

std::string shell_quoted(const std::string& s) {
  std::string q = "'";
  for (const char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}
}  // namespace

void check_lammps_available(const Scenario& sc) {
  if (!sc.dynamics || sc.dynamics->engine != DemEngine::Lammps) return;
  if (!on_path(sc.dynamics->lammps_binary))
    throw InputError(fmt::format("{}: dynamics.engine = \"lammps\": \"{}\" is not on PATH; install LAMMPS (Debian: "
                                 "apt-get install lammps openmpi-bin) or set dynamics.lammps_binary",
                                 sc.file.string(), sc.dynamics->lammps_binary));
  if (sc.dynamics->lammps_ranks > 1 && !on_path("mpirun"))
    throw InputError(fmt::format("{}: dynamics.lammps_ranks = {} needs mpirun, which is not on PATH (Debian: "
                                 "apt-get install openmpi-bin)",
                                 sc.file.string(), sc.dynamics->lammps_ranks));
}

SettlingRun settle_in_lammps(const Scenario& sc, ParticleStore& particles, std::uint32_t layer, double time_offset,
                             TimeSeries& series, Progress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  const DynamicsStage& stage = *sc.dynamics;
  const std::filesystem::path dir = sc.output.directory / "lammps" / fmt::format("settle_layer_{}", layer + 1);
  std::filesystem::create_directories(dir);
  const LammpsDeck deck = lammps_settle_deck(sc, particles, layer);
  write_file_atomically(dir / LammpsDeck::kDataFile, deck.data);
  write_file_atomically(dir / LammpsDeck::kDeckFile, deck.deck);
  std::filesystem::remove(dir / LammpsDeck::kDumpFile);
  progress.start_stage(fmt::format("dynamics in LAMMPS, layer {}", layer + 1));
  progress.update({fmt::format("{} {}", stage.lammps_ranks > 1 ? fmt::format("mpirun -np {}", stage.lammps_ranks) : "",
                               stage.lammps_binary),
                   dir.string()},
                  0.0, Progress::TimeLeft::AtMost);
  const std::string command = fmt::format(
      "cd {} && {}{} -in {} -log lammps.log > lammps.out 2>&1", shell_quoted(dir.string()),
      stage.lammps_ranks > 1 ? fmt::format("mpirun --allow-run-as-root -np {} ", stage.lammps_ranks) : "",
      shell_quoted(stage.lammps_binary), LammpsDeck::kDeckFile);
  const int status = std::system(command.c_str());
  progress.clear();
  if (status != 0 || !std::filesystem::exists(dir / LammpsDeck::kDumpFile))
    throw InputError(fmt::format("{}: LAMMPS failed on the settle step of layer {} (exit status {}); its log is {}",
                                 sc.file.string(), layer + 1, status, (dir / "lammps.log").string()));
  const std::string dump_name = (dir / LammpsDeck::kDumpFile).string();
  const auto max_bytes = static_cast<std::uintmax_t>(sc.limits.max_input_file_gib * double(1u << 30));
  const LammpsBed bed = parse_lammps_dump(read_input_file(dir / LammpsDeck::kDumpFile, "LAMMPS's dump", max_bytes),
                                          dump_name, 1.0, sc.material.density);
  if (bed.particles.size() != particles.size())
    throw InputError(fmt::format("{}: LAMMPS's dump holds {} spheres, the bed {}", dump_name, bed.particles.size(),
                                 particles.size()));
  for (std::size_t i = 0; i < particles.size(); ++i) {
    particles.position[i] = bed.particles.position[i];
    particles.velocity[i] = {};
    particles.angular_velocity[i] = {};
  }
  // What the deck printed at its end: the time, the energy and the quiet samples.
  const std::string log = read_input_file(dir / "lammps.log", "LAMMPS's log", kDefaultMaxInputFileBytes);
  const std::size_t at = log.rfind("\naggpack-settled: ");
  double simulated = 0.0, energy = 0.0;
  long long quiet_samples = 0;
  if (at == std::string::npos ||
      std::sscanf(log.c_str() + at, "\naggpack-settled: time %lf energy %lf quiet_samples %lld", &simulated, &energy,
                  &quiet_samples) != 3)
    throw InputError(fmt::format("{}: the LAMMPS log has no \"aggpack-settled:\" line", (dir / "lammps.log").string()));
  const bool quiet = simulated < stage.quiet.max_time * (1.0 - 1e-12);

  // Contacts, energies and the density as aggpack measures them, on the settled positions.
  std::vector<std::uint8_t> frozen(particles.size());
  double r_min = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < particles.size(); ++i) {
    frozen[i] = particles.layer[i] < layer ? 1 : 0;
    if (!frozen[i]) r_min = std::min(r_min, particles.radius[i]);
  }
  const DemSetup setup = dem_setup(sc, r_min, 1);
  DemSystem measure(particles, sc.container, setup.model, setup.settings, frozen);
  const DensityProbe density = [&](const ParticleStore& store) { return analyse_bed(sc, store).density.mean; };
  SettleSample last;
  try {
    last = sample_system(measure, particles, weight_energy(measure, particles), density);
  } catch (const InputError&) {
    last = sample_system(measure, particles, weight_energy(measure, particles), nullptr);
  }
  last.time = simulated;
  last.translational_per_particle_mgd = energy;
  series.samples.push_back({time_offset + simulated, layer, last.density, energy, last.kinetic_energy.translational,
                            last.kinetic_energy.rotational, last.contacts.mean_overlap, last.contacts.max_overlap,
                            last.contacts.coordination});
  SettlingRun run;
  run.layer = layer;
  run.particles_settled = measure.free_count();
  run.particles_frozen = particles.size() - measure.free_count();
  run.ended_by = quiet ? SettleEnd::Quiet : SettleEnd::MaxTime;
  run.simulated_time = simulated;
  run.time_step = setup.settings.time_step;
  run.steps = static_cast<std::size_t>(std::llround(simulated / run.time_step));
  run.rayleigh_time = setup.rayleigh;
  run.time_step_from_scenario = stage.time_step.fixed.has_value();
  run.skin = lammps_skin(setup, r_min);
  run.last = last;
  run.wall_clock_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  run.particle_steps_per_second =
      run.wall_clock_s > 0 ? static_cast<double>(run.particles_settled * run.steps) / run.wall_clock_s : 0.0;
  run.threads = 1;
  run.lammps_ranks = stage.lammps_ranks;
  return run;
}

std::string export_lammps(const std::filesystem::path& scenario_file, const ScenarioOverrides& overrides,
                          const std::filesystem::path& out, std::ostream& log) {
  const Scenario sc = load_scenario(scenario_file, overrides);
  const Protocol protocol = scenario_protocol(sc);
  std::size_t k = 0;
  const auto is_dem = [](const Step& s) {
    return std::holds_alternative<SettleStep>(s.kind) || std::holds_alternative<PourStep>(s.kind) ||
           std::holds_alternative<TapStep>(s.kind);
  };
  while (k < protocol.steps.size() && !is_dem(protocol.steps[k])) ++k;
  if (k == protocol.steps.size())
    throw InputError(fmt::format("{}: the protocol has no DEM step to export ([dynamics] and a settle step)",
                                 sc.file.string()));
  const auto* settle = std::get_if<SettleStep>(&protocol.steps[k].kind);
  if (!settle)
    throw InputError(fmt::format(
        "{}: the first DEM step (step {}) is a {} step: export-lammps exports settle steps only (a pour's insertion "
        "and a tap's moving walls have no LAMMPS deck here yet); settle the bed in aggpack instead",
        sc.file.string(), k + 1, std::holds_alternative<PourStep>(protocol.steps[k].kind) ? "pour" : "tap"));
  check_output_directory(out, false);
  RunControls controls;
  controls.protocol = Protocol{{protocol.steps.begin(), protocol.steps.begin() + static_cast<std::ptrdiff_t>(k)}};
  Progress silent;
  const RunReport report = run(sc, controls, silent);
  const LammpsDeck deck = lammps_settle_deck(sc, report.particles, settle->layer);
  check_output_directory(out, true);
  write_file_atomically(out / LammpsDeck::kDataFile, deck.data);
  write_file_atomically(out / LammpsDeck::kDeckFile, deck.deck);
  const std::string step = fmt::format("step {} of {} (settle, layer {})", k + 1, protocol.steps.size(),
                                       settle->layer + 1);
  fmt::print(log, "aggpack: exported {} of {}: {} spheres in {}, the deck in {}; run it with: cd {} && lmp -in {}\n",
             step, sc.file.string(), report.particles.size(), (out / LammpsDeck::kDataFile).string(),
             (out / LammpsDeck::kDeckFile).string(), out.string(), LammpsDeck::kDeckFile);
  return step;
}

RunResult import_lammps(const std::filesystem::path& file, std::optional<std::int64_t> timestep,
                        const std::filesystem::path& scenario_file, const RunOptions& options, std::ostream& log) {
  Scenario sc = load_scenario(scenario_file, options.overrides);
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
