#pragma once
#include <cmath>

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
  // p with x and y brought into [lo, hi) when the sides are periodic; p itself otherwise.
  [[nodiscard]] Vec3 wrapped(Vec3 p) const {
    if (!periodic) return p;
    const auto wrap = [](double v, double lo, double length) {
      const double w = lo + std::fmod(std::fmod(v - lo, length) + length, length);
      return w >= lo + length ? lo : w;
    };
    p.x = wrap(p.x, bounds.lo.x, length_x());
    p.y = wrap(p.y, bounds.lo.y, length_y());
    return p;
  }
};

}  // namespace aggpack
