#include "aggpack/lammps/deck.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <variant>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/core/overloaded.hpp"
#include "aggpack/core/version.hpp"
#include "aggpack/deposition/gas_insertion.hpp"
#include "aggpack/dynamics/contact_law_registry.hpp"
#include "aggpack/dynamics/materials.hpp"
#include "aggpack/dynamics/pour.hpp"
#include "aggpack/dynamics/tap.hpp"
#include "aggpack/io/atomic_file.hpp"
#include "aggpack/io/lammps_data.hpp"

namespace aggpack {

const std::string& LammpsDeck::text(const std::string& name) const {
  for (const auto& [file, contents] : files)
    if (file == name) return contents;
  throw std::out_of_range("LammpsDeck: no file " + name);
}

double lammps_skin(const DemSetup& setup, double r_min) {
  return setup.settings.skin > 0.0 ? setup.settings.skin : DemSystem::default_skin(r_min);
}

namespace {

// What every deck of a scenario shares: the law, the time step, the sampling.
struct DeckBasis {
  const Scenario& sc;
  const ContactLawEntry& law;
  std::vector<double> densities;  // kg/m^3, per material (atom types m + 1, frozen M + m + 1)
  DemSetup setup;
  double skin = 0.0;
  double g = 0.0;
  std::size_t steps_per_sample = 1;
  long long quiet_samples = 1;  // consecutive quiet samples that span the quiet window

  DeckBasis(const Scenario& scenario, double r_min)
      : sc(scenario), law(contact_law(scenario.material.contact.friction_model)),
        densities(material_densities(scenario)), setup(dem_setup(scenario, r_min, 1)) {
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
  if (sc.particles.has_grains())  // a dump holds spheres: the run knows the grains they make up
    fmt::format_to(o, "# Then: take {} back within the run, by an import_lammps step (file = \"{}\")\n",
                   LammpsDeck::kDumpFile, LammpsDeck::kDumpFile);
  else
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

// The parameters that make LAMMPS's pair granular give the contact of materials a and b what
// aggpack gives it: LAMMPS computes E* = E / (2 (1 - nu^2)) and G* = E / (4 (2 - nu)(1 + nu))
// from the one E and nu of a pair_coeff I J, so the pair gets the E and nu whose E* and G*
// are aggpack's (G*/E* = (1 - nu) / (2 (2 - nu)) fixes nu), and its mixed coefficients.
ContactParameters lammps_pair(std::span<const ContactParameters> materials,
                              std::span<const MaterialPairCoefficients> pairs, std::size_t a, std::size_t b) {
  const ContactCoefficients c = pair_coefficients(materials, pairs, a, b);
  const PairValues v = pair_values(materials, pairs, a, b);
  const double ratio = c.g_star / c.e_star;
  ContactParameters p = materials[0];
  p.poisson_ratio = (4.0 * ratio - 1.0) / (2.0 * ratio - 1.0);
  p.youngs_modulus = 2.0 * c.e_star * (1.0 - p.poisson_ratio * p.poisson_ratio);
  p.restitution = v.restitution;
  p.friction_particle = v.friction;
  p.rolling_friction = v.rolling_friction;
  p.rolling_stiffness = v.rolling_stiffness;
  p.rolling_damping = v.rolling_damping;
  return p;
}

// The groups a wall fix acts on, the fix names' suffix and the wall's coefficients: `mobile`
// for one material, else each material's mobile spheres with its own.
struct WallGroup {
  std::string group, suffix, keywords;
};
std::vector<WallGroup> wall_groups(const DeckBasis& b) {
  const Scenario& sc = b.sc;
  if (b.densities.size() == 1) return {{"mobile", "", b.law.lammps_keywords(sc.material.contact, true)}};
  std::vector<WallGroup> groups;
  for (std::size_t k = 0; k < b.densities.size(); ++k)
    groups.push_back({fmt::format("mobile_{}", material_name(sc, k)), fmt::format("_{}", material_name(sc, k)),
                      b.law.lammps_keywords(material_of(sc, k).contact, true)});
  return groups;
}

// The farthest a grain's sphere reaches from its centre of mass, m (0 without grains).
double largest_reach(const ParticleStore& bed) {
  double reach = 0.0;
  for (std::size_t i = 0; i < bed.body.size(); ++i)
    if (bed.body[i] != kNoBody) reach = std::max(reach, norm(bed.body_offset[i]) + bed.radius[i]);
  return reach;
}

// The groups a bed with grains adds: `grains`, their spheres (rigid/small moves them), and
// `free`, the mobile spheres of their own (nve/sphere moves them).
void deck_grain_groups(Out o, const ParticleStore& bed) {
  if (!bed.bodies.empty()) fmt::format_to(o, "group grains molecule > 0\ngroup free subtract mobile grains\n");
}

// The system: units, the box from bed.data, the law between spheres, integration, gravity,
// the neighbour list, the time step and the quantities the stopping rules read.
void deck_system(Out o, const DeckBasis& b, const ParticleStore& bed) {
  const Scenario& sc = b.sc;
  const char* boundary = sc.container.periodic ? "p" : "f";
  if (bed.bodies.empty()) {
    fmt::format_to(o, "units si\natom_style sphere\nboundary {0} {0} fm\nnewton off\ncomm_modify vel yes\nread_data {1}\n",
                   boundary, LammpsDeck::kDataFile);
  } else {
    // Grains: molecules of spheres (rigid/small needs the atom map), and ghosts reaching across
    // a whole grain (a grain's spheres must all be seen by the rank that owns it).
    const double cutoff = 2.0 * largest_reach(bed) + b.skin;
    fmt::format_to(o, "units si\natom_style hybrid sphere bond\natom_modify map array\nboundary {0} {0} fm\nnewton off\n"
                      "comm_modify vel yes cutoff {2:.17g}\nread_data {1}\n",
                   boundary, LammpsDeck::kDataFile, cutoff);
  }
  const std::size_t m = b.densities.size();
  if (m == 1) {
    fmt::format_to(o, "group mobile type 1\n");
    deck_grain_groups(o, bed);
    fmt::format_to(o, "pair_style granular\npair_coeff * * {}\n", b.law.lammps_keywords(sc.material.contact, false));
    return;
  }
  // Several materials: material k's spheres are type k + 1, held still M + k + 1.
  fmt::format_to(o, "group mobile type");
  for (std::size_t k = 0; k < m; ++k) fmt::format_to(o, " {}", k + 1);
  fmt::format_to(o, "\n");
  for (std::size_t k = 0; k < m; ++k) fmt::format_to(o, "group mobile_{} type {}\n", material_name(sc, k), k + 1);
  deck_grain_groups(o, bed);
  fmt::format_to(o, "pair_style granular\n");
  const std::vector<ContactParameters> contacts = material_contacts(sc);
  for (std::size_t i = 0; i < 2 * m; ++i)
    for (std::size_t j = i; j < 2 * m; ++j)
      fmt::format_to(o, "pair_coeff {} {} {}\n", i + 1, j + 1,
                     b.law.lammps_keywords(lammps_pair(contacts, sc.material_pairs, i % m, j % m), false));
}

// Integration and gravity: nve/sphere for the spheres of their own; with grains, rigid/small
// for theirs, from bodies.txt (`reinit no`: a later run's setup would put them back where the
// file has them), gravity on each grain's centre of mass (the fix's gravity keyword: by the
// spheres it would act on their summed, overlapping masses).
void deck_motion(Out o, const DeckBasis& b, const ParticleStore& bed) {
  const Vec3 gravity = b.sc.dynamics->dem.gravity;
  const bool grains = !bed.bodies.empty();
  const char* moved = grains ? "free" : "mobile";
  fmt::format_to(o, "fix integrate {} nve/sphere\n", moved);
  if (b.g > 0.0)
    fmt::format_to(o, "fix gravity {} gravity {:.17g} vector {:.17g} {:.17g} {:.17g}\n", moved, b.g, gravity.x / b.g,
                   gravity.y / b.g, gravity.z / b.g);
  if (grains)
    fmt::format_to(o, "fix rigid grains rigid/small molecule infile {} reinit no{}\n", LammpsDeck::kBodiesFile,
                   b.g > 0.0 ? " gravity gravity" : "");
  fmt::format_to(o, "neighbor {:.17g} bin\nneigh_modify delay 0 every 1 check yes\ntimestep {:.17g}\n", b.skin, b.dt());
  // The energy per sum(m g d) of the moving spheres (m d without gravity), as aggpack's samples.
  fmt::format_to(o, "compute radius all property/atom radius\nvariable top_of atom z+c_radius\n"
                    "compute top all reduce max v_top_of\n");
  fmt::format_to(o, "variable weight_of atom mass*{:.17g}*2*c_radius\ncompute weight mobile reduce sum v_weight_of\n",
                 b.g > 0.0 ? b.g : 1.0);
  if (grains)  // a grain's translational energy is its union's mass times its centre's speed, as aggpack's
    fmt::format_to(o, "compute translational_free free ke\ncompute translational_grains all ke/rigid rigid\n"
                      "variable energy equal (c_translational_free+c_translational_grains)/(c_weight+1e-300)\n");
  else
    fmt::format_to(o, "compute translational mobile ke\nvariable energy equal c_translational/(c_weight+1e-300)\n");
  // Thermo output at the end of every run keeps the computes current for the checks between runs.
  fmt::format_to(o, "thermo_style custom step time atoms v_energy c_top\nthermo {}\n", 100 * b.steps_per_sample);
}

// The container at rest: fix wall/gran planes (the floor only with periodic sides; a
// cylinder's floor and its wall by wall/gran/region), one set per material of several (a wall/gran fix has one set of coefficients for its group).
void deck_static_walls(Out o, const DeckBasis& b) {
  const Container& c = b.sc.container;
  // A cylinder's wall: a region's curved side alone (its caps open; the floor is the plane below).
  if (c.is_cylinder())
    fmt::format_to(o, "region measure cylinder z {:.17g} {:.17g} {:.17g} {:.17g} INF side in open 1 open 2 units box\n",
                   c.axis_x(), c.axis_y(), c.radius(), c.bounds.lo.z);
  for (const auto& [group, suffix, wall] : wall_groups(b)) {
    if (c.is_cylinder())
      fmt::format_to(o, "fix wall_side{} {} wall/gran/region granular {} region measure\n", suffix, group, wall);
    else if (!c.periodic) {
      fmt::format_to(o, "fix wall_x{} {} wall/gran granular {} xplane {:.17g} {:.17g}\n", suffix, group, wall,
                     c.bounds.lo.x, c.bounds.hi.x);
      fmt::format_to(o, "fix wall_y{} {} wall/gran granular {} yplane {:.17g} {:.17g}\n", suffix, group, wall,
                     c.bounds.lo.y, c.bounds.hi.y);
    }
    fmt::format_to(o, "fix floor{} {} wall/gran granular {} zplane {:.17g} NULL\n", suffix, group, wall,
                   c.bounds.lo.z);
  }
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

// The highest sphere surface of the bed, m (the floor for an empty one): where aggpack's pour
// puts a batch's slab, the gap above.
double top_of_bed(const ParticleStore& bed, const Container& container) {
  double top = container.bounds.lo.z;
  for (std::size_t i = 0; i < bed.size(); ++i) top = std::max(top, bed.position[i].z + bed.radius[i]);
  return top;
}

// bed.data, and bodies.txt when the bed has grains.
void add_bed_files(LammpsDeck& deck, const DeckBasis& b, const ParticleStore& bed, double z_top,
                   std::span<const std::uint8_t> frozen = {}) {
  deck.files.emplace_back(LammpsDeck::kDataFile, lammps_data(bed, b.sc.container, b.densities, z_top, frozen));
  if (!bed.bodies.empty())
    deck.files.emplace_back(LammpsDeck::kBodiesFile, lammps_rigid_bodies(bed, b.sc.container));
}

// What the comments say of grains, when the bed has them.
void deck_grain_comments(Out o, const ParticleStore& bed) {
  if (bed.bodies.empty()) return;
  fmt::format_to(o, "# {} grains: rigid bodies of spheres (molecules; fix rigid/small), each with its union's mass,\n"
                    "# centre of mass and inertia from {}, as in aggpack. A grain's spheres take their grain's mass\n"
                    "# in contacts (LAMMPS's mass_rigid), as in aggpack.\n",
                 bed.bodies.size(), LammpsDeck::kBodiesFile);
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
  deck_grain_comments(o, bed);
  deck_system(o, b, bed);
  deck_static_walls(o, b);
  deck_motion(o, b, bed);
  // One setup, then the samples without LAMMPS's per-run setup (nothing changes between them).
  fmt::format_to(o, "run 0 post no\n");
  deck_quiet_loop(o, b, "settle", sc.dynamics->quiet.max_time);
  deck_end(o);
  add_bed_files(out, b, bed, sc.container.bounds.hi.z, frozen);
  out.files.emplace_back(out.deck_file, fmt::to_string(d));
  return out;
}

// The pour's batches as pour_batch_<k>.data files (the gas drawn from the pour's own random
// stream, its heights from the slab's bottom), with what the deck needs to let them in.
struct PourBatches {
  std::vector<std::pair<std::string, std::string>> files;  // pour_batch_<k>.data, in order
  std::vector<double> fall_after;                          // s until the next batch comes
  double highest = 0.0;  // the highest a slab can reach: every slab above the one before, each a gap higher
};

// The deck lets every batch in at pour.velocity: a release height (aggpack's DEM's) is refused.
void check_no_release_height(const Scenario& sc) {
  if (sc.pour && sc.pour->release_height)
    throw InputError(
        fmt::format("{}: pour.release_height: the LAMMPS deck lets the pour's batches in at "
                    "pour.velocity, not from a release height (aggpack's own DEM's); expected "
                    "pour.velocity instead, or no export_lammps step",
                    sc.file.string()));
}

PourBatches pour_batches(const DeckBasis& b, const ParticleStore& bed, const PourStep& step,
                         std::span<const double> radii, std::span<const std::uint8_t> materials,
                         const PourSchedule& schedule, double gap) {
  const Scenario& sc = b.sc;
  check_no_release_height(sc);
  const SphereMaterials of{materials, b.densities};
  const double g = b.g;
  const PourSettings& pour = *sc.pour;
  const std::size_t batches = schedule.batches;
  PourBatches out;
  Rng rng = pour_stream(sc.seed, step.layer);
  out.highest = top_of_bed(bed, sc.container);
  out.fall_after.assign(batches, 0.0);
  for (std::size_t k = 0; k < batches; ++k) {
    const std::span<const double> batch = schedule.batch(radii, k);
    BatchGas gas;
    try {
      gas = batch_gas(sc.container, 0.0, batch, pour.solid_fraction, rng);
    } catch (const PourInsertionError& e) {
      throw InputError(fmt::format("{}: pour.solid_fraction: {}", sc.file.string(), e.what()));
    }
    const InsertionRegion& slab = gas.slab;
    out.fall_after[k] = batch_fall_time(pour.velocity, g, slab.top);
    out.highest += gap + slab.top;
    ParticleStore gas_store;
    const auto first = static_cast<std::size_t>(batch.data() - radii.data());  // of the batch in the pour
    for (std::size_t j = 0; j < batch.size(); ++j) {
      gas_store.add(gas.positions[j], batch[j], of.density_of(first + j), step.layer, of.material(first + j));
      gas_store.velocity.back() = {0.0, 0.0, -pour.velocity};
    }
    Container slab_box = sc.container;
    slab_box.bounds.lo.z = 0.0;
    out.files.emplace_back(fmt::format("pour_batch_{}.data", k + 1),
                           lammps_data(gas_store, slab_box, b.densities, std::max(slab.top, 1e-300), {}));
  }
  return out;
}

// The batches, at the sample ends where aggpack's pour lets them in: each read in at the
// bed's top plus the gap, then the runs until the next one. Returns the time the last came in.
double deck_pour_batches(Out o, const DeckBasis& b, const std::vector<double>& fall_after, double gap) {
  const Scenario& sc = b.sc;
  const QuietCriterion& quiet = sc.dynamics->quiet;
  const std::size_t batches = fall_after.size();
  double time = 0.0;
  const double sample = static_cast<double>(b.steps_per_sample) * b.dt();
  const double floor = sc.container.bounds.lo.z;
  for (std::size_t k = 0; k < batches; ++k) {
    fmt::format_to(o, "variable slab_bottom equal $((c_top>{0:.17g})*c_top+(c_top<={0:.17g})*{0:.17g}+{1:.17g})\n",
                   floor, gap);
    fmt::format_to(o, "print \"aggpack-batch: {} bottom ${{slab_bottom}}\"\n", k + 1);
    fmt::format_to(o, "read_data pour_batch_{}.data add append shift 0 0 ${{slab_bottom}} group mobile\n", k + 1);
    // A group is the atoms it held when made: each material's takes its new spheres in.
    if (b.densities.size() > 1)
      for (std::size_t m = 0; m < b.densities.size(); ++m)
        fmt::format_to(o, "group mobile_{} type {}\n", material_name(sc, m), m + 1);
    if (k + 1 == batches) break;
    const double next = time + fall_after[k];
    std::size_t samples = 0;
    while (time < std::min(next, quiet.max_time)) time += sample, ++samples;
    // A new batch changes the atoms: the first run after it sets LAMMPS up again.
    if (samples > 0) fmt::format_to(o, "run {} post no\n", samples * b.steps_per_sample);
  }
  return time;
}

// A pour with grains (of them, or into a bed of them), which LAMMPS takes as one batch: the
// gas is aggpack's (the same positions, and orientations from the same stream), put into
// bed.data above the bed by the gap, as aggpack's pour puts it in at its start; then the
// settling.
LammpsDeck pour_deck_with_grains(const Scenario& sc, const ParticleStore& bed, const PourStep& step,
                                 std::span<const double> radii, std::span<const std::uint8_t> materials,
                                 const PouredShapes& shapes, const DeckBasis& b, double gap, LammpsDeck out) {
  const PourSettings& pour = *sc.pour;
  check_no_release_height(sc);
  if (pour_schedule(pour, radii.size()).batches > 1)
    throw InputError(fmt::format("{}: pour.batches: a pour with grains (of them, or into a bed of them) goes to LAMMPS "
                                 "in one batch, as LAMMPS's fix rigid/small takes its grains once, when it is "
                                 "defined; expected pour.batches = 1, or aggpack's DEM",
                                 sc.file.string()));
  const SphereMaterials of{materials, b.densities};
  Rng rng = pour_stream(sc.seed, step.layer);
  BatchGas gas;
  try {
    gas = batch_gas(sc.container, top_of_bed(bed, sc.container) + gap, radii, pour.solid_fraction, rng);
  } catch (const PourInsertionError& e) {
    throw InputError(fmt::format("{}: pour.solid_fraction: {}", sc.file.string(), e.what()));
  }
  ParticleStore poured = bed;
  for (std::size_t k = 0; k < radii.size(); ++k) {
    const RigidBodyShape* shape = shapes.shape(k);  // orientations drawn as aggpack's pour draws them
    add_poured(poured, gas.positions[k], radii[k], shape, shape ? random_orientation(rng) : Quaternion{},
               {0.0, 0.0, -pour.velocity}, of.density_of(k), step.layer, of.material(k));
  }
  fmt::memory_buffer d;
  Out o(d);
  const QuietCriterion& quiet = sc.dynamics->quiet;
  deck_comments(o, b, out.step, out.deck_file, quiet_rule(b, fmt::format("{:g} s simulated in all", quiet.max_time)));
  fmt::format_to(o, "# The pour in one batch: bed.data holds the bed and the pour's random gas as aggpack draws it,\n"
                    "# its slab from the bed's top plus the gap ({:.17g} m), falling at {:g} m/s.\n",
                 gap, pour.velocity);
  deck_grain_comments(o, poured);
  deck_system(o, b, poured);
  deck_static_walls(o, b);
  deck_motion(o, b, poured);
  fmt::format_to(o, "print \"aggpack-batch: 1 bottom {:.17g}\"\n", gas.slab.bottom);
  fmt::format_to(o, "run 0 post no\n");
  deck_quiet_loop(o, b, "settle", quiet.max_time);
  deck_end(o);
  const double r_max = radii.empty() ? 0.0 : *std::max_element(radii.begin(), radii.end());
  add_bed_files(out, b, poured, std::max(sc.container.bounds.hi.z, gas.slab.top + 2.0 * r_max));
  out.files.emplace_back(out.deck_file, fmt::to_string(d));
  return out;
}

// aggpack's pour (pour_bed) as a deck: the same batches of the same random gas, each lifted to
// the bed's top plus the gap when it comes in, at the same times, then the settling.
LammpsDeck pour_deck(const Scenario& sc, const ParticleStore& bed, const PourStep& step,
                     std::span<const double> radii, std::span<const std::uint8_t> materials,
                     const PouredShapes& shapes) {
  const PourSettings& pour = *sc.pour;
  const QuietCriterion& quiet = sc.dynamics->quiet;
  const double r_max = radii.empty() ? 0.0 : *std::max_element(radii.begin(), radii.end());
  // The time step and skin from the smallest sphere in the bed or still to come (a grain's
  // smallest, its radius at reach 1 times the grain's reach), as aggpack's pour has them.
  double r_min = smallest_radius(bed.radius);
  for (std::size_t k = 0; k < radii.size(); ++k) {
    const RigidBodyShape* shape = shapes.shape(k);
    if (!shape) r_min = std::min(r_min, radii[k]);
    else
      for (const double member : shape->member_radii) r_min = std::min(r_min, radii[k] * member);
  }
  DeckBasis b(sc, r_min);
  const double gap = pour.gap.value_or(2.0 * r_max);
  const PourSchedule schedule = pour_schedule(pour, radii.size());
  LammpsDeck out;
  out.step = fmt::format("pour, part {} of {}", step.layer + 1, step.layers);
  out.deck_file = "pour.in";
  const bool grains = !bed.bodies.empty() ||
                      std::any_of(shapes.of.begin(), shapes.of.end(), [](const RigidBodyShape* s) { return s != nullptr; });
  if (grains) return pour_deck_with_grains(sc, bed, step, radii, materials, shapes, b, gap, std::move(out));
  PourBatches batches = pour_batches(b, bed, step, radii, materials, schedule, gap);
  out.files = std::move(batches.files);

  fmt::memory_buffer d;
  Out o(d);
  deck_comments(o, b, out.step, out.deck_file,
                "the pour as aggpack's: each batch comes once the one before has had the time to fall\n"
                "# its slab's height (or at max_time), then " +
                    quiet_rule(b, fmt::format("{:g} s simulated in all", quiet.max_time)));
  fmt::format_to(o, "# Each pour_batch_<k>.data holds batch k's random gas as aggpack draws it, its heights from the\n"
                    "# bottom of its slab; it is lifted to the bed's top plus the gap ({:.17g} m) as it comes in.\n",
                 gap);
  deck_system(o, b, bed);
  deck_static_walls(o, b);
  deck_motion(o, b, bed);
  fmt::format_to(o, "run 0 post no\n");
  const double poured_at = deck_pour_batches(o, b, batches.fall_after, gap);
  fmt::format_to(o, "run 0 post no\n");
  deck_quiet_loop(o, b, "settle", poured_at + std::max(quiet.sample_interval, quiet.max_time - poured_at));
  deck_end(o);
  out.files.insert(out.files.begin(),
                   {LammpsDeck::kDataFile,
                    lammps_data(bed, sc.container, b.densities,
                                std::max(sc.container.bounds.hi.z, batches.highest + 2.0 * r_max), {})});
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
  deck_grain_comments(o, bed);
  deck_system(o, b, bed);
  fmt::format_to(o, "variable lift equal 0\n");
  if (c.periodic)
    fmt::format_to(o, "region container plane 0 0 {:.17g} 0 0 1 side in move NULL NULL v_lift units box\n",
                   c.bounds.lo.z);
  else if (c.is_cylinder())  // its floor (cap 1) and curved side; the top open
    fmt::format_to(o, "region container cylinder z {:.17g} {:.17g} {:.17g} {:.17g} INF side in open 2 move NULL NULL "
                      "v_lift units box\n",
                   c.axis_x(), c.axis_y(), c.radius(), c.bounds.lo.z);
  else
    fmt::format_to(o, "region container block {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} INF side in open 6 move NULL "
                      "NULL v_lift units box\n",
                   c.bounds.lo.x, c.bounds.hi.x, c.bounds.lo.y, c.bounds.hi.y, c.bounds.lo.z);
  for (const auto& [group, suffix, wall] : wall_groups(b))
    fmt::format_to(o, "fix container{} {} wall/gran/region granular {} region container\n", suffix, group, wall);
  deck_motion(o, b, bed);
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
  add_bed_files(out, b, bed, c.bounds.hi.z);
  out.files.emplace_back(out.deck_file, fmt::to_string(d));
  return out;
}

}  // namespace

LammpsDeck lammps_deck(const Scenario& sc, const ParticleStore& bed, const LammpsStep& step,
                       std::span<const double> pour_radii, std::span<const std::uint8_t> pour_materials,
                       const PouredShapes& pour_shapes) {
  if (!sc.dynamics) throw InputError(fmt::format("{}: a DEM step needs [dynamics]", sc.file.string()));
  return std::visit(Overloaded{[&](const SettleStep& s) { return settle_deck(sc, bed, s.layer); },
                               [&](const PourStep& s) {
                                 return pour_deck(sc, bed, s, pour_radii, pour_materials, pour_shapes);
                               },
                               [&](const TapStep&) { return tap_deck(sc, bed); }},
                    step);
}

void write_lammps_deck(const std::filesystem::path& folder, const LammpsDeck& deck) {
  std::filesystem::create_directories(folder);
  for (const auto& [name, contents] : deck.files) write_file_atomically(folder / name, contents);
}

}  // namespace aggpack
