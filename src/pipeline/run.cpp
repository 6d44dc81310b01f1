#include "aggpack/pipeline/run.hpp"

#include <chrono>
#include <cmath>
#include <fmt/format.h>
#include <fmt/ostream.h>
#include <omp.h>

#include "aggpack/core/error.hpp"
#include "aggpack/core/version.hpp"
#include "aggpack/io/atomic_file.hpp"
#include "aggpack/io/particle_file.hpp"
#include "aggpack/io/vtk.hpp"
#include "aggpack/pipeline/analyze.hpp"

namespace aggpack {

namespace {
using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Particles from a file must lie in the container; periodic sides wrap x and y.
void fit_into_container(ParticleStore& particles, const Container& container, const std::filesystem::path& file) {
  const Box& b = container.bounds;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    Vec3& p = particles.position[i];
    const double r = particles.radius[i];
    const double slack = 1e-9 * r;
    if (container.periodic) {
      p.x = b.lo.x + std::fmod(std::fmod(p.x - b.lo.x, container.length_x()) + container.length_x(), container.length_x());
      p.y = b.lo.y + std::fmod(std::fmod(p.y - b.lo.y, container.length_y()) + container.length_y(), container.length_y());
    }
    const bool outside_walls = !container.periodic && (p.x - r < b.lo.x - slack || p.x + r > b.hi.x + slack ||
                                                       p.y - r < b.lo.y - slack || p.y + r > b.hi.y + slack);
    if (outside_walls || p.z - r < b.lo.z - slack || p.z + r > b.hi.z + slack)
      throw InputError(fmt::format(
          "{}: particle {} (data row {}) at ({:.6g}, {:.6g}, {:.6g}) m, radius {:.6g} m, is not inside the "
          "container [{:.6g}, {:.6g}] x [{:.6g}, {:.6g}] x [{:.6g}, {:.6g}] m",
          file.string(), i, i + 1, p.x, p.y, p.z, r, b.lo.x, b.hi.x, b.lo.y, b.hi.y, b.lo.z, b.hi.z));
  }
}

ParticleStore initial_particles(const Scenario& sc) {
  // load_scenario refuses generated sizes until a stage can place them.
  if (!sc.particles.file) throw InputError(fmt::format("{}: particles: no particle positions", sc.file.string()));
  ParticleStore particles = read_particle_file(*sc.particles.file, sc.particles.file_length_unit, sc.material.density);
  fit_into_container(particles, sc.container, *sc.particles.file);
  return particles;
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
nlohmann::json modelling_notes(const Scenario& sc, bool auto_box) {
  nlohmann::json notes = nlohmann::json::array();
  if (sc.particles.file)
    notes.push_back("particle positions were read from " + sc.particles.file->string() +
                    "; no aggpack stage moved them");
  if (sc.container.periodic)
    notes.push_back("periodic sides: x and y wrap, so the packing has no side-wall effect");
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
}  // namespace

Scenario check_scenario(const std::filesystem::path& scenario_file, const ScenarioOverrides& overrides) {
  Scenario sc = load_scenario(scenario_file, overrides);
  const ParticleStore particles = initial_particles(sc);
  analyze_packing(particles, sc.container, analysis_request(sc));  // box placement errors surface here
  return sc;
}

RunResult run_scenario(const std::filesystem::path& scenario_file, const RunOptions& options, std::ostream& log) {
  const auto t_start = Clock::now();
  if (options.threads > 0) omp_set_num_threads(options.threads);
  const Scenario sc = load_scenario(scenario_file, options.overrides);
  if (options.stop_after)
    throw InputError(fmt::format("--stop-after {}: the scenario has no stage of that name (this run has no "
                                 "stages; known stage names: deposition, dynamics)",
                                 *options.stop_after));

  nlohmann::json wall_clock;
  auto t0 = Clock::now();
  ParticleStore particles = initial_particles(sc);
  wall_clock["input"] = seconds_since(t0);

  t0 = Clock::now();
  PackingReport report;
  try {
    report = analyze_packing(particles, sc.container, analysis_request(sc));
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: analysis.box_sides: {}", sc.file.string(), e.what()));
  }
  wall_clock["analysis"] = seconds_since(t0);

  nlohmann::json summary;
  summary["aggpack_version"] = kVersion;
  summary["seed"] = sc.seed;
  summary["scenario_file"] = sc.file.string();
  summary["scenario"] = to_json(sc);
  summary["particle_count"] = particles.size();
  const Box& b = sc.container.bounds;
  summary["container"] = {{"lo", {b.lo.x, b.lo.y, b.lo.z}}, {"hi", {b.hi.x, b.hi.y, b.hi.z}},
                          {"periodic", sc.container.periodic}};
  summary["stages"] = nlohmann::json::object();
  summary["modelling_notes"] = modelling_notes(sc, sc.analysis.box_sides.empty());
  summary.update(to_json(report));

  // Outputs only once everything has been computed: bad input leaves no files behind.
  t0 = Clock::now();
  const auto& dir = sc.output.directory;
  std::filesystem::create_directories(dir);
  if (sc.output.csv) write_file_atomically(dir / "particles.csv", particles_csv(particles));
  const std::string provenance = fmt::format("aggpack {}, scenario {}, seed {}", kVersion, sc.file.string(), sc.seed);
  if (sc.output.vtp) write_file_atomically(dir / "particles.vtp", particles_vtp(particles, provenance));
  wall_clock["output"] = seconds_since(t0);
  wall_clock["total"] = seconds_since(t_start);
  summary["wall_clock_s"] = wall_clock;
  write_file_atomically(dir / "summary.json", summary.dump(2) + "\n");

  if (!options.quiet) {
    fmt::print(log, "aggpack {}: {} ({} particles, seed {})\n", kVersion, sc.title, particles.size(), sc.seed);
    for (const auto& box : report.density.boxes)
      fmt::print(log, "  virtual cube {:8.4g} m: density {:.4f}\n", box.side, box.density);
    fmt::print(log, "  mean density {:.4f} (sd {:.4f}), mean coordination {:.3f} over {} spheres\n",
               report.density.mean, report.density.sd, report.coordination.mean,
               report.coordination.particles_counted);
    fmt::print(log, "  wrote {}\n", dir.string());
  }
  return {dir, summary};
}

}  // namespace aggpack
