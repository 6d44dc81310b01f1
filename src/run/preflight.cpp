#include "aggpack/run/preflight.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/dynamics/contact_law_registry.hpp"
#include "aggpack/core/overloaded.hpp"
#include "aggpack/io/dem_setup.hpp"
#include "aggpack/io/particle_file.hpp"
#include "aggpack/run/analyze.hpp"
#include "aggpack/run/protocol.hpp"
#include "aggpack/run/run_grains.hpp"  // and generate_sizes.hpp
#include "aggpack/spatial/multilevel_grid.hpp"

namespace aggpack {

namespace {
namespace fs = std::filesystem;

// Estimated bytes per particle of a whole run, outputs included (BENCHMARKS.md: 950 B per
// sphere for a settled 3x10^5 bed, about 130 B per sphere for deposition alone, plus the
// particle store and the text of particles.csv and particles.vtp).
constexpr double kBytesPerParticleDem = 1200.0;
constexpr double kBytesPerParticleDeposition = 450.0;
// A grain's body (pose, momenta, inertia, forces, its members' range) and its template's row.
constexpr double kBytesPerGrain = 400.0;

constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;

// The most slices or shells of a profile the average sphere may reach (4 or 5 at the default
// thickness d_max / 4): each is a sphere-box volume at every analysis.
constexpr double kMaxProfileBinsPerSphere = 100.0;

// What a run keeps until it ends beyond its bed: a copy of the bed's arrays (ParticleStore) for
// each snapshot step, and for each analysis its profiles, a bin's position and solid fraction
// as doubles, as JSON values and as the text of summary.json.
constexpr double kBytesPerSnapshotParticle = 3 * sizeof(Vec3) + 2 * sizeof(double) + sizeof(std::uint32_t);
constexpr double kBytesPerProfileBin = 128.0;
// And each DEM sample, in the time series and as its row of timeseries.csv.
constexpr double kBytesPerSample = 256.0;
// The most samples in the quiet criterion's window: it scans them all at every sample.
constexpr double kMaxSamplesPerWindow = 1e4;

bool uses_dem(const Scenario& sc) { return sc.dynamics.has_value() || sc.pour.has_value(); }

double bytes_per_particle(const Scenario& sc) {
  return uses_dem(sc) ? kBytesPerParticleDem : kBytesPerParticleDeposition;
}

std::string memory_limit_text(const Scenario& sc) {
  return fmt::format("the memory limit of {:.3g} GiB ({})", memory_limit_bytes(sc.limits) / kGiB,
                     sc.limits.max_memory_gib ? "limits.max_memory_gib" : "80 % of this machine's memory");
}

// An import_lammps step's file against the bed it replaces (`bed`: its radii in the store's
// order; `bed_grain`: each one's grain, kNoBody, or empty without grains): a LAMMPS file, at
// the timestep asked for, of as many spheres with the same radii, inside the container and
// none coincident (a grain's own overlap), as run_step checks when it comes to it.
void check_import_step(const Scenario& sc, const ImportLammpsStep& import, const std::vector<double>& bed,
                       const std::vector<std::uint32_t>& bed_grain, const std::string& where) {
  const auto max_bytes = sc.limits.max_input_bytes();
  PackingFile read = read_packing_file(import.file, 1.0, sc.material.density, max_bytes, import.timestep);
  if (!read.format.starts_with("LAMMPS"))
    throw InputError(fmt::format("{}: import_lammps.file: {} is a {} file; expected a LAMMPS dump or data file", where,
                                 import.file.string(), read.format));
  if (read.particles.size() != bed.size())
    throw InputError(fmt::format("{}: import_lammps.file: {} holds {} spheres, the bed at this step {}; expected the "
                                 "file of this bed",
                                 where, import.file.string(), read.particles.size(), bed.size()));
  std::vector<double> theirs = read.particles.radius, ours = bed;
  std::sort(theirs.begin(), theirs.end());
  std::sort(ours.begin(), ours.end());
  for (std::size_t i = 0; i < ours.size(); ++i)
    if (std::abs(theirs[i] - ours[i]) > 1e-9 * ours[i])
      throw InputError(fmt::format("{}: import_lammps.file: the radii of {} are not the bed's (its {}th smallest is "
                                   "{:.6g} m, the bed's {:.6g} m); expected the file of this bed",
                                   where, import.file.string(), i + 1, theirs[i], ours[i]));
  if (!bed_grain.empty()) read.particles.body = bed_grain;
  check_imported_bed(sc, read.particles, import.file);
}

// A number as a person writes it: 1.8e+308 rather than its 309 digits.
std::string shown(double value) { return fmt::format("{:.4g}", value); }

// The tap's amplitude and duration against the container, the rest and the time step: each
// tap is one half sine of the container (ContainerMotion), so an amplitude beyond the
// container, a tap longer than the rest after it, or a period of a few steps is a slip of a
// key (a frequency in kHz read as Hz), not a protocol.
void check_tapping(const Scenario& sc, double time_step) {
  const TappingSettings& t = *sc.tapping;
  const std::string file = sc.file.string();
  const double g = norm(sc.dynamics->dem.gravity);
  const double omega = 2.0 * std::numbers::pi * t.frequency;
  const double amplitude = t.intensity * g / (omega * omega);
  const double tap_seconds = 0.5 / t.frequency;
  const double height = sc.container.height();
  if (!(amplitude <= 0.5 * height))
    throw InputError(fmt::format(
        "{}: tapping.frequency, tapping.intensity: a tap of intensity {} g at {} Hz moves the container by "
        "{} m (A = intensity g / (2 pi f)^2), more than half its height ({} m); expected a frequency of tens "
        "of hertz (a tap of a few millimetres)",
        file, shown(t.intensity), shown(t.frequency), shown(amplitude), shown(0.5 * height)));
  if (!(tap_seconds <= t.rest_time))
    throw InputError(fmt::format("{}: tapping.frequency, tapping.rest_time: one tap lasts {} s (half a period at "
                                 "{} Hz), longer than the {} s of rest after it; expected a tap shorter than "
                                 "its rest (a higher frequency or a longer rest_time)",
                                 file, shown(tap_seconds), shown(t.frequency), shown(t.rest_time)));
  constexpr double kStepsPerPeriod = 20.0;
  if (!(1.0 / t.frequency >= kStepsPerPeriod * time_step))
    throw InputError(fmt::format("{}: tapping.frequency: a period of {} s at {} Hz is fewer than {:g} DEM time "
                                 "steps of {} s; expected a frequency of at most {} Hz",
                                 file, shown(1.0 / t.frequency), shown(t.frequency), kStepsPerPeriod,
                                 shown(time_step), shown(1.0 / (kStepsPerPeriod * time_step))));
}

// The pour's slab and fall against the grid and the time step: a slab of a batch's spheres at
// a tiny solid fraction is kilometres tall, and a sphere that hits the bed too fast passes
// through it (a Hertz contact of the smallest sphere pressed half its radius deep, or a step
// that moves it a tenth of its radius).
void check_pour(const Scenario& sc, std::span<const double> radii, double solid, double time_step) {
  const PourSettings& pour = *sc.pour;
  const Container& c = sc.container;
  const std::string file = sc.file.string();
  const auto [r_lo, r_hi] = std::minmax_element(radii.begin(), radii.end());
  const double r_min = *r_lo, d_max = 2.0 * *r_hi;
  const double batches = static_cast<double>(std::min<std::size_t>(pour.batches, radii.size()));
  const double slab = solid / batches / (pour.solid_fraction * c.cross_section_area());
  const double gap = pour.gap.value_or(d_max);
  // The highest a sphere starts: the slab on a bed at most as deep as the container.
  const double top = c.height() + gap + slab;
  const double cells = MultilevelGrid::cells_needed(c, radii, std::max(solid / 0.6, 1e-300), top);
  if (!(cells <= sc.limits.max_grid_cells))
    throw InputError(fmt::format(
        "{}: pour.solid_fraction, pour.gap: a batch's insertion slab is {} m tall ({} m^3 of spheres at a solid "
        "fraction of {}, in {} batches) and starts {} m above the bed, so the neighbour grid would need {:.3g} "
        "cells, more than limits.max_grid_cells = {:.3g}; expected a solid fraction of 0.05-0.3, more "
        "pour.batches, or a smaller gap",
        file, shown(slab), shown(solid), shown(pour.solid_fraction), batches, shown(gap), cells,
        sc.limits.max_grid_cells));
  const double g = norm(sc.dynamics->dem.gravity);
  // A pour falls into the container from about its own height: from ten times higher (or as
  // fast as that), the spheres rebound out of the open top and the bed never forms.
  constexpr double kMaxDropHeights = 10.0;
  const double drop = pour.velocity * pour.velocity / (2.0 * g);
  if (pour.release_height && !(*pour.release_height <= kMaxDropHeights * c.height()))
    throw InputError(
        fmt::format("{}: pour.release_height: {} m above the floor, more than {:g} times the container's "
                    "height ({} m): the grains would rebound out of the open container; expected a "
                    "release from about the container's height",
                    file, shown(*pour.release_height), kMaxDropHeights, shown(c.height())));
  if (!(gap <= kMaxDropHeights * c.height()) || !(drop <= kMaxDropHeights * c.height()))
    throw InputError(fmt::format(
        "{}: {}: the spheres {} m above the bed, more than {:g} times the container's height ({} m): they "
        "would rebound out of the open container; expected a pour from about the container's height",
        file, gap > kMaxDropHeights * c.height() ? "pour.gap" : "pour.velocity",
        gap > kMaxDropHeights * c.height()
            ? fmt::format("start {}", shown(gap))
            : fmt::format("start at {} m/s, as fast as a fall from {}", shown(pour.velocity), shown(drop)),
        kMaxDropHeights, shown(c.height())));
  // Each batch waits for the one before to fall its slab: a max_time shorter than that ends
  // the pour as a falling gas (pour_bed refuses it then; here it is known before any work).
  const double fall = (std::sqrt(pour.velocity * pour.velocity + 2.0 * g * slab) - pour.velocity) / g;
  const double max_time = sc.dynamics->quiet.max_time;
  if (!(max_time >= batches * fall))
    throw InputError(fmt::format(
        "{}: dynamics.max_time: {} s is shorter than the pour's {:g} batch{} take to fall their slabs ({} s each, "
        "{} m tall): the run would end with the spheres still in the air; expected a max_time of at least {} s "
        "and the time to settle",
        file, shown(max_time), batches, batches == 1 ? "" : "es", shown(fall), shown(slab), shown(2.0 * batches * fall)));
  // The fastest arrival: from the top of a slab over the bed, or released at the release height
  // and falling to the floor.
  const double fall_height = std::max(gap + slab, pour.release_height.value_or(0.0));
  const double impact = std::sqrt(pour.velocity * pour.velocity + 2.0 * g * fall_height);
  const double overlap = largest_impact_overlap(sc, r_min, impact);
  const double per_step = impact * time_step;
  if (!(overlap <= 0.5 * r_min) || !(per_step <= 0.1 * r_min))
    throw InputError(fmt::format(
        "{}: pour.velocity, pour.gap, pour.release_height, pour.solid_fraction: a sphere poured at {} m/s that falls "
        "up to {} m (the gap and a {} m slab above the bed, or from the release height to the floor) arrives at {} "
        "m/s: the smallest sphere (radius {} m) would {}; expected a slower or lower pour",
        file, shown(pour.velocity), shown(fall_height), shown(slab), shown(impact), shown(r_min),
        overlap > 0.5 * r_min
            ? fmt::format("press {} of its radius into the bed (a Hertz impact at this stiffness), passing through",
                          shown(overlap / r_min))
            : fmt::format("move {} of its radius in one time step of {} s, through the spheres it meets",
                          shown(per_step / r_min), shown(time_step))));
}

// The quiet criterion scans the samples of its window at every sample (at most one a DEM
// step): a sample interval far below the window makes that scan the run's work.
void check_sampling(const Scenario& sc, double time_step) {
  const QuietCriterion& q = sc.dynamics->quiet;
  const double every = std::max(q.sample_interval, time_step);
  const double window = std::min(q.window, q.max_time);
  if (!(window / every <= kMaxSamplesPerWindow))
    throw InputError(fmt::format(
        "{}: dynamics.sample_interval: samples every {} s (sample_interval = {} s, at most one a time step) put "
        "{:.3g} samples in the quiet window of {} s, each scanned at every sample; expected at most {:g}: a "
        "sample_interval of at least {} s or a shorter quiet_window",
        sc.file.string(), shown(every), shown(q.sample_interval), window / every, shown(window),
        kMaxSamplesPerWindow, shown(window / kMaxSamplesPerWindow)));
}

// The most samples a DEM step of the protocol takes: one a sample interval (at most one a time
// step) up to max_time for a settle or a pour, and after each tap and through its rest.
double dem_samples(const Scenario& sc, const Step& step, double time_step) {
  const double every = std::max(sc.dynamics->quiet.sample_interval, time_step);
  const double up_to_max_time = sc.dynamics->quiet.max_time / every + 1.0;
  return std::visit(Overloaded{[&](const SettleStep&) { return up_to_max_time; },
                               [&](const PourStep&) { return up_to_max_time; },
                               [&](const TapStep&) {
                                 const TappingSettings& t = *sc.tapping;
                                 return static_cast<double>(t.taps) * (t.rest_time / every + 2.0);
                               },
                               [&](const auto&) { return compaction_samples(sc, step, every); }},
                    step.kind);
}

// Some particles, and a generated bed within limits.max_particles (a file's: by its memory, below).
void check_particle_count(const Scenario& sc, std::span<const double> radii) {
  const std::string file = sc.file.string();
  if (radii.empty()) throw InputError(fmt::format("{}: particles: the scenario makes no particles", file));
  if (!sc.particles.file && !(sc.limits.max_particles >= static_cast<double>(radii.size())))
    throw InputError(fmt::format("{}: particles: {} particles, more than limits.max_particles = {:.3g}", file,
                                 radii.size(), sc.limits.max_particles));
}

// A bed placed here (deposition, pour): a container taller than d_max; fill heights of at least d_max.
void check_heights(const Scenario& sc, double d_max) {
  const std::string file = sc.file.string();
  const Container& c = sc.container;
  if ((sc.deposition || sc.pour) && d_max >= c.height())
    throw InputError(fmt::format("{}: particles: the largest diameter ({:.6g} m) is not below container.height "
                                 "({:.6g} m); expected a container taller than its largest particle",
                                 file, d_max, c.height()));
  if (sc.deposition && sc.deposition->fill_height < d_max)
    throw InputError(fmt::format("{}: deposition.fill_height: {:.6g} m is below the largest diameter ({:.6g} m); "
                                 "expected at least one diameter (the bed would hold no particle)",
                                 file, sc.deposition->fill_height, d_max));
  if (sc.particles.graded && sc.particles.graded->fill_height && *sc.particles.graded->fill_height < d_max)
    throw InputError(fmt::format("{}: particles.fill_height: {:.6g} m is below the largest diameter ({:.6g} m); "
                                 "expected at least one diameter", file, *sc.particles.graded->fill_height, d_max));
}

// The contact search's reach, in the smallest sphere's diameters: the cells it scans grow as its cube.
void check_contact_reach(const Scenario& sc, double r_min, double d_max) {
  const double reach = contact_reach_diameters(sc.analysis.contact_tolerance, r_min, 0.5 * d_max);
  if (!(reach <= kMaxContactReachDiameters))
    throw InputError(fmt::format(
        "{}: analysis.contact_tolerance: {} makes the smallest sphere (radius {} m) look for contacts {} of its "
        "diameters away, beside spheres up to {} m across: the neighbour search would scan some {:.3g} cells for "
        "each; expected at most {:g} diameters, a contact_tolerance of at most {}",
        sc.file.string(), shown(sc.analysis.contact_tolerance), shown(r_min), shown(reach), shown(d_max),
        std::pow(2.0 * reach + 3.0, 3.0), kMaxContactReachDiameters,
        shown(sc.analysis.contact_tolerance * kMaxContactReachDiameters / reach)));
}

// The virtual cubes of the analysis: not too many, and each able to fit in the container.
void check_box_sides(const Scenario& sc, double d_max) {
  const std::string file = sc.file.string();
  const Container& c = sc.container;
  // A virtual cube keeps one d_max from the walls: a side beyond that can never be placed.
  const double horizontal = c.widest_centred_square(d_max);
  const double vertical = c.height() - 2.0 * d_max;
  if (sc.analysis.box_sides.size() > kMaxAnalysisBoxes)
    throw InputError(fmt::format("{}: analysis.box_sides: {} sides; expected at most {} (each cube is a pass over every "
                                 "sphere, at each analysis and each density check of the DEM)",
                                 file, sc.analysis.box_sides.size(), kMaxAnalysisBoxes));
  for (const double side : sc.analysis.box_sides)
    if (side > std::min(horizontal, vertical))
      throw InputError(fmt::format(
          "{}: analysis.box_sides: a cube of side {:.6g} m cannot fit in the container ({}) with one d_max ({:.6g} m) "
          "kept from the walls, the floor and the surface; the largest admissible side is {:.6g} m",
          file, side,
          c.is_cylinder() ? fmt::format("a cylinder {:.6g} m across, {:.6g} m high", c.length_x(), c.height())
                          : fmt::format("{:.6g} x {:.6g} x {:.6g} m", c.length_x(), c.length_y(), c.height()),
          d_max, std::max(0.0, std::min(horizontal, vertical))));
}

// The time step against the contact law's stability limit.
void check_time_step(const Scenario& sc, double r_min) {
  const DynamicsStage& d = *sc.dynamics;
  const double scale = stable_time_scale(sc, r_min);
  const double step = d.time_step.step(scale);
  if (!d.allow_unstable_time_step && step > TimeStepRule::kStableFraction * scale)
    throw InputError(fmt::format(
        "{}: dynamics.{}: the time step {:.4g} s is {:.3g} times the Rayleigh time of the smallest sphere "
        "({:.4g} s, radius {:.4g} m); Hertz contacts are resolved only up to {:g} of it (at 0.75 a bed already "
        "settles 5 % too dense); expected at most {:.4g} s, or set dynamics.allow_unstable_time_step = "
        "true to run it anyway (noted in the output)",
        sc.file.string(), d.time_step.fixed ? "time_step" : "time_step_safety", step, step / scale, scale, r_min,
        TimeStepRule::kStableFraction, TimeStepRule::kStableFraction * scale));
}

// The neighbour grid, sized as the stages size it.
void check_grid_cells(const Scenario& sc, std::span<const double> radii, double solid, double r_min) {
  const Container& c = sc.container;
  const double cells = MultilevelGrid::cells_needed(c, radii, std::max(solid / 0.6, 1e-300), c.height());
  if (!(cells <= sc.limits.max_grid_cells))
    throw InputError(fmt::format("{}: container: the neighbour grid would need {:.3g} cells (a {:.4g} x {:.4g} x "
                                 "{:.4g} m container, spheres from {:.4g} m in radius), more than "
                                 "limits.max_grid_cells = {:.3g}; expected a container nearer the size of its "
                                 "bed, or raise the limit (at most 2^31)",
                                 sc.file.string(), cells, c.length_x(), c.length_y(), c.height(), r_min,
                                 sc.limits.max_grid_cells));
}

// The profiles' bin thicknesses (default d_max / 4), and the slices and shells across the container.
struct ProfileBins { double slice, shell, slices, shells; };

ProfileBins profile_bins(const Scenario& sc, double d_max) {
  const Container& c = sc.container;
  const double slice = sc.analysis.slice_thickness.value_or(0.25 * d_max);
  const double shell = sc.analysis.shell_thickness.value_or(0.25 * d_max);
  return {slice, shell, c.height() / slice, 0.5 * std::min(c.length_x(), c.length_y()) / shell};
}

// Their count, and the sphere-bin volumes each profile sums.
void check_profiles(const Scenario& sc, std::span<const double> radii, const ProfileBins& p) {
  const double bins = std::max(p.slices, p.shells);
  if (!(bins <= sc.limits.max_profile_bins))
    throw InputError(fmt::format("{}: analysis.{}: the profiles would need {:.3g} bins across the container, more "
                                 "than limits.max_profile_bins = {:.3g}; expected a thicker slice (default "
                                 "d_max / 4)",
                                 sc.file.string(), p.slices >= p.shells ? "slice_thickness" : "shell_thickness",
                                 bins, sc.limits.max_profile_bins));
  // Each sphere adds its volume to every slice (shell) it reaches: the bins above bound the
  // profiles' memory, not this work, which grows as the spheres' count times d / thickness.
  double diameters = 0.0;
  for (const double r : radii) diameters += 2.0 * r;
  const double d_mean = diameters / static_cast<double>(radii.size());
  const bool by_slice = p.slice <= p.shell;
  const double thinnest = std::min(p.slice, p.shell);
  if (!(d_mean / thinnest <= kMaxProfileBinsPerSphere))
    throw InputError(fmt::format(
        "{}: analysis.{}: {} m cuts each sphere (mean diameter {} m) into {} {} on average, {:.3g} sphere-{} "
        "volumes for every profile; expected at least d_mean / {:g} = {} m (default d_max / 4)",
        sc.file.string(), by_slice ? "slice_thickness" : "shell_thickness", shown(thinnest), shown(d_mean),
        shown(d_mean / thinnest), by_slice ? "slices" : "shells", diameters / thinnest, by_slice ? "slice" : "shell",
        kMaxProfileBinsPerSphere, shown(d_mean / kMaxProfileBinsPerSphere)));
}

// The memory of the bed (a particle file's is known only now) and of what the run keeps until it
// ends: a copy of the bed for each snapshot step, the profiles of each analysis, the DEM's samples.
void check_run_memory(const Scenario& sc, std::span<const double> radii, const ProfileBins& p, double time_step) {
  const std::string file = sc.file.string();
  const double n = static_cast<double>(radii.size());
  const double bed_bytes = n * bytes_per_particle(sc);
  const double limit = memory_limit_bytes(sc.limits);
  if (bed_bytes > limit)
    throw InputError(fmt::format("{}: {}: {} particles need an estimated {:.3g} GiB ({:.0f} bytes each{}), more than "
                                 "{}; expected a smaller bed, or a larger limits.max_memory_gib",
                                 file, sc.particles.file ? "particles.from" : "particles", radii.size(),
                                 bed_bytes / kGiB, bytes_per_particle(sc), uses_dem(sc) ? " with the DEM" : "",
                                 memory_limit_text(sc)));
  std::size_t snapshots = 0, analyses = 1;  // and the run's final analysis
  double samples = 0.0;                     // of the DEM steps, at most
  const Protocol protocol = scenario_protocol(sc);
  for (const Step& step : protocol.steps) {
    snapshots += std::holds_alternative<SnapshotStep>(step.kind) ? 1 : 0;
    analyses += std::holds_alternative<AnalyseStep>(step.kind) ? 1 : 0;
    if (sc.dynamics) samples += dem_samples(sc, step, time_step);
  }
  const double kept = static_cast<double>(snapshots) * n * kBytesPerSnapshotParticle +
                      static_cast<double>(analyses) * (p.slices + p.shells) * kBytesPerProfileBin;
  if (bed_bytes + kept > limit)
    throw InputError(fmt::format(
        "{}: protocol: {} snapshot step{} (a copy of the {} particles each) and {} analys{} (profiles of {:.3g} bins "
        "each) keep an estimated {:.3g} GiB until the run ends, with the bed's {:.3g} GiB more than {}; expected fewer "
        "snapshot or analyse steps, a thicker analysis.slice_thickness or shell_thickness, or a larger "
        "limits.max_memory_gib",
        file, snapshots, snapshots == 1 ? "" : "s", radii.size(), analyses, analyses == 1 ? "is" : "es",
        p.slices + p.shells, kept / kGiB, bed_bytes / kGiB, memory_limit_text(sc)));
  if (sc.dynamics && bed_bytes + kept + samples * kBytesPerSample > limit) {
    const QuietCriterion& q = sc.dynamics->quiet;
    throw InputError(fmt::format(
        "{}: dynamics.sample_interval: the DEM steps would keep up to {:.3g} samples for timeseries.csv (a sample "
        "every {} s, up to max_time = {} s for each settle or pour step), an estimated {:.3g} GiB, with the bed's "
        "{:.3g} GiB more than {}; expected a longer sample_interval or a shorter max_time",
        file, samples, shown(std::max(q.sample_interval, time_step)), shown(q.max_time),
        samples * kBytesPerSample / kGiB, bed_bytes / kGiB, memory_limit_text(sc)));
  }
}

// A generated bed can be no deeper than its solid volume at a loose solid fraction of 0.5:
// if even that leaves no room for a virtual cube, the run would fail after all its work.
void check_room_for_cubes(const Scenario& sc, std::span<const double> radii, double solid, double d_max) {
  const Container& c = sc.container;
  double deepest = std::min(c.height(), solid / (0.5 * c.cross_section_area()));
  if (sc.deposition) deepest = std::min(deepest, sc.deposition->fill_height);
  const double room = deepest - 2.0 * d_max;
  const double needed = sc.analysis.box_sides.empty()
                            ? 0.0
                            : *std::min_element(sc.analysis.box_sides.begin(), sc.analysis.box_sides.end());
  if (room <= needed)
    throw InputError(fmt::format(
        "{}: particles: the bed will be at most {:.4g} m deep ({} particles, {:.4g} m^3 of solid at a solid "
        "fraction of 0.5), which leaves no room for a virtual cube{} one d_max ({:.4g} m) from the floor and the "
        "free surface; expected more particles (count, solid_volume or fill_height) or smaller analysis.box_sides",
        sc.file.string(), deepest, radii.size(), solid,
        needed > 0.0 ? fmt::format(" of side {:.4g} m", needed) : std::string(), d_max));
}

}  // namespace

void check_thread_count(int threads, OptionStyle named) {
  if (threads < 0 || threads > kMaxThreads)
    throw InputError(fmt::format("{}: expected 0 (all cores) or a count from 1 to {}",
                                 option_given("--threads", std::to_string(threads), named), kMaxThreads));
}

void check_frames(const Scenario& sc) {
  if (!sc.output.frame_interval) return;
  const double interval = *sc.output.frame_interval;
  const std::string where = fmt::format("{}: output.frame_interval", sc.file.string());
  if (!sc.dynamics)
    throw InputError(fmt::format("{}: frames are taken at the DEM's samples, and the scenario has no [dynamics] "
                                 "(no settle, pour or tap step); remove the key or add the DEM",
                                 where));
  if (sc.dynamics->engine != DemEngine::Aggpack)
    throw InputError(fmt::format("{}: frames are taken by aggpack's own DEM, not with dynamics.engine = \"lammps\"; "
                                 "remove the key (LAMMPS's own dump commands can write frames)",
                                 where));
  if (!sc.output.vtp)
    throw InputError(fmt::format("{}: frames are VTP files, and output.formats has no \"vtp\"; add it or remove the "
                                 "key",
                                 where));
  const double sample_interval = sc.dynamics->quiet.sample_interval;
  if (!(interval >= sample_interval))
    throw InputError(fmt::format("{}: {} s is shorter than dynamics.sample_interval ({} s), and frames are taken at "
                                 "the samples; expected at least {} s",
                                 where, shown(interval), shown(sample_interval), shown(sample_interval)));
  // The most simulated time the DEM steps can take: the frames at most one a multiple of the
  // interval over it, and the first.
  double budget = 0.0;
  for (const Step& step : scenario_protocol(sc).steps)
    budget += std::visit(Overloaded{[&](const SettleStep&) { return sc.dynamics->quiet.max_time; },
                                    [&](const PourStep&) { return sc.dynamics->quiet.max_time; },
                                    [&](const TapStep&) {
                                      const TappingSettings& t = *sc.tapping;
                                      return static_cast<double>(t.taps) * (0.5 / t.frequency + t.rest_time);
                                    },
                                    [&](const auto&) { return compaction_time(sc, step); }},
                         step.kind);
  const double frames = std::floor(budget / interval) + 1.0;
  if (!(frames <= kMaxFrames))
    throw InputError(fmt::format("{}: up to {:.4g} frames of {} s over the DEM's {} s at most (max_time for each "
                                 "settle or pour step, every tap and rest of each tap step), more than {:g}; expected "
                                 "a frame_interval of at least {} s",
                                 where, frames, shown(interval), shown(budget), kMaxFrames,
                                 shown(budget / (kMaxFrames - 1.0))));
}

// The particles of a generated bed (about so many before they are drawn, exactly after) within
// limits.max_particles and the memory limit, a grain counted as its member spheres (each a
// particle of the DEM) with its body's row and its template.
void check_amount(const Scenario& sc, const ExpectedAmount& amount, bool drawn) {
  const std::string where = fmt::format("{}: particles", sc.file.string());
  const std::string about = drawn ? "" : "about ";
  const std::string members =
      amount.grains > 0.0 ? fmt::format(" ({:.3g} spheres: the grains' members counted)", amount.spheres) : "";
  if (!(amount.spheres <= sc.limits.max_particles))
    throw InputError(fmt::format("{}: this amount needs {}{:.3g} particles{}, more than limits.max_particles = "
                                 "{:.3g}; generate less (count, solid_volume or fill_height), raise the fine "
                                 "cut-off d_min, give grains fewer spheres, or raise the limit",
                                 where, about, amount.particles, members, sc.limits.max_particles));
  double templates = 0.0;  // their spheres, at most
  for (const auto& shape : sc.particles.component_shape)
    if (shape) templates += static_cast<double>(shape->templates * shape->spheres);
  const double bytes =
      amount.spheres * bytes_per_particle(sc) + (amount.grains + templates) * kBytesPerGrain;
  if (bytes > memory_limit_bytes(sc.limits))
    throw InputError(fmt::format("{}: {}{:.3g} particles{} need an estimated {:.3g} GiB ({:.0f} bytes a sphere{}{}), "
                                 "more than {}; generate less, or raise limits.max_memory_gib",
                                 where, about, amount.particles, members, bytes / kGiB, bytes_per_particle(sc),
                                 uses_dem(sc) ? " with the DEM" : "",
                                 amount.grains > 0.0 ? fmt::format(", {:.0f} a grain's body", kBytesPerGrain) : "",
                                 memory_limit_text(sc)));
}

// The checks run in this order, the cheapest and most basic first: the first that fails is
// the message the user sees.
void check_sizes(const Scenario& sc, std::span<const double> radii, std::optional<double> solid_volume) {
  check_particle_count(sc, radii);
  const auto [r_lo, r_hi] = std::minmax_element(radii.begin(), radii.end());
  const double d_max = 2.0 * *r_hi, r_min = *r_lo;
  check_heights(sc, d_max);
  check_contact_reach(sc, r_min, d_max);
  check_box_sides(sc, d_max);
  if (sc.dynamics) check_time_step(sc, r_min);
  double solid = 0.0;
  for (const double r : radii) solid += 4.0 / 3.0 * std::numbers::pi * r * r * r;
  const double own_solid = solid_volume.value_or(solid);  // the bed's depth: grains fill less than their reach
  const double time_step = sc.dynamics ? sc.dynamics->time_step.step(stable_time_scale(sc, r_min)) : 0.0;
  if (sc.dynamics) {
    if (sc.tapping) check_tapping(sc, time_step);
    check_compaction(sc, time_step, r_min);
    if (sc.pour) check_pour(sc, radii, solid, time_step);
    check_sampling(sc, time_step);
  }
  check_grid_cells(sc, radii, solid, r_min);
  const ProfileBins bins = profile_bins(sc, d_max);
  check_profiles(sc, radii, bins);
  check_run_memory(sc, radii, bins, time_step);
  if (sc.deposition || sc.pour) check_room_for_cubes(sc, radii, own_solid, d_max);
}

// Particles from a file must lie in the container (a cylinder's: inside its circle); periodic
// sides wrap x and y. A bed
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
    auto [overlap, where] = *std::max_element(reach.begin(), container.periodic ? reach.begin() + 2 : reach.end(),
                                              [](const auto& a, const auto& c) { return a.first < c.first; });
    if (container.is_cylinder()) {  // its one wall in place of the box's four
      Vec3 outward;
      const double floor_or_top = std::max(reach[0].first, reach[1].first);
      const double wall = r - container.plane_distance(Container::kCylinderWall, p, outward);
      overlap = std::max(floor_or_top, wall);
      where = wall >= floor_or_top ? "the cylinder's wall" : reach[0].first >= reach[1].first ? reach[0].second
                                                                                             : reach[1].second;
    }
    if (overlap > tolerance * r)
      throw InputError(fmt::format(
          "{}: particle {} (data row {}) at ({:.6g}, {:.6g}, {:.6g}) m, radius {:.6g} m, reaches {:.3g} m "
          "({:.3g} r) beyond {} of the container {}; particles.boundary_overlap_tolerance accepts up to {:g} r "
          "(a contact overlap), not an intrusion",
          file.string(), i, i + 1, p.x, p.y, p.z, r, overlap, overlap / r, where, box_text(b), tolerance));
    largest = std::max(largest, overlap / r);  // a sphere clear of every boundary counts as 0
  }
  return largest;
}

void check_imported_bed(const Scenario& sc, ParticleStore& bed, const std::filesystem::path& file) {
  (void)fit_into_container(bed, sc.container, sc.particles.boundary_overlap_tolerance, file);
  (void)check_particle_overlaps(bed, sc.container, sc.particles.overlap_tolerance, sc.particles.soft_contacts,
                                file.string(), sc.limits.max_grid_cells);
}

void check_protocol_beds(const Scenario& sc, std::span<const double> bed_radii, std::span<const double> to_place,
                         const RunGrains* grains) {
  const std::string file = sc.file.string();
  const Protocol protocol = scenario_protocol(sc);
  std::vector<double> bed(bed_radii.begin(), bed_radii.end());
  std::vector<std::uint32_t> bed_grain(grains && !grains->empty() ? bed.size() : 0, kNoBody);  // with grains
  const std::size_t n = to_place.size();
  for (std::size_t k = 0; k < protocol.steps.size(); ++k) {
    const Step& step = protocol.steps[k];
    const std::string where = fmt::format("{}: protocol step {} ({})", file, k + 1, step.stage);
    const auto place = [&](std::uint32_t layer, std::uint32_t layers) {
      const std::size_t begin = n * layer / layers, end = n * (layer + 1) / layers;
      if (begin == end)
        throw InputError(fmt::format("{}: part {} of {} holds no sphere ({} spheres in {} parts); expected at most {} "
                                     "parts",
                                     where, layer + 1, layers, n, layers, n));
      if (grains && !grains->empty()) grains->append_spheres(to_place.subspan(begin, end - begin), begin, bed, bed_grain);
      else bed.insert(bed.end(), to_place.begin() + static_cast<std::ptrdiff_t>(begin),
                      to_place.begin() + static_cast<std::ptrdiff_t>(end));
    };
    std::visit(Overloaded{[&](const DepositStep& d) { place(d.layer, d.layers); },
                          [&](const PourStep& p) { place(p.layer, p.layers); },
                          [&](const ImportLammpsStep& import) { check_import_step(sc, import, bed, bed_grain, where); },
                          [&](const auto&) {
                            if (bed.empty())
                              throw InputError(fmt::format("{}: it comes before any step places the spheres: the bed "
                                                           "is empty; expected a deposit or pour step first",
                                                           where));
                          }},
               step.kind);
  }
}

}  // namespace aggpack
