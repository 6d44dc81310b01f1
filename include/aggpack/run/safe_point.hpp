#pragma once
#include <functional>
#include <ostream>
#include <string>

#include "aggpack/core/stop_request.hpp"

namespace aggpack {

// Writes a part of a checkpoint straight into its file (a bed's worth of bytes is not copied).
using StateWriter = std::function<void(std::ostream&)>;

// A place where a run may stop and later continue exactly: after a DEM sample, between steps.
// The run's checkpointer (run/checkpoint.hpp) implements it.
class SafePoint {
 public:
  virtual ~SafePoint() = default;
  // Writes a checkpoint when one is due, or a stop was requested: the run so far with, inside a
  // step, the step's state as `save_step` writes it (null between steps). Then, if a stop was
  // requested, throws Interrupted naming `where`.
  virtual void reached(const std::string& where, const StateWriter& save_step) = 0;
};

// The safe point of a step that may have no checkpointer: then only a requested stop counts.
inline void at_safe_point(SafePoint* safe_point, const StopRequest* stop, const std::string& where,
                          const StateWriter& save_step) {
  if (safe_point) safe_point->reached(where, save_step);
  else stop_here_if_requested(stop, where);
}

}  // namespace aggpack
