// DemSystem's neighbour list: the Morton sort of the records, the list build (with the
// contact history carried over) and the index of its cross-block entries.
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <utility>

#include "aggpack/dynamics/dem_system.hpp"
#include "aggpack/spatial/multilevel_grid.hpp"
#include "dem_system_internal.hpp"

namespace aggpack {
namespace {

using dem_internal::kForceBlock;

// Interleaves the low 21 bits of a, b and c (Morton code).
std::uint64_t spread_bits(std::uint64_t v) {
  v &= 0x1FFFFF;
  v = (v | v << 32) & 0x1F00000000FFFFull;
  v = (v | v << 16) & 0x1F0000FF0000FFull;
  v = (v | v << 8) & 0x100F00F00F00F00Full;
  v = (v | v << 4) & 0x10C30C30C30C30C3ull;
  v = (v | v << 2) & 0x1249249249249249ull;
  return v;
}

}  // namespace

std::vector<std::uint32_t> DemSystem::morton_order() const {
  // Cells of one mean diameter from the container's corner; ties keep the slot order.
  const Vec3 lo = container_.bounds.lo;
  const auto cell = [&](double v, double origin) {
    const double c = std::floor((v - origin) / morton_cell_);
    return static_cast<std::uint64_t>(std::clamp(c, 0.0, double{0x1FFFFF}));
  };
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keys(n_);
#pragma omp parallel for schedule(static) if (threaded_) num_threads(threads_)
  for (std::uint32_t i = 0; i < n_; ++i) {
    const Vec3& x = grain_[i].position;
    keys[i] = {spread_bits(cell(x.x, lo.x)) | spread_bits(cell(x.y, lo.y)) << 1 | spread_bits(cell(x.z, lo.z)) << 2, i};
  }
  std::sort(keys.begin(), keys.end());
  std::vector<std::uint32_t> from(n_);
  for (std::uint32_t s = 0; s < n_; ++s) from[s] = keys[s].second;
  return from;
}

void DemSystem::reorder(const std::vector<std::uint32_t>& from) {
  const auto permute = [&](auto& values) {
    std::remove_reference_t<decltype(values)> reordered(values.size());
    for (std::uint32_t s = 0; s < n_; ++s) reordered[s] = values[from[s]];
    values.swap(reordered);
  };
  permute(grain_);
  permute(user_index_);
  permute(frozen_);
  permute(load_);
  if (!material_.empty()) permute(material_);
  if (!body_of_.empty()) permute(body_of_);
  for (std::uint32_t s = 0; s < n_; ++s) slot_of_[user_index_[s]] = s;
}

void DemSystem::build_neighbour_list() {
  ++rebuilds_;
  // Before the grid is sized by the spheres' extent: a blown-up bed would ask for billions of cells.
  check_not_blown_up();
  const std::uint32_t n = n_;
  if (container_.periodic) {
    // A body's centre into the box, and each member into it as an image of its place.
    for (Body& body : body_) body.position = container_.wrapped(body.position);
    for (std::uint32_t s = 0; s < n; ++s) {
      Grain& g = grain_[s];
      if (!is_member(s)) {
        g.position = container_.wrapped(g.position);
        continue;
      }
      const std::uint32_t i = user_index_[s];
      const Vec3 unwrapped = body_[body_of_[s]].position + arm_[i];
      g.position = container_.wrapped(unwrapped);
      image_[i] = g.position - unwrapped;
    }
  }
  // The old list names the slots before the reorder: new slot s was old slot from[s].
  const std::vector<std::uint32_t> from = morton_order();
  reorder(from);
  std::vector<std::uint32_t> offset, other;
  find_pairs(offset, other);
  std::vector<Vec3> roll;
  std::vector<Vec3> spring = sort_rows_and_carry_springs(from, offset, other, roll);
  offset_.swap(offset);
  other_.swap(other);
  spring_.swap(spring);
  roll_.swap(roll);
  index_cross_block_entries();
  listed_position_.resize(n);
  for (std::uint32_t i = 0; i < n; ++i) listed_position_[i] = grain_[i].position;
  listed_count_ = n;
  listed_offset_ = container_offset();
  listed_tool_tip_ = tool_tip_;
}

void DemSystem::find_pairs(std::vector<std::uint32_t>& offset, std::vector<std::uint32_t>& other) const {
  const std::uint32_t n = n_;
  MultilevelGrid grid(container_, p_.radius, grid_bed_volume_);
  grid.reserve(n);
  for (std::uint32_t i = 0; i < n; ++i) grid.insert(i, grain_[i].position, grain_[i].radius);
  const std::uint32_t wall_count = wall_entries();  // the container's planes, then the rod

  // Calls add(owner, entry) for every pair found from slot i: a neighbour within the skin,
  // unless both are frozen, in the row of the lower slot (its owner); then every wall within
  // the skin of a free slot i. The grid visits a pair of grains of two sizes once, from the
  // smaller (see for_each_near_larger), and a pair of one size from both: the higher slot
  // skips it. The exact test is symmetric in i and j (the reach's sum commutes, the minimum
  // image of -d is -d's), so the pairs are those of a search from every owner.
  const auto for_each_pair = [&](std::uint32_t i, auto&& add) {
    const Vec3& xi = grain_[i].position;
    const double ri = grain_[i].radius;
    grid.for_each_near_larger(xi, ri, ri + skin_, [&](std::uint32_t j, bool same_level) {
      if (j == i || (same_level && j < i) || (frozen_[i] && frozen_[j])) return;
      if (is_member(i) && body_of_[i] == body_of_[j]) return;  // one body: no contact
      const double reach = ri + grain_[j].radius + skin_;
      if (norm2(separation(xi, grain_[j].position)) < reach * reach) add(std::min(i, j), std::max(i, j));
    });
    if (frozen_[i]) return;
    for (std::uint32_t w = 0; w < wall_count; ++w) {
      Vec3 towards;
      if (wall_distance(w, xi, towards) < ri + skin_) add(i, n + w);
    }
  };
  // The grid is searched once: each thread keeps the pairs it finds, (owner, entry). A pair
  // found from i may belong to another thread's row: counts and places are claimed
  // atomically; each row is sorted afterwards, so the list does not depend on who came first.
  // One thread claims with plain adds: the atomics are for the threads' races, which it has none of.
  const std::size_t workers = threaded_ ? static_cast<std::size_t>(std::max(1, threads_)) : 1;
  const auto claim = [alone = workers == 1](std::uint32_t& counter) {
    return alone ? counter++ : std::atomic_ref<std::uint32_t>(counter).fetch_add(1, std::memory_order_relaxed);
  };
  using Pair = std::pair<std::uint32_t, std::uint32_t>;
  std::vector<std::vector<Pair>> pairs_found(workers);
  offset.assign(std::size_t{n} + 1, 0);
#pragma omp parallel if (threaded_) num_threads(threads_)
  {
    std::vector<Pair>& mine = pairs_found[static_cast<std::size_t>(omp_get_thread_num())];
    mine.reserve(other_.size() / workers + other_.size() / (8 * workers));  // the last list's size, and some
#pragma omp for schedule(dynamic, 512)
    for (std::uint32_t i = 0; i < n; ++i)
      for_each_pair(i, [&](std::uint32_t owner, std::uint32_t entry) {
        mine.emplace_back(owner, entry);
        claim(offset[owner + 1]);
      });
  }
  for (std::uint32_t i = 0; i < n; ++i) offset[i + 1] += offset[i];
  other.assign(offset[n], 0);
  {
    std::vector<std::uint32_t> next_free(offset.begin(), offset.end() - 1);
#pragma omp parallel for schedule(static, 1) if (threaded_) num_threads(threads_)
    for (std::size_t t = 0; t < workers; ++t) {
      for (const auto& [owner, entry] : pairs_found[t]) other[claim(next_free[owner])] = entry;
      std::vector<Pair>().swap(pairs_found[t]);
    }
  }
}

std::vector<Vec3> DemSystem::sort_rows_and_carry_springs(const std::vector<std::uint32_t>& from,
                                                         const std::vector<std::uint32_t>& offset,
                                                         std::vector<std::uint32_t>& other,
                                                         std::vector<Vec3>& roll) const {
  const std::uint32_t n = n_;
  std::vector<Vec3> spring(offset[n]);
  roll.assign(rolling_history_ ? offset[n] : 0, Vec3{});
#pragma omp parallel for schedule(dynamic, 512) if (threaded_) num_threads(threads_)
  for (std::uint32_t i = 0; i < n; ++i) {
    const auto row = other.begin() + offset[i], row_end = other.begin() + offset[i + 1];
    std::sort(row, row_end);
    // Carry each contact's tangential history over from the old list, where the pair sat in
    // the row of its lower old slot (as seen from there: the sign flips if the order did).
    // Grains admitted since that list (old slots from listed_count_ on) have no history; the
    // walls' entries were numbered after the old count.
    const std::uint32_t oi = from[i];
    if (oi >= listed_count_) continue;
    for (std::uint32_t k = offset[i]; k < offset[i + 1]; ++k) {
      const std::uint32_t j = other[k];
      const std::uint32_t oj = j < n ? from[j] : listed_count_ + (j - n);
      if (j < n && oj >= listed_count_) continue;
      const std::uint32_t owner = std::min(oi, oj), partner = std::max(oi, oj);
      const auto first = other_.begin() + offset_[owner], last = other_.begin() + offset_[owner + 1];
      const auto found = std::lower_bound(first, last, partner);
      if (found == last || *found != partner) continue;
      const auto old_entry = static_cast<std::size_t>(found - other_.begin());
      const Vec3& old = spring_[old_entry];
      spring[k] = owner == oi ? old : -old;
      // The rolling history is the same from either side: no sign to flip.
      if (rolling_history_) roll[k] = roll_[old_entry];
    }
  }
  return spring;
}

void DemSystem::index_cross_block_entries() {
  const std::uint32_t n = n_;
  cross_begin_.resize(n);
  slot_base_.resize(n);
  reverse_offset_.assign(std::size_t{n} + 1, 0);
  std::vector<std::uint32_t> cross_end(n);  // where the row's walls begin
  std::uint32_t slots = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    const auto row = other_.begin() + offset_[i], row_end = other_.begin() + offset_[i + 1];
    const std::uint32_t block_end = std::min(n, (i / kForceBlock + 1) * kForceBlock);
    cross_begin_[i] = static_cast<std::uint32_t>(std::lower_bound(row, row_end, block_end) - other_.begin());
    cross_end[i] = static_cast<std::uint32_t>(std::lower_bound(row, row_end, n) - other_.begin());
    slot_base_[i] = slots;
    slots += cross_end[i] - cross_begin_[i];
    for (std::uint32_t k = cross_begin_[i]; k < cross_end[i]; ++k) ++reverse_offset_[other_[k] + 1];
  }
  for (std::uint32_t j = 0; j < n; ++j) reverse_offset_[j + 1] += reverse_offset_[j];
  reverse_.resize(slots);
  std::vector<std::uint32_t> filled(reverse_offset_.begin(), reverse_offset_.end() - 1);
  for (std::uint32_t i = 0; i < n; ++i)
    for (std::uint32_t k = cross_begin_[i], slot = slot_base_[i]; k < cross_end[i]; ++k, ++slot)
      reverse_[filled[other_[k]]++] = slot;
  cross_.assign(slots, {});
}

}  // namespace aggpack
