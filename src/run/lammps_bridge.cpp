#include "aggpack/run/lammps_bridge.hpp"

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

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <nlohmann/json.hpp>

#include "aggpack/core/error.hpp"
#include "aggpack/core/input_file.hpp"
#include "aggpack/core/overloaded.hpp"
#include "aggpack/core/version.hpp"
#include "aggpack/deposition/gas_insertion.hpp"
#include "aggpack/dynamics/contact_law_registry.hpp"
#include "aggpack/dynamics/pour.hpp"
#include "aggpack/io/atomic_file.hpp"
#include "aggpack/io/lammps_data.hpp"
#include "aggpack/io/particle_file.hpp"
#include "aggpack/run/generate_sizes.hpp"
#include "aggpack/run/preflight.hpp"
#include "aggpack/run/settle_stage.hpp"
#include "aggpack/run/steps.hpp"

namespace aggpack {

const std::string& LammpsDeck::text(const std::string& name) const {
  for (const auto& [file, contents] : files)
    if (file == name) return contents;
  throw std::out_of_range("LammpsDeck: no file " + name);
}

namespace {

using Clock = std::chrono::steady_clock;

// The Verlet skin: the scenario's, else DemSystem's default, 0.1 of the smallest diameter.
double lammps_skin(const DemSetup& setup, double r_min) {
  return setup.settings.skin > 0.0 ? setup.settings.skin : 0.1 * 2.0 * r_min;
}

// What every deck of a scenario shares: the law, the time step, the sampling.
struct DeckBasis {
  const Scenario& sc;
  const ContactLawEntry& law;
  DemSetup setup;
  double skin = 0.0;
  double g = 0.0;
  std::size_t steps_per_sample = 1;
  long long quiet_samples = 1;  // consecutive quiet samples that span the quiet window

  DeckBasis(const Scenario& scenario, double r_min)
      : sc(scenario), law(contact_law(scenario.material.contact.friction_model)), setup(dem_setup(scenario, r_min, 1)) {
    skin = lammps_skin(setup, r_min);
    g = norm(sc.dynamics->dem.gravity);
    const QuietCriterion& quiet = sc.dynamics->quiet;
    steps_per_sample = quiet.steps_per_sample(setup.settings.time_step);
    // Quiet once the samples below the threshold span the window: window / interval + 1 of them.
    quiet_samples = static_cast<long long>(std::ceil(quiet.window / quiet.sample_interval * (1.0 - 1e-9))) + 1;
  }
  [[nodiscard]] double dt() const { return setup.settings.time_step; }
};

using Out = std::back_insert_iterator<fmt::memory_buffer>;

// The comment block every deck opens with: what it is, how to run it, how it differs.
void deck_comments(Out o, const DeckBasis& b, const std::string& step, const std::string& deck_file,
                   const std::string& stopping_rule) {
  const Scenario& sc = b.sc;
  fmt::format_to(o, "# aggpack {}: the {} step of {}, seed {}, handed to LAMMPS.\n", kVersion, step, sc.file.string(),
                 sc.seed);
  fmt::format_to(o, "# Run it unchanged: lmp -in {0}   or   mpirun -np N lmp -in {0}\n", deck_file);
  fmt::format_to(o, "# Then: aggpack import-lammps {} --scenario <the scenario> --out <folder>\n",
                 LammpsDeck::kDumpFile);
  fmt::format_to(o, "# aggpack's law: {}\n", b.law.describe(sc.material.contact));
  fmt::format_to(o, "# Differences of definition: {}\n", b.law.lammps_differences);
  fmt::format_to(o, "# Stopping rule: {}\n", stopping_rule);
}

// The quiet criterion as the deck applies it (without the density condition).
std::string quiet_rule(const DeckBasis& b, const std::string& limit) {
  const QuietCriterion& q = b.sc.dynamics->quiet;
  return fmt::format(
      "aggpack's quiet criterion without its density condition (usually met long before\n"
      "# the energy one): translational kinetic energy of the moving spheres / sum(m g d) below {:g} at\n"
      "# every sample (every {:g} s) over {:g} s, or {}. Samples start after the first\n"
      "# interval (aggpack's also at 0 s).",
      q.kinetic_fraction, q.sample_interval, q.window, limit);
}

// The system: units, the box from bed.data, the law between spheres, integration, gravity,
// the neighbour list, the time step and the quantities the stopping rules read.
void deck_system(Out o, const DeckBasis& b) {
  const Scenario& sc = b.sc;
  fmt::format_to(o, "units si\natom_style sphere\nboundary {0} {0} fm\nnewton off\ncomm_modify vel yes\nread_data {1}\n",
                 sc.container.periodic ? "p" : "f", LammpsDeck::kDataFile);
  fmt::format_to(o, "group mobile type 1\n");
  fmt::format_to(o, "pair_style granular\npair_coeff * * {}\n", b.law.lammps_keywords(sc.material.contact, false));
}

void deck_motion(Out o, const DeckBasis& b) {
  const Vec3 gravity = b.sc.dynamics->dem.gravity;
  fmt::format_to(o, "fix integrate mobile nve/sphere\n");
  if (b.g > 0.0)
    fmt::format_to(o, "fix gravity mobile gravity {:.17g} vector {:.17g} {:.17g} {:.17g}\n", b.g, gravity.x / b.g,
                   gravity.y / b.g, gravity.z / b.g);
  fmt::format_to(o, "neighbor {:.17g} bin\nneigh_modify delay 0 every 1 check yes\ntimestep {:.17g}\n", b.skin, b.dt());
  // The energy per sum(m g d) of the moving spheres (m d without gravity), as aggpack's samples.
  fmt::format_to(o, "compute radius all property/atom radius\nvariable top_of atom z+c_radius\n"
                    "compute top all reduce max v_top_of\n");
  fmt::format_to(o, "variable weight_of atom mass*{:.17g}*2*c_radius\ncompute weight mobile reduce sum v_weight_of\n",
                 b.g > 0.0 ? b.g : 1.0);
  fmt::format_to(o, "compute translational mobile ke\nvariable energy equal c_translational/(c_weight+1e-300)\n");
  // Thermo output at the end of every run keeps the computes current for the checks between runs.
  fmt::format_to(o, "thermo_style custom step time atoms v_energy c_top\nthermo {}\n", 100 * b.steps_per_sample);
}

// The container at rest: fix wall/gran planes (the floor only with periodic sides).
void deck_static_walls(Out o, const DeckBasis& b) {
  const Container& c = b.sc.container;
  const std::string wall = b.law.lammps_keywords(b.sc.material.contact, true);
  if (!c.periodic) {
    fmt::format_to(o, "fix wall_x mobile wall/gran granular {} xplane {:.17g} {:.17g}\n", wall, c.bounds.lo.x,
                   c.bounds.hi.x);
    fmt::format_to(o, "fix wall_y mobile wall/gran granular {} yplane {:.17g} {:.17g}\n", wall, c.bounds.lo.y,
                   c.bounds.hi.y);
  }
  fmt::format_to(o, "fix floor mobile wall/gran granular {} zplane {:.17g} NULL\n", wall, c.bounds.lo.z);
}

// Samples of `steps_per_sample` steps until the quiet criterion's energy condition holds or
// the time reaches `max_time` (s, LAMMPS's clock), at labels `name` and `name`_done.
void deck_quiet_loop(Out o, const DeckBasis& b, const std::string& name, double max_time) {
  const QuietCriterion& q = b.sc.dynamics->quiet;
  fmt::format_to(o, "variable quiet_samples equal 0\nlabel {}\nrun {} pre no post no\n", name, b.steps_per_sample);
  fmt::format_to(o,
                 "if \"${{energy}} < {:.17g}\" then \"variable quiet_samples equal $(v_quiet_samples+1)\" "
                 "else \"variable quiet_samples equal 0\"\n",
                 q.kinetic_fraction);
  fmt::format_to(o, "if \"${{quiet_samples}} >= {}\" then \"jump SELF {}_done\"\n", b.quiet_samples, name);
  fmt::format_to(o, "if \"$(time) >= {:.17g}\" then \"jump SELF {}_done\"\n", max_time * (1.0 - 1e-12), name);
  fmt::format_to(o, "jump SELF {0}\nlabel {0}_done\n", name);
}

void deck_end(Out o) {
  fmt::format_to(o, "print \"aggpack-settled: time $(time) energy ${{energy}} quiet_samples ${{quiet_samples}}\"\n");
  fmt::format_to(o, "write_dump all custom {} id type x y z radius vx vy vz modify format float %.17g sort id\n",
                 LammpsDeck::kDumpFile);
}

double smallest_radius(std::span<const double> radii, double r_min = std::numeric_limits<double>::infinity()) {
  for (const double r : radii) r_min = std::min(r_min, r);
  return r_min;
}

LammpsDeck settle_deck(const Scenario& sc, const ParticleStore& bed, std::uint32_t layer) {
  std::vector<std::uint8_t> frozen(bed.size());
  double r_min = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < bed.size(); ++i) {
    frozen[i] = bed.layer[i] < layer ? 1 : 0;
    if (!frozen[i]) r_min = std::min(r_min, bed.radius[i]);
  }
  const DeckBasis b(sc, r_min);
  LammpsDeck out;
  out.step = fmt::format("settle, layer {}", layer + 1);
  out.deck_file = "settle.in";
  fmt::memory_buffer d;
  Out o(d);
  deck_comments(o, b, out.step, out.deck_file,
                quiet_rule(b, fmt::format("{:g} s simulated", sc.dynamics->quiet.max_time)));
  if (std::any_of(frozen.begin(), frozen.end(), [](std::uint8_t f) { return f != 0; }))
    fmt::format_to(o, "# The spheres of the layers below (atom type 2) are held still, as in aggpack.\n");
  deck_system(o, b);
  deck_static_walls(o, b);
  deck_motion(o, b);
  // One setup, then the samples without LAMMPS's per-run setup (nothing changes between them).
  fmt::format_to(o, "run 0 post no\n");
  deck_quiet_loop(o, b, "settle", sc.dynamics->quiet.max_time);
  deck_end(o);
  out.files.emplace_back(LammpsDeck::kDataFile,
                         lammps_data(bed, sc.container, sc.material.density, sc.container.bounds.hi.z, frozen));
  out.files.emplace_back(out.deck_file, fmt::to_string(d));
  return out;
}

// aggpack's pour (pour_bed) as a deck: the same batches of the same random gas, each lifted to
// the bed's top plus the gap when it comes in, at the same times, then the settling.
LammpsDeck pour_deck(const Scenario& sc, const ParticleStore& bed, const PourStep& step,
                     std::span<const double> radii) {
  const PourSettings& pour = *sc.pour;
  const QuietCriterion& quiet = sc.dynamics->quiet;
  const double r_max = radii.empty() ? 0.0 : *std::max_element(radii.begin(), radii.end());
  DeckBasis b(sc, smallest_radius(radii, smallest_radius(bed.radius)));
  // The skin is chosen for the smallest sphere still to come, as aggpack's pour does.
  const double gap = pour.gap.value_or(2.0 * r_max);
  const PourSchedule schedule = pour_schedule(pour, radii.size());
  const std::size_t batches = schedule.batches;
  LammpsDeck out;
  out.step = fmt::format("pour, part {} of {}", step.layer + 1, step.layers);
  out.deck_file = "pour.in";

  // The gas of each batch, from the pour's own random stream, its heights from the slab's bottom.
  Rng rng = pour_stream(sc.seed, step.layer);
  double bed_top = sc.container.bounds.lo.z, highest = bed_top;
  for (std::size_t i = 0; i < bed.size(); ++i) bed_top = std::max(bed_top, bed.position[i].z + bed.radius[i]);
  highest = bed_top;
  std::vector<double> fall_after(batches, 0.0);  // s until the next batch comes
  const double dt = b.dt();
  for (std::size_t k = 0; k < batches; ++k) {
    const std::span<const double> batch = schedule.batch(radii, k);
    BatchGas gas;
    try {
      gas = batch_gas(sc.container, 0.0, batch, pour.solid_fraction, rng);
    } catch (const PourInsertionError& e) {
      throw InputError(fmt::format("{}: pour.solid_fraction: {}", sc.file.string(), e.what()));
    }
    const InsertionRegion& slab = gas.slab;
    fall_after[k] = batch_fall_time(pour.velocity, b.g, slab.top);
    // The highest a slab can reach: every slab above the one before, each a gap higher.
    highest += gap + slab.top;
    ParticleStore gas_store;
    for (std::size_t j = 0; j < batch.size(); ++j) {
      gas_store.add(gas.positions[j], batch[j], sc.material.density, step.layer);
      gas_store.velocity.back() = {0.0, 0.0, -pour.velocity};
    }
    Container slab_box = sc.container;
    slab_box.bounds.lo.z = 0.0;
    out.files.emplace_back(fmt::format("pour_batch_{}.data", k + 1),
                           lammps_data(gas_store, slab_box, sc.material.density, std::max(slab.top, 1e-300), {}));
  }

  fmt::memory_buffer d;
  Out o(d);
  deck_comments(o, b, out.step, out.deck_file,
                "the pour as aggpack's: each batch comes once the one before has had the time to fall\n"
                "# its slab's height (or at max_time), then " +
                    quiet_rule(b, fmt::format("{:g} s simulated in all", quiet.max_time)));
  fmt::format_to(o, "# Each pour_batch_<k>.data holds batch k's random gas as aggpack draws it, its heights from the\n"
                    "# bottom of its slab; it is lifted to the bed's top plus the gap ({:.17g} m) as it comes in.\n",
                 gap);
  deck_system(o, b);
  deck_static_walls(o, b);
  deck_motion(o, b);
  fmt::format_to(o, "run 0 post no\n");
  // The batches, at the sample ends where aggpack's pour lets them in.
  double time = 0.0;
  const double sample = static_cast<double>(b.steps_per_sample) * dt;
  const double floor = sc.container.bounds.lo.z;
  for (std::size_t k = 0; k < batches; ++k) {
    fmt::format_to(o, "variable slab_bottom equal $((c_top>{0:.17g})*c_top+(c_top<={0:.17g})*{0:.17g}+{1:.17g})\n",
                   floor, gap);
    fmt::format_to(o, "print \"aggpack-batch: {} bottom ${{slab_bottom}}\"\n", k + 1);
    fmt::format_to(o, "read_data pour_batch_{}.data add append shift 0 0 ${{slab_bottom}} group mobile\n", k + 1);
    if (k + 1 == batches) break;
    const double next = time + fall_after[k];
    std::size_t samples = 0;
    while (time < std::min(next, quiet.max_time)) time += sample, ++samples;
    // A new batch changes the atoms: the first run after it sets LAMMPS up again.
    if (samples > 0) fmt::format_to(o, "run {} post no\n", samples * b.steps_per_sample);
  }
  const double poured_at = time;
  fmt::format_to(o, "run 0 post no\n");
  deck_quiet_loop(o, b, "settle", poured_at + std::max(quiet.sample_interval, quiet.max_time - poured_at));
  deck_end(o);
  out.files.insert(out.files.begin(),
                   {LammpsDeck::kDataFile,
                    lammps_data(bed, sc.container, sc.material.density,
                                std::max(sc.container.bounds.hi.z, highest + 2.0 * r_max), {})});
  out.files.emplace_back(out.deck_file, fmt::to_string(d));
  return out;
}

// aggpack's tapping (tap_bed) as a deck: the container a region whose height follows the
// taps, its walls `fix wall/gran/region` (the walls' velocity enters the contacts, as in
// aggpack), a dump after every rest.
LammpsDeck tap_deck(const Scenario& sc, const ParticleStore& bed) {
  const TappingSettings& tapping = *sc.tapping;
  const DeckBasis b(sc, smallest_radius(bed.radius));
  const QuietCriterion& quiet = sc.dynamics->quiet;
  const double omega = 2.0 * std::numbers::pi * tapping.frequency;
  const double amplitude = tapping.intensity * b.g / (omega * omega);
  const double dt = b.dt();
  const double half_period = 0.5 * 2.0 * std::numbers::pi / omega;
  const Container& c = sc.container;
  LammpsDeck out;
  out.step = "tap";
  out.deck_file = "tap.in";
  fmt::memory_buffer d;
  Out o(d);
  deck_comments(o, b, out.step, out.deck_file,
                fmt::format("{} taps, each half a sine period of {:g} Hz (amplitude {:.6g} m, peak acceleration "
                            "{:g} g)\n# of the container, then a rest of {:g} s{}; tap_<k>.dump after each rest.",
                            tapping.taps, tapping.frequency, amplitude, tapping.intensity, tapping.rest_time,
                            tapping.rest_until_quiet ? ", ended early once quiet (energy condition over the quiet window)"
                                                     : ""));
  fmt::format_to(o, "# The container is a region moved by v_lift; LAMMPS takes its velocity from the change of\n"
                    "# position over a step (aggpack: the exact derivative).\n");
  deck_system(o, b);
  const std::string wall = b.law.lammps_keywords(sc.material.contact, true);
  fmt::format_to(o, "variable lift equal 0\n");
  if (c.periodic)
    fmt::format_to(o, "region container plane 0 0 {:.17g} 0 0 1 side in move NULL NULL v_lift units box\n",
                   c.bounds.lo.z);
  else
    fmt::format_to(o, "region container block {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} INF side in open 6 move NULL "
                      "NULL v_lift units box\n",
                   c.bounds.lo.x, c.bounds.hi.x, c.bounds.lo.y, c.bounds.hi.y, c.bounds.lo.z);
  fmt::format_to(o, "fix container mobile wall/gran/region granular {} region container\n", wall);
  deck_motion(o, b);
  fmt::format_to(o, "variable quiet_samples equal 0\nvariable tap equal 1\nrun 0 post no\nlabel tap\n");
  // The tap: to the step after its end, so the container is at rest again (as aggpack's).
  fmt::format_to(o, "variable start equal $(time)\n");
  fmt::format_to(o, "variable lift equal \"(time>v_start)*(time<v_start+{0:.17g})*{1:.17g}*sin({2:.17g}*(time-v_start))\"\n",
                 half_period, amplitude, omega);
  fmt::format_to(o, "run {} post no\n", static_cast<std::size_t>(std::ceil(half_period / dt)) + 1);
  // The rest, in samples; the last one shorter when the rest is not a whole number of them.
  const auto rest_steps = static_cast<std::size_t>(std::llround(tapping.rest_time / dt));
  const std::size_t full = rest_steps / b.steps_per_sample, last = rest_steps % b.steps_per_sample;
  fmt::format_to(o, "variable rest_samples equal 0\nvariable quiet_samples equal 0\nlabel rest\n");
  if (full > 0) {
    fmt::format_to(o, "run {} pre no post no\nvariable rest_samples equal $(v_rest_samples+1)\n", b.steps_per_sample);
    if (tapping.rest_until_quiet) {
      fmt::format_to(o,
                     "if \"${{energy}} <= {:.17g}\" then \"variable quiet_samples equal $(v_quiet_samples+1)\" "
                     "else \"variable quiet_samples equal 0\"\n",
                     quiet.kinetic_fraction);
      fmt::format_to(o, "if \"${{quiet_samples}} >= {}\" then \"jump SELF rest_done\"\n", b.quiet_samples);
    }
    fmt::format_to(o, "if \"${{rest_samples}} < {}\" then \"jump SELF rest\"\n", full);
  }
  if (last > 0) fmt::format_to(o, "run {} pre no post no\n", last);
  fmt::format_to(o, "label rest_done\n");
  fmt::format_to(o, "print \"aggpack-tap: ${{tap}} time $(time) energy ${{energy}}\"\n");
  fmt::format_to(o, "write_dump all custom tap_${{tap}}.dump id type x y z radius modify format float %.17g sort id\n");
  fmt::format_to(o, "variable tap equal $(v_tap+1)\nif \"${{tap}} <= {}\" then \"jump SELF tap\"\n", tapping.taps);
  deck_end(o);
  out.files.emplace_back(LammpsDeck::kDataFile, lammps_data(bed, c, sc.material.density, c.bounds.hi.z, {}));
  out.files.emplace_back(out.deck_file, fmt::to_string(d));
  return out;
}

}  // namespace

LammpsDeck lammps_deck(const Scenario& sc, const ParticleStore& bed, const LammpsStep& step,
                       std::span<const double> pour_radii) {
  if (!sc.dynamics) throw InputError(fmt::format("{}: a DEM step needs [dynamics]", sc.file.string()));
  return std::visit(Overloaded{[&](const SettleStep& s) { return settle_deck(sc, bed, s.layer); },
                               [&](const PourStep& s) { return pour_deck(sc, bed, s, pour_radii); },
                               [&](const TapStep&) { return tap_deck(sc, bed); }},
                    step);
}

void write_lammps_deck(const std::filesystem::path& folder, const LammpsDeck& deck) {
  std::filesystem::create_directories(folder);
  for (const auto& [name, contents] : deck.files) write_file_atomically(folder / name, contents);
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

std::uintmax_t max_input_bytes(const Scenario& sc) {
  return static_cast<std::uintmax_t>(sc.limits.max_input_file_gib * double(1u << 30));
}

LammpsBed read_dump(const std::filesystem::path& file, const Scenario& sc, std::optional<std::int64_t> timestep = {}) {
  return parse_lammps_dump(read_input_text(file, "LAMMPS's dump", max_input_bytes(sc)), file.string(), 1.0,
                           sc.material.density, timestep);
}

// What the deck printed: the lines that begin with `tag`, each read by `scan` (false: malformed).
std::vector<std::string> tagged_lines(const std::string& log, const std::string& tag) {
  std::vector<std::string> lines;
  for (std::size_t at = log.find(tag); at != std::string::npos; at = log.find(tag, at + 1))
    if (at == 0 || log[at - 1] == '\n') lines.push_back(log.substr(at, log.find('\n', at) - at));
  return lines;
}

// A deck run by LAMMPS in `folder`, its output in lammps.log and lammps.out; its log's text.
std::string run_lammps(const Scenario& sc, const std::filesystem::path& folder, const LammpsDeck& deck,
                       Progress& progress) {
  const DynamicsStage& stage = *sc.dynamics;
  std::filesystem::remove(folder / LammpsDeck::kDumpFile);
  write_lammps_deck(folder, deck);
  const std::string mpirun =
      stage.lammps_ranks > 1 ? fmt::format("mpirun --allow-run-as-root -np {} ", stage.lammps_ranks) : "";
  progress.start_stage(fmt::format("{} in LAMMPS", deck.step));
  progress.update({mpirun + stage.lammps_binary, folder.string()}, 0.0, Progress::TimeLeft::AtMost);
  const std::string command =
      fmt::format("cd {} && {}{} -in {} -log {} > lammps.out 2>&1", shell_quoted(folder.string()), mpirun,
                  shell_quoted(stage.lammps_binary), deck.deck_file, LammpsDeck::kLogFile);
  const int status = std::system(command.c_str());
  progress.clear();
  if (status != 0 || !std::filesystem::exists(folder / LammpsDeck::kDumpFile))
    throw InputError(fmt::format("{}: LAMMPS failed on the {} step (exit status {}); its log is {}", sc.file.string(),
                                 deck.step, status, (folder / LammpsDeck::kLogFile).string()));
  return read_input_text(folder / LammpsDeck::kLogFile, "LAMMPS's log", kDefaultMaxInputFileBytes);
}

struct SettledLine {
  double time = 0.0, energy = 0.0;
};
SettledLine settled_line(const std::string& log, const std::filesystem::path& folder) {
  const std::vector<std::string> lines = tagged_lines(log, "aggpack-settled: ");
  SettledLine s;
  long long quiet_samples = 0;
  if (lines.empty() || std::sscanf(lines.back().c_str(), "aggpack-settled: time %lf energy %lf quiet_samples %lld",
                                   &s.time, &s.energy, &quiet_samples) != 3)
    throw InputError(
        fmt::format("{}: the LAMMPS log has no \"aggpack-settled:\" line", (folder / LammpsDeck::kLogFile).string()));
  return s;
}

// The positions of `dump` put in place of the store's first spheres (same radii, by id).
void take_positions(ParticleStore& particles, const ParticleStore& dump, const std::string& name, std::size_t count) {
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
  const auto t0 = Clock::now();
  const std::filesystem::path folder = lammps_folder(sc, fmt::format("settle_layer_{}", layer + 1));
  const std::string log = run_lammps(sc, folder, lammps_deck(sc, particles, SettleStep{layer}), progress);
  const std::filesystem::path dump = folder / LammpsDeck::kDumpFile;
  take_positions(particles, read_dump(dump, sc).particles, dump.string(), particles.size());
  double r_min = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < particles.size(); ++i)
    if (particles.layer[i] >= layer) r_min = std::min(r_min, particles.radius[i]);
  return lammps_settling_run(sc, particles, layer, layer, settled_line(log, folder), r_min, t0, time_offset, series);
}

PourRun pour_in_lammps(const Scenario& sc, ParticleStore& particles, std::span<const double> radii,
                       const PourStep& step, double time_offset, TimeSeries& series, Progress& progress) {
  const auto t0 = Clock::now();
  const std::filesystem::path folder = lammps_folder(sc, fmt::format("pour_part_{}", step.layer + 1));
  const LammpsDeck deck = lammps_deck(sc, particles, step, radii);
  const std::string log = run_lammps(sc, folder, deck, progress);
  const std::filesystem::path dump_file = folder / LammpsDeck::kDumpFile;
  const LammpsBed dump = read_dump(dump_file, sc);
  // The poured spheres come after the bed's, in the order aggpack inserts them.
  for (const double r : radii) particles.add({}, r, sc.material.density, step.layer);
  take_positions(particles, dump.particles, dump_file.string(), particles.size());

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
  const DeckBasis basis(sc, smallest_radius(particles.radius));
  TapReport report;
  const double omega = 2.0 * std::numbers::pi * tapping.frequency;
  report.taps = tapping.taps;
  report.intensity = tapping.intensity;
  report.frequency = tapping.frequency;
  report.amplitude = tapping.intensity * basis.g / (omega * omega);
  report.rest_time = tapping.rest_time;
  report.rest_until_quiet = tapping.rest_until_quiet;
  report.time_step = basis.dt();
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
    take_positions(after, read_dump(dump, sc).particles, dump.string(), after.size());
    append_sample(series, time_offset + time, 0, measured_sample(sc, after, 0, false, energy));
    report.samples.push_back({k + 1, time_offset + time, box_density_or_nan(sc, after), energy});
  }
  const std::filesystem::path dump = folder / LammpsDeck::kDumpFile;
  take_positions(particles, read_dump(dump, sc).particles, dump.string(), particles.size());
  report.simulated_time = settled_line(log, folder).time;
  report.steps = static_cast<std::size_t>(std::llround(report.simulated_time / report.time_step));
  report.wall_clock_s = std::chrono::duration<double>(Clock::now() - t0).count();
  return report;
}

std::string take_positions_from_lammps(ParticleStore& particles, const std::filesystem::path& file,
                                       std::optional<std::int64_t> timestep, const Scenario& sc) {
  PackingFile read = read_packing_file(file, 1.0, sc.material.density, max_input_bytes(sc), timestep);
  if (read.format.rfind("LAMMPS", 0) != 0)
    throw InputError(fmt::format("{}: a {} file, not a LAMMPS dump or data file", file.string(), read.format));
  take_positions(particles, read.particles, file.string(), particles.size());
  check_imported_bed(sc, particles, file);
  return read.format;
}

std::string export_lammps(const std::filesystem::path& scenario_or_run, const ScenarioOverrides& overrides,
                          const std::filesystem::path& out, bool tap, std::ostream& log) {
  check_output_directory(out, false);
  LammpsDeck deck;
  std::string source;
  std::size_t spheres = 0, poured = 0;
  if (std::filesystem::is_directory(scenario_or_run)) {
    // A finished run: its scenario (with the overrides it ran with) and its final bed.
    const std::filesystem::path summary_file = scenario_or_run / "summary.json";
    const std::filesystem::path bed_file = scenario_or_run / "particles.csv";
    for (const auto& f : {summary_file, bed_file})
      if (!std::filesystem::exists(f))
        throw InputError(fmt::format("{}: a run's folder holds {}; this one has none (is it the output folder of a "
                                     "finished aggpack run?)",
                                     scenario_or_run.string(), f.filename().string()));
    std::filesystem::path scenario_file;
    std::optional<std::string> stopped;  // where an interrupted run stopped: its bed is not a final one
    ScenarioOverrides recorded = overrides;
    try {
      const auto summary =
          nlohmann::json::parse(read_input_text(summary_file, "the run's summary", kDefaultMaxInputFileBytes));
      scenario_file = summary.value("scenario_file", std::string());
      // A relative path is the run's: from the folder it was started in, not this one.
      const std::filesystem::path started_in = summary.value("working_directory", std::string());
      if (!scenario_file.empty() && !started_in.empty()) scenario_file = started_in / scenario_file;
      if (summary.value("interrupted", false))
        stopped = summary.at("interruption").value("stopped", std::string("at an unrecorded point"));
      if (!recorded.seed && summary.contains("seed")) recorded.seed = recorded_seed(summary.at("seed"), summary_file);
      // The run's own overrides first, in their order; the command's --set after them win.
      if (summary.contains("scenario_overrides")) {
        const auto run_sets = summary.at("scenario_overrides").get<std::vector<std::string>>();
        recorded.set.insert(recorded.set.begin(), run_sets.begin(), run_sets.end());
      }
    } catch (const nlohmann::json::exception& e) {
      throw InputError(fmt::format("{}: not a summary.json aggpack wrote: {}", summary_file.string(), e.what()));
    }
    if (scenario_file.empty() || !std::filesystem::exists(scenario_file))
      throw InputError(fmt::format("{}: its scenario_file \"{}\" is gone; export the bed with "
                                   "export-lammps SCENARIO, or run the scenario again",
                                   summary_file.string(), scenario_file.string()));
    const Scenario sc = load_scenario(scenario_file, recorded);
    if (!sc.dynamics)
      throw InputError(fmt::format("{}: the scenario has no [dynamics]: the deck takes its law, time step and "
                                   "stopping rule from there",
                                   scenario_file.string()));
    if (tap && !sc.tapping)
      throw InputError(fmt::format("{}: --tap: the scenario has no [tapping] table for the taps",
                                   scenario_file.string()));
    ParticleStore bed = read_packing_file(bed_file, 1.0, sc.material.density, max_input_bytes(sc)).particles;
    for (auto& l : bed.layer) l = 0;
    deck = lammps_deck(sc, bed, tap ? LammpsStep{TapStep{}} : LammpsStep{SettleStep{0}});
    if (stopped) {
      // particles.csv is the bed mid-step (a settle, a pour, a tap): say so wherever it goes.
      const std::string bed_was =
          fmt::format("the bed of the interrupted run in {}, as it stood {}", scenario_or_run.string(), *stopped);
      add_note(deck, "Not a final bed: " + bed_was);
      source = bed_was + ", not a final bed";
    } else {
      source = fmt::format("the final bed of the run in {}", scenario_or_run.string());
    }
    spheres = bed.size();
  } else {
    if (tap)
      throw InputError(fmt::format("{}: --tap applies to a run's folder; for a scenario the step exported is its "
                                   "first DEM step (a tap step when that comes first)",
                                   scenario_or_run.string()));
    const Scenario sc = load_scenario(scenario_or_run, overrides);
    const Protocol protocol = scenario_protocol(sc);
    std::size_t k = 0;
    const auto is_dem = [](const Step& s) {
      return std::holds_alternative<SettleStep>(s.kind) || std::holds_alternative<PourStep>(s.kind) ||
             std::holds_alternative<TapStep>(s.kind);
    };
    while (k < protocol.steps.size() && !is_dem(protocol.steps[k])) ++k;
    if (k == protocol.steps.size())
      throw InputError(fmt::format("{}: the protocol has no DEM step to export (a settle, pour or tap step)",
                                   sc.file.string()));
    RunControls controls;
    // The steps before it, but the scenario's own exports (they would write into its output folder).
    controls.protocol.emplace();
    for (std::size_t j = 0; j < k; ++j)
      if (!std::holds_alternative<ExportLammpsStep>(protocol.steps[j].kind))
        controls.protocol->steps.push_back(protocol.steps[j]);
    controls.final_analysis = false;
    Progress silent;
    const RunReport report = run(sc, controls, silent);
    const StepKind& kind = protocol.steps[k].kind;
    std::span<const double> pour_radii;
    std::vector<double> radii;
    LammpsStep step;
    if (const auto* p = std::get_if<PourStep>(&kind)) {
      for (const double d : generate_sizes(sc.particles, sc.seed).diameters) radii.push_back(0.5 * d);
      const std::size_t begin = radii.size() * p->layer / p->layers, end = radii.size() * (p->layer + 1) / p->layers;
      pour_radii = std::span<const double>(radii).subspan(begin, end - begin);
      step = *p;
    } else if (const auto* s = std::get_if<SettleStep>(&kind)) {
      step = *s;
    } else {
      step = TapStep{};
    }
    deck = lammps_deck(sc, report.particles, step, pour_radii);
    poured = pour_radii.size();
    source = fmt::format("step {} of {} of {}", k + 1, protocol.steps.size(), sc.file.string());
    spheres = report.particles.size();
  }
  check_output_directory(out, true);
  write_lammps_deck(out, deck);
  fmt::print(log, "aggpack: exported {} ({}): {} spheres in {}{}, the deck in {}; run it with: cd {} && lmp -in {}\n",
             source, deck.step, spheres, (out / LammpsDeck::kDataFile).string(),
             poured > 0 ? fmt::format(" and {} to pour in pour_batch_*.data", poured) : std::string(),
             (out / deck.deck_file).string(), out.string(), deck.deck_file);
  return deck.step;
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
