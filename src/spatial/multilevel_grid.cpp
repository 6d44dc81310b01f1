#include "aggpack/spatial/multilevel_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"

namespace aggpack {

namespace {
// Cells per horizontal axis: as many as fit at the given minimum width, so that cells tile a
// periodic side exactly; never fewer than one.
int cells_along(double extent, double min_width) {
  return static_cast<int>(std::clamp(std::floor(extent / min_width), 1.0, 65536.0));
}
}  // namespace

std::vector<MultilevelGrid::Level> MultilevelGrid::plan_levels(const Container& container,
                                                               std::span<const double> radii, double bed_volume) {
  const auto [min_it, max_it] = std::minmax_element(radii.begin(), radii.end());
  if (!(*min_it > 0.0)) throw std::invalid_argument("MultilevelGrid: radii must be positive");
  const double top = *max_it;
  // Levels a factor of two apart in radius: level l holds radii in (top/2^(l+1), top/2^l].
  const auto level_count = static_cast<std::size_t>(std::floor(std::log2(top / *min_it))) + 1;
  if (level_count > 64)
    throw InputError(fmt::format("the radii span {:.3g} to {:.3g} m, a ratio of {:.3g}; the neighbour grid takes "
                                 "a ratio of at most 2^64", *min_it, top, top / *min_it));
  std::vector<std::size_t> members(level_count, 0);
  for (double r : radii) ++members[level_index(r, top, level_count)];
  std::vector<Level> levels(level_count);
  for (std::size_t l = 0; l < level_count; ++l) {
    Level& level = levels[l];
    level.max_radius = std::ldexp(top, -static_cast<int>(l));
    // A sparse level (few spheres in a large bed) gets cells of about one sphere each.
    // An empty level (a gap in the size range) gets one cell.
    const double sparse_cell = members[l] > 0 ? std::cbrt(bed_volume / static_cast<double>(members[l]))
                                              : std::numeric_limits<double>::infinity();
    const double min_width = std::max(2.0 * level.max_radius, sparse_cell);
    level.nx = cells_along(container.length_x(), min_width);
    level.ny = cells_along(container.length_y(), min_width);
    level.cell_x = container.length_x() / level.nx;
    level.cell_y = container.length_y() / level.ny;
    level.cell_z = std::max(level.cell_x, level.cell_y);
  }
  return levels;
}

MultilevelGrid::MultilevelGrid(const Container& container, std::span<const double> radii, double bed_volume)
    : lo_(container.bounds.lo),
      container_(container),
      period_x_(container.length_x()),
      period_y_(container.length_y()),
      periodic_(container.periodic) {
  if (radii.empty()) return;
  radius_top_ = *std::max_element(radii.begin(), radii.end());
  levels_ = plan_levels(container, radii, bed_volume);
  std::size_t columns = 0;
  for (const Level& level : levels_) columns += static_cast<std::size_t>(level.nx) * level.ny;
  if (columns > kMaxCells) too_many_cells(static_cast<double>(columns), "its footprint");
  for (Level& level : levels_) level.top_layer.assign(static_cast<std::size_t>(level.nx) * level.ny, -1);
}

double MultilevelGrid::cells_needed(const Container& container, std::span<const double> radii, double bed_volume,
                                    double height) {
  if (radii.empty()) return 0.0;
  double cells = 0.0;
  for (const Level& level : plan_levels(container, radii, bed_volume))
    cells += static_cast<double>(level.nx) * level.ny * std::max(1.0, std::ceil(height / level.cell_z));
  return cells;
}

void MultilevelGrid::too_many_cells(double cells, std::string_view what) const {
  throw InputError(fmt::format("the neighbour grid would need {:.3g} cells to cover {} (container {}, spheres of "
                               "radius {:.3g} m and less), more than its limit of {:.3g}: a sphere far from the "
                               "others, or a container far larger than its spheres",
                               cells, what, box_text(container_.bounds), radius_top_, static_cast<double>(kMaxCells)));
}

std::size_t MultilevelGrid::level_index(double radius, double top, std::size_t level_count) {
  if (radius >= top) return 0;
  auto l = static_cast<std::size_t>(std::floor(std::log2(top / radius)));  // top / radius > 1
  // Exact powers of two belong to the finer-indexed (coarser) level: (top/2^(l+1), top/2^l].
  if (std::ldexp(radius, static_cast<int>(l)) == top && l > 0) --l;
  return std::min(l, level_count - 1);
}

std::size_t MultilevelGrid::level_of(double radius) const { return level_index(radius, radius_top_, levels_.size()); }

int MultilevelGrid::column_index(double v, double lo, double width, int n) const {
  double c = std::floor((v - lo) / width);
  if (periodic_) {
    c = std::fmod(c, static_cast<double>(n));
    if (c < 0) c += n;
  }
  return static_cast<int>(std::clamp(c, 0.0, static_cast<double>(n - 1)));
}

int MultilevelGrid::layer_index(double z, const Level& level) const {
  const double c = std::floor((z - lo_.z) / level.cell_z);
  return static_cast<int>(std::clamp(c, -1.0, 1e9));
}

void MultilevelGrid::axis_range(double a, double b, double lo, double width, int n, int& first,
                                int& last) const {
  if (periodic_) {
    first = static_cast<int>(std::floor((a - lo) / width));
    last = static_cast<int>(std::floor((b - lo) / width));
    if (last - first + 1 >= n) first = 0, last = n - 1;
    return;
  }
  first = column_index(a, lo, width, n);
  last = column_index(b, lo, width, n);
}

void MultilevelGrid::insert(std::uint32_t id, const Vec3& centre, double radius) {
  if (levels_.empty() || radius > radius_top_ * (1 + 1e-12))
    throw std::invalid_argument("MultilevelGrid::insert: radius larger than any announced");
  if (id == kEmpty) throw std::length_error("MultilevelGrid: too many spheres");
  Level& level = levels_[level_of(radius)];
  const std::size_t column =
      static_cast<std::size_t>(column_index(centre.y, lo_.y, level.cell_y, level.ny)) * level.nx +
      column_index(centre.x, lo_.x, level.cell_x, level.nx);
  const int iz = std::max(0, layer_index(centre.z, level));
  const std::size_t layer_size = static_cast<std::size_t>(level.nx) * level.ny;
  if (iz >= level.layers()) {
    std::size_t cells = (static_cast<std::size_t>(iz) + 1) * layer_size;
    for (const Level& other : levels_) cells += &other == &level ? 0 : other.head.size();
    if (cells > kMaxCells)
      too_many_cells(static_cast<double>(cells), fmt::format("a sphere at height {:.6g} m", centre.z));
    level.head.resize((static_cast<std::size_t>(iz) + 1) * layer_size, kEmpty);
  }
  if (next_.size() <= id) next_.resize(static_cast<std::size_t>(id) + 1, kEmpty);
  std::uint32_t& head = level.head[iz * layer_size + column];
  next_[id] = head;
  head = id;
  level.top_layer[column] = std::max(level.top_layer[column], iz);
}

std::size_t MultilevelGrid::memory_bytes() const {
  std::size_t bytes = next_.capacity() * sizeof(std::uint32_t);
  for (const Level& level : levels_)
    bytes += level.head.capacity() * sizeof(std::uint32_t) + level.top_layer.capacity() * sizeof(std::int32_t);
  return bytes;
}

}  // namespace aggpack
