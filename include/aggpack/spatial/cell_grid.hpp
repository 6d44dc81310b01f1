#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "aggpack/core/container.hpp"
#include "aggpack/core/vec3.hpp"

namespace aggpack {

// A uniform cell list over a set of spheres, built once (counting sort, no per-cell
// allocations). Cells are at least as wide as the largest interaction range, so the
// neighbours of a point lie in the 27 cells around it. Periodic containers wrap x and y.
class CellGrid {
 public:
  // `reach` is the largest centre distance a query will ask for.
  CellGrid(std::span<const Vec3> positions, const Container& container, double reach);

  // Calls visit(j) for every sphere j whose centre may lie within `reach` of p
  // (a superset: callers test the exact distance), each j once.
  template <class Visit>
  void for_each_candidate(const Vec3& p, Visit&& visit) const;

  // Displacement b - a, by the minimum image where the container is periodic.
  [[nodiscard]] Vec3 separation(const Vec3& a, const Vec3& b) const;

 private:
  [[nodiscard]] static int cell_coord(double v, double lo, double width, int n);

  Vec3 lo_;
  Vec3 cell_{1.0, 1.0, 1.0};  // cell widths, each >= reach
  int nx_ = 1, ny_ = 1, nz_ = 1;
  bool periodic_ = false;
  double period_ = 0.0;
  std::vector<std::uint32_t> cell_start_;  // size cells + 1
  std::vector<std::uint32_t> members_;     // sphere indices grouped by cell
};

template <class Visit>
void CellGrid::for_each_candidate(const Vec3& p, Visit&& visit) const {
  const int cx = cell_coord(p.x, lo_.x, cell_.x, nx_);
  const int cy = cell_coord(p.y, lo_.y, cell_.y, ny_);
  const int cz = cell_coord(p.z, lo_.z, cell_.z, nz_);
  // With fewer than 3 periodic cells the wrapped offsets would visit a cell twice: scan the row.
  const bool whole_x = periodic_ && nx_ < 3, whole_y = periodic_ && ny_ < 3;
  const int lo_x = whole_x ? 0 : cx - 1, hi_x = whole_x ? nx_ - 1 : cx + 1;
  const int lo_y = whole_y ? 0 : cy - 1, hi_y = whole_y ? ny_ - 1 : cy + 1;
  for (int iz = cz - 1; iz <= cz + 1; ++iz) {
    if (iz < 0 || iz >= nz_) continue;
    for (int iy0 = lo_y; iy0 <= hi_y; ++iy0) {
      int iy = iy0;
      if (periodic_) iy = (iy + ny_) % ny_;
      else if (iy < 0 || iy >= ny_) continue;
      for (int ix0 = lo_x; ix0 <= hi_x; ++ix0) {
        int ix = ix0;
        if (periodic_) ix = (ix + nx_) % nx_;
        else if (ix < 0 || ix >= nx_) continue;
        const std::size_t cell = (static_cast<std::size_t>(iz) * ny_ + iy) * nx_ + ix;
        for (std::uint32_t k = cell_start_[cell]; k < cell_start_[cell + 1]; ++k) visit(members_[k]);
      }
    }
  }
}

}  // namespace aggpack
