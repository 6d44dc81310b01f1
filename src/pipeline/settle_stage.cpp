#include "aggpack/pipeline/settle_stage.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "aggpack/analysis/density.hpp"
#include "aggpack/core/error.hpp"
#include "aggpack/dynamics/contact_law_registry.hpp"
#include "aggpack/dynamics/settle.hpp"
#include "aggpack/pipeline/analyze.hpp"

namespace aggpack {

std::string TimeSeries::csv() const {
  std::string body;
  for (const TimeSample& s : samples)
    fmt::format_to(std::back_inserter(body), "{:.9g},{},{},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.5g}\n", s.time, s.layer,
                   std::isnan(s.density) ? std::string() : fmt::format("{:.6f}", s.density),
                   s.translational_per_particle_mgd, s.translational_energy, s.rotational_energy, s.mean_overlap,
                   s.max_overlap, s.coordination);
  return "time_s,layer,density,translational_energy_per_particle_mgd,translational_energy_j,rotational_energy_j,"
         "mean_overlap_rel,max_overlap_rel,coordination\n" +
         body;
}


SettlingRun settle_bed(const Scenario& sc, ParticleStore& particles, std::uint32_t layer, double time_offset,
                       int threads, TimeSeries& series, Progress& progress) {
  const DynamicsStage& stage = *sc.dynamics;
  // The layers below this one stay where they are (the paper's layer-by-layer method).
  std::vector<std::uint8_t> frozen(particles.size());
  for (std::size_t i = 0; i < particles.size(); ++i) frozen[i] = particles.layer[i] < layer ? 1 : 0;
  double r_min = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < particles.size(); ++i)
    if (!frozen[i]) r_min = std::min(r_min, particles.radius[i]);
  if (!std::isfinite(r_min)) throw InputError(fmt::format("{}: [dynamics]: there are no particles to settle",
                                                          sc.file.string()));

  const ContactModel model = [&] {
    try {
      return make_contact_model(sc.material.contact);
    } catch (const InputError& e) {
      throw InputError(fmt::format("{}: [material]: {}", sc.file.string(), e.what()));
    }
  }();
  const double rayleigh = stable_time_scale(sc.material.contact, r_min, sc.material.density);
  DemSettings settings = stage.dem;
  settings.time_step = stage.time_step.step(rayleigh);
  settings.threads = threads;

  AnalysisRequest request;
  request.cube_sides = sc.analysis.box_sides;
  const auto density = [&](const ParticleStore& store) {
    try {
      const BedGeometry bed = measure_bed(store, sc.container);
      return measure_density(store, sc.container, virtual_boxes(sc.container, bed, request)).mean;
    } catch (const InputError&) {
      return std::numeric_limits<double>::quiet_NaN();  // the boxes do not fit the bed yet
    }
  };
  const QuietCriterion& criterion = stage.quiet;

  const auto t0 = std::chrono::steady_clock::now();
  DemSystem dem(particles, sc.container, model, settings, std::move(frozen));
  const std::size_t free_count = dem.free_count();
  progress.start_stage(layer > 0 || stage.layers > 1 ? fmt::format("dynamics, layer {}", layer + 1) : "dynamics");
  QuietForecast forecast(criterion);
  const auto record = [&](const SettleSample& s) {
    series.samples.push_back({time_offset + s.time, layer, s.density, s.translational_per_particle_mgd,
                              s.kinetic_energy.translational, s.kinetic_energy.rotational, s.contacts.mean_overlap,
                              s.contacts.max_overlap, s.contacts.coordination});
    forecast.add(s);
    // The forecast is a fit over the samples so far: only worth it for a line that will show.
    if (!progress.due()) return;
    const std::optional<double> end = forecast.expected_end();
    progress.update({fmt::format("{:.3f} s simulated", s.time),
                     fmt::format("density {}", std::isnan(s.density) ? std::string("-") : fmt::format("{:.4f}", s.density)),
                     fmt::format("kinetic energy {:.1e} m g d (quiet below {:.0e})", s.translational_per_particle_mgd,
                                 criterion.kinetic_fraction),
                     fmt::format("max_time {:g} s", stage.quiet.max_time)},
                    s.time / end.value_or(stage.quiet.max_time),
                    end ? Progress::TimeLeft::Estimate : Progress::TimeLeft::AtMost);
  };
  const SettleResult result = settle(dem, particles, criterion, density, record);
  dem.finish();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  SettlingRun run;
  run.layer = layer;
  run.particles_settled = free_count;
  run.particles_frozen = particles.size() - free_count;
  run.ended_by = result.end;
  run.simulated_time = result.simulated_time;
  run.steps = result.steps;
  run.time_step = settings.time_step;
  run.rayleigh_time = rayleigh;
  run.time_step_from_scenario = stage.time_step.fixed.has_value();
  run.skin = dem.skin();
  run.neighbour_list_builds = result.rebuilds;
  run.last = result.last;
  run.wall_clock_s = seconds;
  run.particle_steps_per_second =
      seconds > 0 ? static_cast<double>(free_count) * static_cast<double>(result.steps) / seconds : 0.0;
  run.threads = dem.threads();
  run.memory_bytes_per_particle =
      static_cast<double>(dem.memory_bytes()) / static_cast<double>(std::max<std::size_t>(1, particles.size()));
  return run;
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
