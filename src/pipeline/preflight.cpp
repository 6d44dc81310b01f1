#include "aggpack/pipeline/preflight.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>

#include <fmt/format.h>
#include <unistd.h>

#include "aggpack/core/error.hpp"
#include "aggpack/dynamics/contact_law_registry.hpp"
#include "aggpack/pipeline/generate_sizes.hpp"
#include "aggpack/spatial/multilevel_grid.hpp"

namespace aggpack {

namespace {
namespace fs = std::filesystem;

// Estimated bytes per particle of a whole run, outputs included (BENCHMARKS.md: 950 B per
// sphere for a settled 3x10^5 bed, about 130 B per sphere for deposition alone, plus the
// particle store and the text of particles.csv and particles.vtp).
constexpr double kBytesPerParticleDem = 1200.0;
constexpr double kBytesPerParticleDeposition = 450.0;

constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;

bool uses_dem(const Scenario& sc) { return sc.dynamics.has_value() || sc.pour.has_value(); }
}  // namespace

void check_thread_count(int threads) {
  if (threads < 0 || threads > kMaxThreads)
    throw InputError(fmt::format("--threads {}: expected 0 (all cores) or a count from 1 to {}", threads,
                                 kMaxThreads));
}

void check_amount(const Scenario& sc) {
  const double count = sc.particles.file ? 0.0 : expected_particle_count(sc.particles);
  const std::string where = fmt::format("{}: particles", sc.file.string());
  if (!(count <= sc.limits.max_particles))
    throw InputError(fmt::format("{}: this amount needs about {:.3g} particles, more than limits.max_particles = "
                                 "{:.3g}; generate less (count, solid_volume or fill_height), raise the fine "
                                 "cut-off d_min, or raise the limit",
                                 where, count, sc.limits.max_particles));
  const double bytes = count * (uses_dem(sc) ? kBytesPerParticleDem : kBytesPerParticleDeposition);
  const double limit = memory_limit_bytes(sc.limits);
  if (bytes > limit)
    throw InputError(fmt::format("{}: about {:.3g} particles need an estimated {:.3g} GiB ({:.0f} bytes each{}), "
                                 "more than the memory limit of {:.3g} GiB ({}); generate less, or raise "
                                 "limits.max_memory_gib",
                                 where, count, bytes / kGiB,
                                 uses_dem(sc) ? kBytesPerParticleDem : kBytesPerParticleDeposition,
                                 uses_dem(sc) ? " with the DEM" : "", limit / kGiB,
                                 sc.limits.max_memory_gib ? "limits.max_memory_gib" : "80 % of this machine's memory"));
}

void check_sizes(const Scenario& sc, std::span<const double> radii) {
  const std::string file = sc.file.string();
  if (radii.empty()) throw InputError(fmt::format("{}: particles: the scenario makes no particles", file));
  if (!sc.particles.file && !(sc.limits.max_particles >= static_cast<double>(radii.size())))
    throw InputError(fmt::format("{}: particles: {} particles, more than limits.max_particles = {:.3g}", file,
                                 radii.size(), sc.limits.max_particles));
  const auto [r_lo, r_hi] = std::minmax_element(radii.begin(), radii.end());
  const double d_max = 2.0 * *r_hi, r_min = *r_lo;
  const Container& c = sc.container;
  const bool placed_here = sc.deposition || sc.pour;
  if (placed_here && d_max >= c.height())
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
  // A virtual cube keeps one d_max from the walls: a side beyond that can never be placed.
  const double width = std::min(c.length_x(), c.length_y());
  const double horizontal = c.periodic ? width : width - 2.0 * d_max;
  const double vertical = c.height() - 2.0 * d_max;
  for (const double side : sc.analysis.box_sides)
    if (side > std::min(horizontal, vertical))
      throw InputError(fmt::format(
          "{}: analysis.box_sides: a cube of side {:.6g} m cannot fit in the container ({:.6g} x {:.6g} x {:.6g} m) "
          "with one d_max ({:.6g} m) kept from the walls, the floor and the surface; the largest admissible side "
          "is {:.6g} m",
          file, side, c.length_x(), c.length_y(), c.height(), d_max, std::max(0.0, std::min(horizontal, vertical))));

  // The time step against the contact law's stability limit.
  if (sc.dynamics) {
    const DynamicsStage& d = *sc.dynamics;
    const double scale = stable_time_scale(sc.material.contact, r_min, sc.material.density);
    const double step = d.time_step.step(scale);
    if (!d.allow_unstable_time_step && step > TimeStepRule::kStableFraction * scale)
      throw InputError(fmt::format(
          "{}: dynamics.{}: the time step {:.4g} s is {:.3g} times the Rayleigh time of the smallest sphere "
          "({:.4g} s, radius {:.4g} m); Hertz contacts are resolved only up to {:g} of it (at 0.75 a bed already "
          "settles 5 % too dense); expected at most {:.4g} s, or set dynamics.allow_unstable_time_step = "
          "true to run it anyway (noted in the output)",
          file, d.time_step.fixed ? "time_step" : "time_step_safety", step, step / scale, scale, r_min,
          TimeStepRule::kStableFraction, TimeStepRule::kStableFraction * scale));
  }

  // The neighbour grid, sized as the stages size it.
  double solid = 0.0;
  for (const double r : radii) solid += 4.0 / 3.0 * std::numbers::pi * r * r * r;
  const double cells = MultilevelGrid::cells_needed(c, radii, std::max(solid / 0.6, 1e-300), c.height());
  if (!(cells <= sc.limits.max_grid_cells))
    throw InputError(fmt::format("{}: container: the neighbour grid would need {:.3g} cells (a {:.4g} x {:.4g} x "
                                 "{:.4g} m container, spheres from {:.4g} m in radius), more than "
                                 "limits.max_grid_cells = {:.3g}; expected a container nearer the size of its "
                                 "bed, or raise the limit (at most 2^31)",
                                 file, cells, c.length_x(), c.length_y(), c.height(), r_min,
                                 sc.limits.max_grid_cells));
  const double slice = sc.analysis.slice_thickness.value_or(0.25 * d_max);
  const double shell = sc.analysis.shell_thickness.value_or(0.25 * d_max);
  const double bins = std::max(c.height() / slice, 0.5 * width / shell);
  if (!(bins <= sc.limits.max_profile_bins))
    throw InputError(fmt::format("{}: analysis.{}: the profiles would need {:.3g} bins across the container, more "
                                 "than limits.max_profile_bins = {:.3g}; expected a thicker slice (default "
                                 "d_max / 4)",
                                 file, c.height() / slice >= 0.5 * width / shell ? "slice_thickness" : "shell_thickness",
                                 bins, sc.limits.max_profile_bins));

  // A generated bed can be no deeper than its solid volume at a loose solid fraction of 0.5:
  // if even that leaves no room for a virtual cube, the run would fail after all its work.
  if (placed_here) {
    double deepest = std::min(c.height(), solid / (0.5 * c.length_x() * c.length_y()));
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
          file, deepest, radii.size(), solid,
          needed > 0.0 ? fmt::format(" of side {:.4g} m", needed) : std::string(), d_max));
  }
}

void check_output_directory(const fs::path& directory, bool create) {
  const std::string shown = directory.string();
  if (shown.empty()) throw InputError("output.directory: the output folder is an empty path; expected a folder name");
  std::error_code ec;
  // The nearest part of the path that exists must be a directory we may write into.
  fs::path existing = directory;
  while (!existing.empty() && !fs::exists(existing, ec)) existing = existing.parent_path();
  if (existing.empty()) existing = ".";
  if (!fs::is_directory(existing, ec))
    throw InputError(fmt::format("{}: cannot make the output folder: {} is a file, not a folder; expected a folder "
                                 "path (--out or output.directory)",
                                 shown, existing.string()));
  if (::access(existing.c_str(), W_OK | X_OK) != 0)
    throw InputError(fmt::format("{}: cannot write the output folder: {} is not writable; expected a folder you "
                                 "may write (--out or output.directory)",
                                 shown, existing.string()));
  if (!create) return;
  fs::create_directories(directory, ec);
  if (ec)
    throw InputError(fmt::format("{}: cannot make the output folder: {}", shown, ec.message()));
  const fs::path probe = directory / fmt::format(".aggpack-write-probe.{}", ::getpid());
  bool written = false;
  {
    std::ofstream out(probe);
    out << "probe\n";
    written = static_cast<bool>(out.flush());
  }
  fs::remove(probe, ec);
  if (!written) throw InputError(fmt::format("{}: cannot write into the output folder", shown));
  // Temporary files of an earlier run into this folder that was killed mid-write.
  for (const auto& entry : fs::directory_iterator(directory, ec))
    if (entry.path().filename().string().find(".tmp.") != std::string::npos && entry.is_regular_file(ec))
      fs::remove(entry.path(), ec);
}

}  // namespace aggpack
