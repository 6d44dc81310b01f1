#pragma once
#include "aggpack/core/box.hpp"

namespace aggpack {

// The container: a floor at bounds.lo.z and side walls at the x and y faces of `bounds`;
// with periodic sides, x and y wrap instead. Scenarios make square containers with the
// floor at z = 0; a packing file from another tool gets its own bounding box.
struct Container {
  Box bounds;
  bool periodic = false;

  static Container square(double side, double height, bool periodic) {
    return {{{0.0, 0.0, 0.0}, {side, side, height}}, periodic};
  }
  [[nodiscard]] double length_x() const { return bounds.hi.x - bounds.lo.x; }
  [[nodiscard]] double length_y() const { return bounds.hi.y - bounds.lo.y; }
  [[nodiscard]] double height() const { return bounds.hi.z - bounds.lo.z; }
};

}  // namespace aggpack
