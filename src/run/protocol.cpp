#include "aggpack/run/protocol.hpp"

#include <algorithm>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "aggpack/core/error.hpp"

namespace aggpack {

Protocol default_protocol(const Scenario& sc) {
  Protocol p;
  const std::uint32_t layers = sc.dynamics ? static_cast<std::uint32_t>(sc.dynamics->layers) : 1;
  if (sc.deposition && layers > 1) {
    for (std::uint32_t k = 0; k < layers; ++k) {
      p.steps.push_back({"deposition", DepositStep{k, layers}});
      p.steps.push_back({"dynamics", SettleStep{k}});
    }
    return p;
  }
  if (sc.pour) {  // the pour settles as it goes: [dynamics] gives its DEM settings
    p.steps.push_back({"pour", PourStep{0, 1}});
  } else {
    if (sc.deposition) {
      p.steps.push_back({"deposition", DepositStep{0, 1}});
      p.steps.push_back({"deposition", AnalyseStep{"deposition"}});
    }
    if (sc.dynamics) p.steps.push_back({"dynamics", SettleStep{0}});
  }
  if (sc.tapping) {  // the bed as made so far (stages.pour or stages.before_tapping), then tapped
    const std::string before = sc.pour ? "pour" : "before_tapping";
    p.steps.push_back({before, AnalyseStep{before}});
    p.steps.push_back({"tapping", TapStep{}});
  }
  if (sc.rodding) p.steps.push_back({"rodding", RodStep{}});
  if (sc.jigging) p.steps.push_back({"jigging", JigStep{}});
  return p;
}

Protocol scenario_protocol(const Scenario& sc) { return sc.protocol ? *sc.protocol : default_protocol(sc); }

Protocol stop_after(const Protocol& protocol, std::string_view stage, const Scenario& sc) {
  const std::vector<std::string> names = protocol.stage_names();
  if (std::find(names.begin(), names.end(), stage) == names.end())
    throw InputError(fmt::format("--stop-after {}: the scenario has no stage of that name (its stages: {})", stage,
                                 names.empty() ? std::string("none") : fmt::format("{}", fmt::join(names, ", "))));
  const auto last = std::find_if(protocol.steps.rbegin(), protocol.steps.rend(),
                                 [&](const Step& s) { return s.stage == stage; });
  Protocol kept;
  kept.steps.assign(protocol.steps.begin(), last.base());
  // Stopping must leave a state of that stage: not one with another stage's steps between.
  const auto first = std::find_if(kept.steps.begin(), kept.steps.end(), [&](const Step& s) { return s.stage == stage; });
  if (std::any_of(first, kept.steps.end(), [&](const Step& s) { return s.stage != stage; }))
    throw InputError(fmt::format("--stop-after {}: {} settles each of its {} layers before depositing the next, "
                                 "so there is no deposited bed to stop at; use dynamics.layers = 1",
                                 stage, sc.file.string(), sc.dynamics ? sc.dynamics->layers : 1));
  return kept;
}

}  // namespace aggpack
