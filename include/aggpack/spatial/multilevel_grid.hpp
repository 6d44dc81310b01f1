#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "aggpack/core/container.hpp"
#include "aggpack/core/vec3.hpp"

namespace aggpack {

// A dynamic multilevel cell grid (Ogarko and Luding, Comput. Phys. Commun. 183, 2012):
// spheres are binned by radius into levels a factor of two apart, and each level has its
// own cell size, so a query costs O(1) per neighbour however wide the size range. Cells
// hold singly linked lists (4 bytes per cell and per sphere); z layers are allocated as
// the bed grows, so a tall, mostly empty container costs nothing. Periodic containers wrap
// x and y; elsewhere coordinates outside the container are clamped into the edge cells.
class MultilevelGrid {
 public:
  // `radii` are all the radii that will ever be inserted (they choose the levels and their
  // cell sizes); `bed_volume` is the expected volume the spheres will occupy, used to keep
  // the cells of sparse levels coarse enough that no level has many more cells than spheres.
  MultilevelGrid(const Container& container, std::span<const double> radii, double bed_volume);

  // The most cells (of all levels together) a grid may hold, 2^31 (8 GiB of cell heads): a
  // sphere that would need more (one far from the others, or a container far larger than its
  // spheres) is refused with an InputError that says why, never an exhausted memory.
  static constexpr std::size_t kMaxCells = std::size_t{1} << 31;

  // The cells a grid for these radii would need to hold a bed `height` tall (for checks
  // before any work; allocates nothing).
  [[nodiscard]] static double cells_needed(const Container& container, std::span<const double> radii,
                                           double bed_volume, double height);

  void reserve(std::size_t sphere_count) { next_.reserve(sphere_count); }

  // Registers sphere `id` (ids need not be dense, but memory grows with the largest id).
  void insert(std::uint32_t id, const Vec3& centre, double radius);

  // Calls visit(k) once for every sphere k that may have |c_k - p| <= reach + r_k
  // (a superset: the caller tests the exact distance).
  template <class Visit>
  void for_each_near(const Vec3& p, double reach, Visit&& visit) const {
    for_each_in_box(p - Vec3{reach, reach, reach}, p + Vec3{reach, reach, reach}, visit);
  }

  // Calls visit(k, same_level) once for every sphere k that may have |c_k - p| <= reach + r_k
  // and whose level holds spheres at least as large as `radius` (a superset, as above):
  // same_level says whether k shares the level of `radius`. Every pair of spheres on two
  // different levels is thus visited once, from the smaller sphere, whose query of the larger
  // levels spans a few of their coarse cells; a large sphere's query of the fine levels would
  // scan every small sphere in a cube twice its size.
  template <class Visit>
  void for_each_near_larger(const Vec3& p, double radius, double reach, Visit&& visit) const {
    const std::size_t own = level_of(radius);
    for (std::size_t l = 0; l <= own && l < levels_.size(); ++l)
      for_each_in_level_box(levels_[l], p - Vec3{reach, reach, reach}, p + Vec3{reach, reach, reach},
                            [&](std::uint32_t k) { visit(k, l == own); });
  }

  // Calls visit(k) once for every sphere k whose ball may meet the box [lo, hi] (a superset).
  template <class Visit>
  void for_each_in_box(const Vec3& lo, const Vec3& hi, Visit&& visit) const {
    for (const Level& level : levels_) for_each_in_level_box(level, lo, hi, visit);
  }

  // For a sphere of radius r falling down the vertical line through p: calls visit(k) for the
  // spheres k whose horizontal distance may be below r + r_k and whose centre is at most
  // p.z, scanning each cell column from the top down. A column is left as soon as its next
  // cell cannot hold a centre above stop_height() - r - r_max(level), so passing the best
  // hit found so far gives an early exit.
  template <class Visit, class StopHeight>
  void for_each_below(const Vec3& p, double r, Visit&& visit, StopHeight&& stop_height) const;

  // Displacement b - a, by the container's minimum image (its centres lie in the footprint).
  [[nodiscard]] Vec3 separation(const Vec3& a, const Vec3& b) const { return container_.minimum_image(b - a); }

  [[nodiscard]] std::size_t level_count() const { return levels_.size(); }
  [[nodiscard]] std::size_t memory_bytes() const;

 private:
  struct Level {
    double max_radius = 0.0;  // largest radius binned here
    double cell_x = 0.0, cell_y = 0.0, cell_z = 0.0;  // cell widths
    int nx = 1, ny = 1;
    std::vector<std::uint32_t> head;       // nx*ny per z layer; kEmpty or a sphere id
    std::vector<std::int32_t> top_layer;   // per column: highest non-empty layer, -1 if none
    [[nodiscard]] int layers() const { return static_cast<int>(head.size() / (static_cast<std::size_t>(nx) * ny)); }
  };
  static constexpr std::uint32_t kEmpty = 0xFFFFFFFFu;

  [[nodiscard]] std::size_t level_of(double radius) const;
  // for_each_in_box on one level.
  template <class Visit>
  void for_each_in_level_box(const Level& level, const Vec3& lo, const Vec3& hi, Visit&& visit) const;
  // The level of a radius among `level_count` levels below the largest radius `top`.
  [[nodiscard]] static std::size_t level_index(double radius, double top, std::size_t level_count);
  // The levels and their cells for these radii, nothing allocated: what the constructor
  // makes and what cells_needed counts.
  [[nodiscard]] static std::vector<Level> plan_levels(const Container& container, std::span<const double> radii,
                                                      double bed_volume);
  [[noreturn]] void too_many_cells(double cells, std::string_view what) const;
  [[nodiscard]] int column_index(double v, double lo, double width, int n) const;
  [[nodiscard]] int layer_index(double z, const Level& level) const;
  // Cell range [first, last] covering [a, b] on one horizontal axis; with periodic sides the
  // range may leave [0, n) and callers wrap it (it never exceeds n cells).
  void axis_range(double a, double b, double lo, double width, int n, int& first, int& last) const;
  [[nodiscard]] int wrap(int i, int n) const { return periodic_ ? ((i % n) + n) % n : i; }

  Vec3 lo_;
  Container container_;  // the boundary: periodic images and the footprint
  double period_x_ = 0.0, period_y_ = 0.0;
  bool periodic_ = false;
  double radius_top_ = 0.0;        // upper radius of level 0
  std::vector<Level> levels_;      // levels_[0] holds the largest spheres
  std::vector<std::uint32_t> next_;  // per sphere id: next in its cell's list
};

template <class Visit>
void MultilevelGrid::for_each_in_level_box(const Level& level, const Vec3& lo, const Vec3& hi, Visit&& visit) const {
  const int layers = level.layers();
  if (layers == 0) return;
  const double r = level.max_radius;
  int x0, x1, y0, y1;
  axis_range(lo.x - r, hi.x + r, lo_.x, level.cell_x, level.nx, x0, x1);
  axis_range(lo.y - r, hi.y + r, lo_.y, level.cell_y, level.ny, y0, y1);
  const int z0 = std::max(0, layer_index(lo.z - r, level));
  const int z1 = std::min(layers - 1, layer_index(hi.z + r, level));
  const std::size_t layer_size = static_cast<std::size_t>(level.nx) * level.ny;
  for (int iy0 = y0; iy0 <= y1; ++iy0) {
    const int iy = wrap(iy0, level.ny);
    for (int ix0 = x0; ix0 <= x1; ++ix0) {
      const std::size_t column = static_cast<std::size_t>(iy) * level.nx + wrap(ix0, level.nx);
      const int top = std::min(z1, level.top_layer[column]);
      for (int iz = z0; iz <= top; ++iz)
        for (std::uint32_t k = level.head[iz * layer_size + column]; k != kEmpty; k = next_[k]) visit(k);
    }
  }
}

template <class Visit, class StopHeight>
void MultilevelGrid::for_each_below(const Vec3& p, double r, Visit&& visit, StopHeight&& stop_height) const {
  constexpr int kMaxColumns = 64;
  std::size_t columns[kMaxColumns];
  for (const Level& level : levels_) {
    if (level.layers() == 0) continue;
    const double reach = r + level.max_radius;
    int x0, x1, y0, y1;
    axis_range(p.x - reach, p.x + reach, lo_.x, level.cell_x, level.nx, x0, x1);
    axis_range(p.y - reach, p.y + reach, lo_.y, level.cell_y, level.ny, y0, y1);
    const std::size_t layer_size = static_cast<std::size_t>(level.nx) * level.ny;
    // Layer by layer from the top of the highest column, across all columns at once, so that
    // the first hits found bound the rest of the scan.
    int top = -1, used = 0;
    const auto scan = [&](int first_layer) {
      for (int iz = first_layer; iz >= 0; --iz) {
        // Centres in this layer are below lo + (iz+1) cell; their hits at most reach above that.
        if (lo_.z + (iz + 1) * level.cell_z + reach < stop_height()) return;
        for (int c = 0; c < used; ++c)
          if (iz <= level.top_layer[columns[c]])
            for (std::uint32_t k = level.head[iz * layer_size + columns[c]]; k != kEmpty; k = next_[k]) visit(k);
      }
    };
    const int start = layer_index(p.z, level);
    for (int iy0 = y0; iy0 <= y1; ++iy0) {
      const int iy = wrap(iy0, level.ny);
      for (int ix0 = x0; ix0 <= x1; ++ix0) {
        const std::size_t column = static_cast<std::size_t>(iy) * level.nx + wrap(ix0, level.nx);
        if (level.top_layer[column] < 0) continue;
        if (used == kMaxColumns) {  // a sphere much larger than this level's cells: scan in batches
          scan(std::min(start, top));
          used = 0, top = -1;
        }
        columns[used++] = column;
        top = std::max(top, level.top_layer[column]);
      }
    }
    scan(std::min(start, top));
  }
}

}  // namespace aggpack
