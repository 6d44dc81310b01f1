#pragma once
#include <string>

#include <fmt/format.h>

#include "aggpack/core/vec3.hpp"

namespace aggpack {

// Axis-aligned box [lo, hi], metres.
struct Box {
  Vec3 lo, hi;

  [[nodiscard]] constexpr Vec3 size() const { return hi - lo; }
  [[nodiscard]] constexpr double volume() const {
    const Vec3 s = size();
    return s.x * s.y * s.z;
  }
  [[nodiscard]] constexpr bool contains(const Vec3& p) const {
    return p.x >= lo.x && p.x < hi.x && p.y >= lo.y && p.y < hi.y && p.z >= lo.z && p.z < hi.z;
  }
};

// "[x_lo, x_hi] x [y_lo, y_hi] x [z_lo, z_hi] m", for messages.
inline std::string box_text(const Box& b) {
  return fmt::format("[{:.6g}, {:.6g}] x [{:.6g}, {:.6g}] x [{:.6g}, {:.6g}] m", b.lo.x, b.hi.x, b.lo.y, b.hi.y,
                     b.lo.z, b.hi.z);
}

}  // namespace aggpack
