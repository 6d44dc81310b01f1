#pragma once
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace aggpack {

// A run is a protocol: steps run in order by one loop over one particle store. Each kind
// of step is a value type here, a `run_step(const Kind&, RunContext&)` of its own
// (run/steps.cpp) and a reader of its [[protocol]] keys (io/scenario.cpp,
// read_protocol); the loop (run/run.cpp) only visits them and never changes for a new kind.

// Drop-and-roll deposition of part `layer` of `layers` equal parts of the drop sequence.
struct DepositStep {
  std::uint32_t layer = 0;
  std::uint32_t layers = 1;
};
// A pour of part `layer` of `layers` equal parts of the drop sequence ([pour] settings): a
// random gas above the bed, falling through the DEM ([dynamics] settings) until quiet.
struct PourStep {
  std::uint32_t layer = 0;
  std::uint32_t layers = 1;
};
// DEM settling of the bed, the particles of the layers below `layer` frozen.
struct SettleStep {
  std::uint32_t layer = 0;
};
// Tapping of the bed as it is now ([tapping] settings, the DEM of [dynamics]).
struct TapStep {};
// Rodding of the bed's top layer as it is now ([rodding] settings, the DEM of [dynamics];
// README "Rodding"): aggpack's DEM only.
struct RodStep {};
// Jigging of the bed as it is now ([jigging] settings, the DEM of [dynamics]; README
// "Jigging"): aggpack's DEM only.
struct JigStep {};
// The virtual-box analysis of the bed as it is now, reported as `stages.<report_as>`
// (density and coordination; with the deposition's own keys when that is "deposition").
struct AnalyseStep {
  std::string report_as;
};
// A copy of the bed as it is now, written as particles_<name>.csv beside the final one.
struct SnapshotStep {
  std::string name;
};
// The DEM steps: what a LAMMPS deck can run (run/lammps_bridge.hpp).
using DemStep = std::variant<SettleStep, PourStep, TapStep>;
// The bed as it is now and a LAMMPS deck of the protocol's next DEM step, written into
// <output>/lammps/<name>/; the run then goes on with that step itself.
struct ExportLammpsStep {
  std::string name;
  DemStep next;
};
// The bed's positions replaced by those of a LAMMPS dump (its last snapshot, or `timestep`'s)
// or data file, matched by id: the file must hold the same spheres (count and radii).
struct ImportLammpsStep {
  std::filesystem::path file;
  std::optional<std::int64_t> timestep;
};
using StepKind = std::variant<DepositStep, PourStep, SettleStep, TapStep, AnalyseStep, SnapshotStep, ExportLammpsStep,
                              ImportLammpsStep, RodStep, JigStep>;

struct Step {
  std::string stage;  // the stage it belongs to: what --stop-after names
  StepKind kind;
};

struct Protocol {
  std::vector<Step> steps;
  // The stages in order, each once: what --stop-after may name.
  [[nodiscard]] std::vector<std::string> stage_names() const {
    std::vector<std::string> names;
    std::set<std::string_view> seen;  // each analyse step is a stage: a search of `names` was quadratic
    for (const Step& s : steps)
      if (seen.insert(s.stage).second) names.push_back(s.stage);
    return names;
  }
};

}  // namespace aggpack
