#pragma once
#include <optional>
#include <vector>

#include "aggpack/run/carried_dem.hpp"
#include "aggpack/run/progress.hpp"
#include "aggpack/run/protocol.hpp"
#include "aggpack/run/run_grains.hpp"
#include "aggpack/run/run_report.hpp"

namespace aggpack {

// What the steps of one run share: the report they fill in (its particle store is the bed)
// and the state that passes from step to step. Made by RunSession, by member name.
struct RunContext {
  RunReport& report;
  Progress& progress;
  int threads = 0;                              // OpenMP threads of the DEM; 0: OpenMP's default
  const StopRequest* stop = nullptr;            // checked at every safe point; null: never
  SafePoint* safe_point = nullptr;              // the run's checkpointer; null: none
  const std::string* resume_state = nullptr;    // the step in progress at a checkpoint, to continue
  std::vector<double> radii{};                  // the drop sequence, m
  std::vector<std::uint8_t> sphere_materials{}; // the drop sequence's materials; empty: all [material]
  std::vector<double> material_densities{};     // kg/m^3, per material of the run
  RunGrains grains{};                           // the drop sequence's grains; empty: all spheres
  double simulated_time = 0.0;                  // s of DEM so far, over all settle steps
  std::optional<std::uint32_t> deposition_stopped_at{};  // the layer whose deposition ended early
  const SampleObserver* at_sample = nullptr;    // at every DEM sample (the frames); null: nothing
  CarriedDem dem{};                             // the DEM system consecutive DEM steps continue
  bool in_step = false;                         // inside a step (whose safe points save its DEM state)
  // The materials of the drop sequence's spheres [begin, end).
  [[nodiscard]] SphereMaterials materials(std::size_t begin, std::size_t end) const {
    return SphereMaterials{sphere_materials, material_densities}.part(begin, end - begin);
  }
  [[nodiscard]] StageControls stage_controls() {
    return {threads, stop, safe_point, resume_state, at_sample, &dem};
  }
};

// One adapter per step kind, with one signature; each is the only code that knows its kind.
void run_step(const DepositStep& step, RunContext& context);
void run_step(const PourStep& step, RunContext& context);
void run_step(const SettleStep& step, RunContext& context);
void run_step(const TapStep& step, RunContext& context);
void run_step(const RodStep& step, RunContext& context);
void run_step(const JigStep& step, RunContext& context);
void run_step(const AnalyseStep& step, RunContext& context);
void run_step(const SnapshotStep& step, RunContext& context);
void run_step(const ExportLammpsStep& step, RunContext& context);
void run_step(const ImportLammpsStep& step, RunContext& context);

// The analysis of a scenario's bed, naming the scenario key when a box does not fit.
PackingReport analyse_bed(const Scenario& scenario, const ParticleStore& particles);
AnalysisRequest analysis_request(const Scenario& scenario);

}  // namespace aggpack
