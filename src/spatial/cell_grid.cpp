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
  // Per axis n = floor(extent / reach) cells of width extent / n >= reach, so that the
  // cells tile a periodic side exactly. The cap keeps a tiny reach from exhausting memory.
  const auto axis = [&](double extent, int& n, double& width) {
    n = static_cast<int>(std::clamp(std::floor(extent / std::max(reach, 1e-300)), 1.0, 1024.0));
    width = std::max(extent, 1e-300) / n;
  };
  axis(hi.x - lo.x, nx_, cell_.x);
  axis(hi.y - lo.y, ny_, cell_.y);
  axis(hi.z - lo.z, nz_, cell_.z);
  // No more cells than a few per sphere: merge cells along the finest axis (never below 1).
  const std::size_t max_cells = 8 * positions.size() + 64;
  while (static_cast<std::size_t>(nx_) * ny_ * nz_ > max_cells) {
    int& n = (nx_ >= ny_ && nx_ >= nz_) ? nx_ : (ny_ >= nz_ ? ny_ : nz_);
    double& width = (&n == &nx_) ? cell_.x : (&n == &ny_ ? cell_.y : cell_.z);
    const double extent = width * n;
    n = std::max(1, n / 2);
    width = extent / n;
  }

  const std::size_t cells = static_cast<std::size_t>(nx_) * ny_ * nz_;
  cell_start_.assign(cells + 1, 0);
  std::vector<std::uint32_t> cell_of(positions.size());
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const Vec3& p = positions[i];
    const std::size_t c =
        (static_cast<std::size_t>(cell_coord(p.z, lo_.z, cell_.z, nz_)) * ny_ + cell_coord(p.y, lo_.y, cell_.y, ny_)) *
            nx_ +
        cell_coord(p.x, lo_.x, cell_.x, nx_);
    cell_of[i] = static_cast<std::uint32_t>(c);
    ++cell_start_[c + 1];
  }
  for (std::size_t c = 0; c < cells; ++c) cell_start_[c + 1] += cell_start_[c];
  members_.resize(positions.size());
  std::vector<std::uint32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (std::size_t i = 0; i < positions.size(); ++i) members_[fill[cell_of[i]]++] = static_cast<std::uint32_t>(i);
}

int CellGrid::cell_coord(double v, double lo, double width, int n) {
  const double c = std::floor((v - lo) / width);
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
