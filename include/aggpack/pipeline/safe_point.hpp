#pragma once
#include <functional>
#include <string>

#include "aggpack/core/stop_request.hpp"

namespace aggpack {

// A place where a run may stop and later continue exactly: after a DEM sample, between steps.
// The run's checkpointer (pipeline/checkpoint.hpp) implements it.
class SafePoint {
 public:
  virtual ~SafePoint() = default;
  // Writes a checkpoint when one is due, or a stop was requested: the run so far with, inside a
  // step, `save_step()`'s state of the step (null between steps). Then, if a stop was
  // requested, throws Interrupted naming `where`.
  virtual void reached(const std::string& where, const std::function<std::string()>& save_step) = 0;
};

// The safe point of a step that may have no checkpointer: then only a requested stop counts.
inline void at_safe_point(SafePoint* safe_point, const StopRequest* stop, const std::string& where,
                          const std::function<std::string()>& save_step) {
  if (safe_point) safe_point->reached(where, save_step);
  else stop_here_if_requested(stop, where);
}

}  // namespace aggpack
