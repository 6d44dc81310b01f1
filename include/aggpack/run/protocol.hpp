#pragma once
#include <string_view>

#include "aggpack/io/protocol.hpp"
#include "aggpack/io/scenario.hpp"

namespace aggpack {

// The protocol today's [deposition] and [dynamics] tables describe: deposit, analyse,
// settle; or, with dynamics.layers = N, deposit and settle each layer in turn (the paper's
// method); or settle a bed read from a file; or, with [pour], pour (which settles as it goes).
Protocol default_protocol(const Scenario& scenario);

// The scenario's own [[protocol]] when it has one, else the default above.
Protocol scenario_protocol(const Scenario& scenario);

// The protocol up to its last step of `stage`. InputError when the protocol has no such
// stage, or when stopping there leaves later steps of another stage inside it.
Protocol stop_after(const Protocol& protocol, std::string_view stage, const Scenario& scenario);

}  // namespace aggpack
