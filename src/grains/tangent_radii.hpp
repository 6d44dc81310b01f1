// The tangent spheres' radii of fill_convex (grain_shape.cpp): for each surface point, the
// largest sphere behind every tangent plane that touches the point's own plane there. An
// ellipsoid's surface is thousands of planes, each tried for each point, so the search runs
// over Highway vectors (tangent_radii.cpp); internal to the grains module.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "aggpack/grains/grain_shape.hpp"

namespace aggpack::grains_internal {

// Tangent planes n.x <= offset, by columns.
struct PlaneColumns {
  std::vector<double> nx, ny, nz, offset;
  void add(const Vec3& normal, double plane_offset);
};

// For each point p, min over the planes k with 1 - n_k.n_p > 1e-12 of
// max(0, offset_k - n_k.p) / (1 - n_k.n_p); infinity where no plane bounds it. The same bits
// as that scalar loop (each lane's operations in its order, the minimum exact in any order).
[[nodiscard]] std::vector<double> tangent_radii(const PlaneColumns& planes, std::span<const SurfacePoint> points);

// The Highway targets this machine runs, and tangent_radii on one of them, for tests and
// benchmarks (it sets Highway's target for the whole process while it runs: one thread only).
[[nodiscard]] std::vector<std::string> tangent_radii_targets();
[[nodiscard]] std::vector<double> tangent_radii_on(const std::string& target, const PlaneColumns& planes,
                                                   std::span<const SurfacePoint> points);

}  // namespace aggpack::grains_internal
