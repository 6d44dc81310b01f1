#include "aggpack/run/steps.hpp"

#include <algorithm>
#include <chrono>
#include <span>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/deposition/drop_and_roll.hpp"
#include "aggpack/run/lammps_steps.hpp"

namespace aggpack {

namespace {
using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
}  // namespace

AnalysisRequest analysis_request(const Scenario& sc) {
  AnalysisRequest request;
  request.cube_sides = sc.analysis.box_sides;
  request.contact_tolerance = sc.analysis.contact_tolerance;
  request.slice_thickness = sc.analysis.slice_thickness;
  request.shell_thickness = sc.analysis.shell_thickness;
  request.max_profile_bins = sc.limits.max_profile_bins;
  request.max_grid_cells = sc.limits.max_grid_cells;
  return request;
}

PackingReport analyse_bed(const Scenario& sc, const ParticleStore& particles) {
  try {
    return analyze_packing(particles, sc.container, analysis_request(sc));
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: analysis.box_sides: {}", sc.file.string(), e.what()));
  }
}

void run_step(const DepositStep& step, RunContext& ctx) {
  if (ctx.deposition_stopped_at) return;  // an earlier layer could not be placed: the bed is full
  const Scenario& sc = ctx.report.scenario;
  ParticleStore& particles = ctx.report.particles;
  const std::size_t n = ctx.radii.size();
  const std::size_t begin = n * step.layer / step.layers, end = n * (step.layer + 1) / step.layers;
  const std::span<const double> radii(ctx.radii.data() + begin, end - begin);

  const DepositionSettings& settings = *sc.deposition;
  ctx.dem.drop();  // the bed grows outside the DEM: the next DEM step starts afresh
  particles.reserve(particles.size() + radii.size());
  DropAndRoll deposition(particles, sc.container, radii, settings, deposition_stream(sc.seed, step.layer));
  const auto t0 = Clock::now();
  ctx.progress.start_stage(step.layers > 1 || step.layer > 0 ? fmt::format("deposition, layer {}", step.layer + 1)
                                                             : std::string("deposition"));
  const DepositionObserver observer{std::max<std::size_t>(1000, radii.size() / 100), [&](std::size_t placed) {
    stop_here_if_requested(ctx.stop, fmt::format("while depositing, {} of {} particles placed", placed, radii.size()));
    ctx.progress.update({fmt::format("{} of {} particles placed", placed, radii.size())},
                        static_cast<double>(placed) / static_cast<double>(radii.size()));
  }};
  deposition.deposit(radii, ctx.materials(begin, end), step.layer, observer);
  DepositionReport layer;
  layer.requested = radii.size();
  layer.stats = deposition.stats();
  layer.fill_height = settings.fill_height;
  layer.wall_clock_s = seconds_since(t0);
  layer.layers = step.layers;
  if (ctx.report.deposition) *ctx.report.deposition += layer;
  else ctx.report.deposition = layer;
  // The deposition's supports cover the whole bed; only the new spheres' are this step's.
  const std::vector<Supports>& supports = deposition.supports();
  ctx.report.supports.insert(ctx.report.supports.end(),
                             supports.begin() + static_cast<std::ptrdiff_t>(ctx.report.supports.size()),
                             supports.end());
  if (layer.stats.end != DepositionEnd::AllPlaced) ctx.deposition_stopped_at = step.layer;
}

void run_step(const PourStep& step, RunContext& ctx) {
  if (ctx.deposition_stopped_at) return;  // an earlier part could not be placed: the bed is full
  RunReport& r = ctx.report;
  const std::size_t n = ctx.radii.size();
  const std::size_t begin = n * step.layer / step.layers, end = n * (step.layer + 1) / step.layers;
  const std::span<const double> radii(ctx.radii.data() + begin, end - begin);
  // Grains come in by their bounding spheres' radii, each with its shape.
  const RunGrains::PourPart part = ctx.grains.pour_part(radii, begin);
  const PouredShapes shapes = ctx.grains.empty() ? PouredShapes{} : PouredShapes{part.shapes};
  const PourRun run =
      r.scenario.dynamics->engine == DemEngine::Lammps
          ? pour_in_lammps(r.scenario, r.particles, part.radii, ctx.materials(begin, end), shapes, step,
                           ctx.simulated_time, r.series, ctx.progress)
          : pour_bed(r.scenario, r.particles, part.radii, ctx.materials(begin, end), shapes, step.layer,
                     ctx.simulated_time, ctx.stage_controls(), r.series, ctx.progress);
  ctx.simulated_time += run.settling.simulated_time;
  if (!r.dynamics) r.dynamics.emplace();
  r.dynamics->runs.push_back(run.settling);
  r.pours.push_back(run.pour);
}

void run_step(const SettleStep& step, RunContext& ctx) {
  if (ctx.deposition_stopped_at && step.layer > *ctx.deposition_stopped_at) return;  // that layer was never deposited
  RunReport& r = ctx.report;
  // The bed as deposited, kept for the report's before/after pictures: when the whole drop
  // sequence was deposited before the first settling (kept already when it is resumed).
  if (r.deposition && !r.dynamics && !r.deposited && r.deposition->requested == ctx.radii.size())
    r.deposited = r.particles;
  const SettlingRun run =
      r.scenario.dynamics->engine == DemEngine::Lammps
          ? settle_in_lammps(r.scenario, r.particles, step.layer, ctx.simulated_time, r.series, ctx.progress)
          : settle_bed(r.scenario, r.particles, step.layer, ctx.simulated_time, ctx.stage_controls(), r.series,
                       ctx.progress);
  ctx.simulated_time += run.simulated_time;
  if (!r.dynamics) r.dynamics.emplace();
  r.dynamics->runs.push_back(run);
}

void run_step(const TapStep& /*step*/, RunContext& ctx) {
  RunReport& r = ctx.report;
  TapReport report =
      r.scenario.dynamics->engine == DemEngine::Lammps
          ? tap_in_lammps(r.scenario, r.particles, r.tappings.size(), ctx.simulated_time, r.series, ctx.progress)
          : tap_bed(r.scenario, r.particles, ctx.simulated_time, ctx.stage_controls(), r.series, ctx.progress);
  ctx.simulated_time += report.simulated_time;
  r.tappings.push_back(std::move(report));
}

// Rodding and jigging: aggpack's DEM only (the scenario reader refuses them with LAMMPS).
void run_step(const RodStep& /*step*/, RunContext& ctx) {
  RunReport& r = ctx.report;
  RoddingReport report = rod_bed(r.scenario, r.particles, ctx.simulated_time, ctx.stage_controls(), r.series, ctx.progress);
  ctx.simulated_time += report.simulated_time;
  r.roddings.push_back(std::move(report));
}

void run_step(const JigStep& /*step*/, RunContext& ctx) {
  RunReport& r = ctx.report;
  JigReport report = jig_bed(r.scenario, r.particles, ctx.simulated_time, ctx.stage_controls(), r.series, ctx.progress);
  ctx.simulated_time += report.simulated_time;
  r.jiggings.push_back(std::move(report));
}

void run_step(const AnalyseStep& step, RunContext& ctx) {
  const auto t0 = Clock::now();
  StageAnalysis analysis{analyse_bed(ctx.report.scenario, ctx.report.particles), 0.0};
  analysis.wall_clock_s = seconds_since(t0);
  ctx.report.analyses[step.report_as] = std::move(analysis);
}

void run_step(const SnapshotStep& step, RunContext& ctx) {
  ctx.report.snapshots[step.name] = ctx.report.particles;
  ctx.report.snapshot_times[step.name] = ctx.simulated_time;  // its place in particles.pvd
}

void run_step(const ExportLammpsStep& step, RunContext& ctx) {
  const Scenario& sc = ctx.report.scenario;
  RunGrains::PourPart part;
  SphereMaterials pour_materials;
  if (const auto* pour = std::get_if<PourStep>(&step.next)) {
    const std::size_t n = ctx.radii.size();
    const std::size_t begin = n * pour->layer / pour->layers, end = n * (pour->layer + 1) / pour->layers;
    part = ctx.grains.pour_part(std::span<const double>(ctx.radii.data() + begin, end - begin), begin);
    pour_materials = ctx.materials(begin, end);
  }
  const LammpsDeck deck = lammps_deck(sc, ctx.report.particles, step.next, part.radii, pour_materials.of,
                                      ctx.grains.empty() ? PouredShapes{} : PouredShapes{part.shapes});
  const std::filesystem::path folder = sc.output.directory / "lammps" / step.name;
  write_lammps_deck(folder, deck);
  ctx.report.lammps_exchanges.push_back({"export", folder.string(), deck.step, ctx.report.particles.size()});
}

void run_step(const ImportLammpsStep& step, RunContext& ctx) {
  ParticleStore& bed = ctx.report.particles;
  ctx.dem.drop();  // the bed comes from elsewhere: the next DEM step starts afresh
  const std::string format = take_positions_from_lammps(bed, step.file, step.timestep, ctx.report.scenario);
  ctx.report.lammps_exchanges.push_back({"import", step.file.string(), format, bed.size()});
}

}  // namespace aggpack
