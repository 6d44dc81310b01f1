#include "aggpack/spatial/cell_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace aggpack {

CellGrid::CellGrid(std::span<const Vec3> positions, const Container& container, double reach)
    : periodic_(container.periodic), period_(container.length_x()) {
  if (positions.size() >= std::numeric_limits<std::uint32_t>::max())
    throw std::length_error("CellGrid: too many spheres");
  Vec3 lo{std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
          std::numeric_limits<double>::max()};
  Vec3 hi = -lo;
  for (const Vec3& p : positions) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  if (positions.empty()) lo = hi = {};
  if (periodic_) {
    lo.x = container.bounds.lo.x;
    lo.y = container.bounds.lo.y;
    hi.x = container.bounds.hi.x;
    hi.y = container.bounds.hi.y;
  }
  lo_ = lo;
  cell_ = std::max(reach, 1e-300);
  const auto count = [&](double extent) {
    // Cap the cell count so a tiny reach in a large domain cannot exhaust memory.
    const double n = std::floor(extent / cell_);
    return static_cast<int>(std::clamp(n, 1.0, 1024.0));
  };
  if (periodic_) {
    // Periodic cells must tile the period exactly.
    // Periodic cells must tile the period exactly (square footprint).
    nx_ = ny_ = count(period_);
    cell_ = std::max(cell_, period_ / nx_);
  } else {
    nx_ = count(hi.x - lo.x);
    ny_ = count(hi.y - lo.y);
  }
  nz_ = count(hi.z - lo.z);
  // Non-periodic: make the cells wide enough that nx_ cells cover the extent.
  if (!periodic_)
    cell_ = std::max({cell_, (hi.x - lo.x) / nx_, (hi.y - lo.y) / ny_, (hi.z - lo.z) / nz_});
  else
    cell_ = std::max(cell_, (hi.z - lo.z) / nz_);

  const std::size_t cells = static_cast<std::size_t>(nx_) * ny_ * nz_;
  cell_start_.assign(cells + 1, 0);
  std::vector<std::uint32_t> cell_of(positions.size());
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const Vec3& p = positions[i];
    const std::size_t c =
        (static_cast<std::size_t>(cell_coord(p.z, lo_.z, nz_)) * ny_ + cell_coord(p.y, lo_.y, ny_)) * nx_ +
        cell_coord(p.x, lo_.x, nx_);
    cell_of[i] = static_cast<std::uint32_t>(c);
    ++cell_start_[c + 1];
  }
  for (std::size_t c = 0; c < cells; ++c) cell_start_[c + 1] += cell_start_[c];
  members_.resize(positions.size());
  std::vector<std::uint32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (std::size_t i = 0; i < positions.size(); ++i) members_[fill[cell_of[i]]++] = static_cast<std::uint32_t>(i);
}

int CellGrid::cell_coord(double v, double lo, int n) const {
  const double c = std::floor((v - lo) / cell_);
  return static_cast<int>(std::clamp(c, 0.0, static_cast<double>(n - 1)));
}

Vec3 CellGrid::separation(const Vec3& a, const Vec3& b) const {
  Vec3 d = b - a;
  if (periodic_) {
    d.x -= period_ * std::nearbyint(d.x / period_);
    d.y -= period_ * std::nearbyint(d.y / period_);
  }
  return d;
}

}  // namespace aggpack
