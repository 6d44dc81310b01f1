#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "aggpack/io/scenario.hpp"

namespace aggpack {

// A run is a protocol: steps run in order by one loop over one particle store. Each kind
// of step is a value type here and a `run_step(const Kind&, RunContext&)` of its own
// (pipeline/steps.cpp); the loop (run.cpp) only visits them. A new kind touches this list,
// its run_step and where protocols are made; never the loop.

// Drop-and-roll deposition of part `layer` of `layers` equal parts of the drop sequence.
struct DepositStep {
  std::uint32_t layer = 0;
  std::uint32_t layers = 1;
};
// DEM settling of the bed, the particles of the layers below `layer` frozen.
struct SettleStep {
  std::uint32_t layer = 0;
};
// The virtual-box analysis of the bed as it is now, reported as `stages.<report_as>`
// (density and coordination; with the deposition's own keys when that is "deposition").
struct AnalyseStep {
  std::string report_as;
};
using StepKind = std::variant<DepositStep, SettleStep, AnalyseStep>;

struct Step {
  std::string stage;  // the stage it belongs to: what --stop-after names
  StepKind kind;
};

struct Protocol {
  std::vector<Step> steps;
  [[nodiscard]] std::vector<std::string> stage_names() const;  // in order, each once
};

// The protocol today's [deposition] and [dynamics] tables describe: deposit, analyse,
// settle; or, with dynamics.layers = N, deposit and settle each layer in turn (the paper's
// method); or settle a bed read from a file.
Protocol default_protocol(const Scenario& scenario);

// The protocol up to its last step of `stage`. InputError when the protocol has no such
// stage, or when stopping there leaves later steps of another stage inside it.
Protocol stop_after(const Protocol& protocol, std::string_view stage, const Scenario& scenario);

}  // namespace aggpack
