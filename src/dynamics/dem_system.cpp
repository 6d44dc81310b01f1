#include "aggpack/dynamics/dem_system.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <utility>
#include <variant>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/dynamics/contact_batch.hpp"
#include "aggpack/spatial/multilevel_grid.hpp"
#include "core/archive.hpp"

namespace aggpack {
namespace {

constexpr std::size_t kSumBlock = 1024;  // fixed blocks make sums independent of thread count
// Below this many particles a step is too short to pay for waking threads (and on a busy
// machine each barrier can cost a scheduler tick). Results do not depend on it.
constexpr std::uint32_t kThreadedFrom = 1024;
// Slots per force block. Larger blocks leave fewer pairs to the cross-block slots (48 bytes
// each); there must still be several blocks per thread to balance the load. Results depend
// on it (it fixes the summation order), the thread count does not.
constexpr std::uint32_t kForceBlock = 2048;
// Contacts gathered before the law is evaluated on them at once (whole rows: a batch may
// hold more). Enough for the vector kernel's loop to run long; few enough to stay in cache.
constexpr std::size_t kBatchContacts = 64;
// How many list entries ahead the gather prefetches the neighbour's record.
constexpr std::size_t kPrefetchAhead = 6;

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

DemSystem::DemSystem(ParticleStore& particles, const Container& container, const ContactModel& model,
                     const DemSettings& settings, std::vector<std::uint8_t> frozen)
    : p_(particles), container_(container), model_(model), settings_(settings), frozen_(std::move(frozen)) {
  if (!(settings.time_step > 0.0)) throw InputError(fmt::format("time step {} s must be > 0", settings.time_step));
  if (frozen_.empty()) frozen_.assign(particles.size(), 0);
  if (frozen_.size() != particles.size()) throw std::invalid_argument("DemSystem: one frozen flag per particle");
  threads_ = settings.threads > 0 ? settings.threads : omp_get_max_threads();
  skin_ = settings.skin;
  rest_floor_ = container_.bounds.lo.z;
  rest_top_ = container_.bounds.hi.z;
  admit(frozen_);
}

void DemSystem::set_container_motion(const ContainerMotion& motion) {
  motion_ = motion;
  place_container(time_);
}

void DemSystem::place_container(double t) {
  const double offset = motion_.offset(t);
  container_.bounds.lo.z = rest_floor_ + offset;
  container_.bounds.hi.z = rest_top_ + offset;
}

void DemSystem::admit_new_particles() {
  std::vector<std::uint8_t> frozen(frozen_);
  frozen.resize(p_.size(), 0);
  admit(frozen);
}

// Slots n_ .. store size take the store's particles of the same index; the grains already
// in the system keep their slots (and their contact history) until the list build sorts them.
void DemSystem::admit(const std::vector<std::uint8_t>& frozen_by_index) {
  if (p_.size() >= 0xFFFFFFF0u) throw InputError("the dynamics stage holds at most 4e9 particles");
  const std::uint32_t first = n_;
  n_ = static_cast<std::uint32_t>(p_.size());
  threaded_ = n_ >= kThreadedFrom;
  grain_.resize(n_);
  frozen_.resize(n_);
  user_index_.resize(n_);
  slot_of_.resize(n_);
  load_.resize(n_);
  for (std::uint32_t i = first; i < n_; ++i) {
    frozen_[i] = frozen_by_index[i];
    user_index_[i] = slot_of_[i] = i;
    Grain& g = grain_[i];
    g = Grain{};
    g.position = p_.position[i];
    g.radius = p_.radius[i];
    g.mass = p_.mass[i];
    if (frozen_[i]) {
      p_.velocity[i] = {};
      p_.angular_velocity[i] = {};
      continue;
    }
    ++free_count_;
    g.velocity = p_.velocity[i];
    g.angular_velocity = p_.angular_velocity[i];
    g.inverse_inertia = 1.0 / (0.4 * p_.mass[i] * p_.radius[i] * p_.radius[i]);
  }
  // Sizes of the whole system: the skin (unless set, 0.1 of the smallest diameter, kept once
  // chosen), the Morton cell (the mean diameter) and the grid's expected bed volume.
  double r_min = std::numeric_limits<double>::infinity(), d_sum = 0.0, solid = 0.0;
  for (std::uint32_t i = 0; i < n_; ++i) {
    r_min = std::min(r_min, grain_[i].radius);
    d_sum += 2.0 * grain_[i].radius;
    solid += std::pow(grain_[i].radius, 3);
  }
  if (!(skin_ > 0.0) && n_ > 0) skin_ = default_skin(r_min);
  morton_cell_ = n_ > 0 ? d_sum / n_ : 1.0;
  grid_bed_volume_ = 4.0 / 3.0 * std::numbers::pi * solid / 0.5 + 1e-300;  // the spheres at a loose 0.5
  offset_.resize(std::max<std::size_t>(offset_.size(), first + 1), 0);
  batches_.resize(threaded_ ? static_cast<std::size_t>(std::max(1, threads_)) : 1);
  build_neighbour_list();
  if (first == 0) {
    compute_forces();
    return;
  }
  // Forces are not recomputed: that would advance every contact's spring a second time in
  // this step. The old grains' loads stand (the reorder carried them), and a new grain, which
  // must touch nothing (checked over every list entry it is in), feels its weight alone.
  const auto is_new = [&](std::uint32_t slot) { return user_index_[slot] >= first; };
  for (std::uint32_t s = 0; s < n_; ++s) {
    if (is_new(s)) load_[s] = {frozen_[s] ? Vec3{} : grain_[s].mass * settings_.gravity, {}};
    for (std::uint32_t k = offset_[s]; k < offset_[s + 1]; ++k) {
      const std::uint32_t j = other_[k];
      if (!is_new(s) && (j >= n_ || !is_new(j))) continue;
      Vec3 towards;
      const double gap = j < n_ ? norm(separation(grain_[s].position, grain_[j].position)) - grain_[s].radius -
                                      grain_[j].radius
                                : container_.plane_distance(j - n_, grain_[s].position, towards) - grain_[s].radius;
      if (gap < 0.0)
        throw std::invalid_argument(fmt::format("DemSystem: admitted particle {} touches another particle or a wall",
                                                is_new(s) ? user_index_[s] : user_index_[j]));
    }
  }
}

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
  for (std::uint32_t s = 0; s < n_; ++s) slot_of_[user_index_[s]] = s;
}

void DemSystem::write_back() {
#pragma omp parallel for schedule(static) if (threaded_) num_threads(threads_)
  for (std::uint32_t s = 0; s < n_; ++s) {
    const std::uint32_t i = user_index_[s];
    p_.position[i] = grain_[s].position;
    p_.velocity[i] = grain_[s].velocity;
    p_.angular_velocity[i] = grain_[s].angular_velocity;
  }
}

void DemSystem::check_not_blown_up() const {
  const double dt = settings_.time_step;
  const Box& b = container_.bounds;  // where the container is now (a tap moves it)
  for (std::uint32_t s = 0; s < n_; ++s) {
    if (frozen_[s]) continue;
    const Grain& g = grain_[s];
    const std::size_t user = user_index_[s];
    const double step = std::sqrt(norm2(g.velocity)) * dt;
    if (!(step <= g.radius))
      throw DemBlowUp(fmt::format("at {:.4g} s simulated, sphere {} (radius {:.3g} m) moved {:.3g} m in one time step, more "
                                  "than its radius: no contact resolves that",
                                  time_, user, g.radius, step));
    if (g.position.z < b.lo.z - g.radius)
      throw DemBlowUp(fmt::format("at {:.4g} s simulated, sphere {} went through the floor (its centre at z = {:.4g} m, the "
                                  "floor at {:.4g} m)",
                                  time_, user, g.position.z, b.lo.z));
    if (!container_.periodic &&
        (g.position.x < b.lo.x || g.position.x > b.hi.x || g.position.y < b.lo.y || g.position.y > b.hi.y))
      throw DemBlowUp(fmt::format("at {:.4g} s simulated, sphere {} went through a side wall (its centre at x = {:.4g}, y = "
                                  "{:.4g} m)",
                                  time_, user, g.position.x, g.position.y));
  }
}

void DemSystem::build_neighbour_list() {
  ++rebuilds_;
  // Before the grid is sized by the spheres' extent: a blown-up bed would ask for billions of cells.
  check_not_blown_up();
  const std::uint32_t n = n_;
  if (container_.periodic)
    for (Grain& g : grain_) g.position = container_.wrapped(g.position);
  // The old list names the slots before the reorder: new slot s was old slot from[s].
  const std::vector<std::uint32_t> from = morton_order();
  reorder(from);
  MultilevelGrid grid(container_, p_.radius, grid_bed_volume_);
  grid.reserve(n);
  for (std::uint32_t i = 0; i < n; ++i) grid.insert(i, grain_[i].position, grain_[i].radius);
  const std::uint32_t wall_count = container_.plane_count();

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
      const double reach = ri + grain_[j].radius + skin_;
      if (norm2(separation(xi, grain_[j].position)) < reach * reach) add(std::min(i, j), std::max(i, j));
    });
    if (frozen_[i]) return;
    for (std::uint32_t w = 0; w < wall_count; ++w) {
      Vec3 towards;
      if (container_.plane_distance(w, xi, towards) < ri + skin_) add(i, n + w);
    }
  };
  // The grid is searched once: each thread keeps the pairs it finds, (owner, entry). A pair
  // found from i may belong to another thread's row: counts and places are claimed
  // atomically; each row is sorted afterwards, so the list does not depend on who came first.
  const auto claim = [](std::uint32_t& counter) {
    return std::atomic_ref<std::uint32_t>(counter).fetch_add(1, std::memory_order_relaxed);
  };
  using Pair = std::pair<std::uint32_t, std::uint32_t>;
  const std::size_t workers = threaded_ ? static_cast<std::size_t>(std::max(1, threads_)) : 1;
  std::vector<std::vector<Pair>> pairs_found(workers);
  std::vector<std::uint32_t> offset(n + 1, 0);
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
  std::vector<std::uint32_t> other(offset[n]);
  {
    std::vector<std::uint32_t> next_free(offset.begin(), offset.end() - 1);
#pragma omp parallel for schedule(static, 1) if (threaded_) num_threads(threads_)
    for (std::size_t t = 0; t < workers; ++t) {
      for (const auto& [owner, entry] : pairs_found[t]) other[claim(next_free[owner])] = entry;
      std::vector<Pair>().swap(pairs_found[t]);
    }
  }
  std::vector<Vec3> spring(offset[n]);
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
      const Vec3& old = spring_[static_cast<std::size_t>(found - other_.begin())];
      spring[k] = owner == oi ? old : -old;
    }
  }
  offset_.swap(offset);
  other_.swap(other);
  spring_.swap(spring);
  index_cross_block_entries();
  listed_position_.resize(n);
  for (std::uint32_t i = 0; i < n; ++i) listed_position_[i] = grain_[i].position;
  listed_count_ = n;
  listed_offset_ = container_offset();
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

std::uint32_t DemSystem::gather_contacts(ContactBatch& batch, std::uint32_t first_row, std::uint32_t block_end,
                                         bool spin_needed) {
  using C = ContactBatch;
  const std::uint32_t n = n_;
  const Grain* grain = grain_.data();
  const ForceTorque* load = load_.data();
  Vec3* spring = spring_.data();
  const std::uint32_t* offset = offset_.data();
  const std::uint32_t* other = other_.data();
  const std::size_t entries = other_.size();
  batch.clear();
  std::uint32_t i = first_row;
  for (; i < block_end && batch.size < kBatchContacts; ++i) {
    const Grain& gi = grain[i];
    batch.reserve_more(offset[i + 1] - offset[i]);
    std::uint32_t* const entry = batch.entry.data();
    const std::size_t row_begin = batch.size;
    std::size_t k = row_begin;
    // Pass 1, every particle entry: the separation, kept when the grains touch. Every entry
    // is written at slot k and k moves on only for a contact: whether two grains touch is
    // close to a coin toss in a bed, and a branch on it mispredicts a third of the time.
    // A spring left out is reset here; the scatter writes back the kept ones.
    {
      const Vec3 xi = gi.position;
      const double ri = gi.radius;
      std::uint32_t e = offset[i];
      for (; e < offset[i + 1] && other[e] < n; ++e) {
        // The neighbours' records: ask for the ones a few entries ahead now, and for their
        // force slots, which the scatter adds to.
        if (e + kPrefetchAhead < entries) {
          const std::uint32_t ahead = other[e + kPrefetchAhead];
          if (ahead < n) {
            __builtin_prefetch(&grain[ahead]);
            __builtin_prefetch(reinterpret_cast<const char*>(&grain[ahead]) + 64);
            // Only this block's force slots: another block's may be in another core's cache.
            if (ahead < block_end) __builtin_prefetch(&load[ahead], 1);
          }
        }
        const Grain& gj = grain[other[e]];
        const Vec3 d = separation(xi, gj.position);
        const double reach = ri + gj.radius;
        const double d2 = norm2(d);
        double* const slot = batch.contact(k);
        entry[k] = e;
        C::put3(slot, C::kDx, d);
        slot[C::kDistance2 * C::kGroup] = d2;
        C::put3(slot, C::kUx, spring[e]);
        spring[e] = {};
        k += d2 < reach * reach ? 1 : 0;
      }
      batch.rows.push_back({static_cast<std::uint32_t>(k), e});
    }
    // Pass 2, the contacts kept: their grains' sizes, masses and motion.
    const Vec3 vi = gi.velocity, wi = gi.angular_velocity;
    const double ri = gi.radius, mi = gi.mass;
    const Vec3 spin_i = ri * wi;
    for (std::size_t c = row_begin; c < k; ++c) {
      const Grain& gj = grain[other[entry[c]]];
      double* const slot = batch.contact(c);
      slot[C::kRadiusI * C::kGroup] = ri;
      slot[C::kRadiusJ * C::kGroup] = gj.radius;
      slot[C::kMassI * C::kGroup] = mi;
      slot[C::kMassJ * C::kGroup] = gj.mass;
      C::put3(slot, C::kVx, vi - gj.velocity);
      C::put3(slot, C::kSx, spin_i + gj.radius * gj.angular_velocity);
      if (spin_needed) C::put3(slot, C::kWx, wi - gj.angular_velocity);
    }
    batch.size = k;
  }
  return i;
}

template <class Law>
void DemSystem::scatter_contacts(const ContactBatch& batch, std::uint32_t first_row, std::uint32_t last_row,
                                 const Law& wall_law) {
  using C = ContactBatch;
  const std::uint32_t n = n_;
  const double dt = settings_.time_step;
  ForceTorque* load = load_.data();
  Vec3* spring = spring_.data();
  const std::uint32_t* offset = offset_.data();
  const std::uint32_t* other = other_.data();
  const std::uint32_t* const entry = batch.entry.data();
  std::size_t k = 0;
  for (std::uint32_t i = first_row; i < last_row; ++i) {
    const ContactBatch::Row& row = batch.rows[i - first_row];
    Vec3 f{}, t{};
    // The row's cross-block slots: zero unless a contact fills them below.
    const std::uint32_t cross_begin = cross_begin_[i];
    ForceTorque* const row_cross = cross_.data() + slot_base_[i];
    std::fill(row_cross, row_cross + (row.walls_begin - cross_begin), ForceTorque{});
    for (; k < row.contacts_end; ++k) {
      const std::uint32_t e = entry[k];
      const double* const slot = batch.contact(k);
      const Vec3 pair_force = C::get3(slot, C::kFx), torque_j = C::get3(slot, C::kTjx);
      spring[e] = C::get3(slot, C::kUx);
      f += pair_force;
      t += C::get3(slot, C::kTix);
      if (e >= cross_begin) {
        row_cross[e - cross_begin] = {-pair_force, torque_j};
      } else {
        const std::uint32_t j = other[e];
        load[j].force += -pair_force;
        load[j].torque += torque_j;
      }
    }
    // The walls, one at a time (few, and each with the wall law's coefficients).
    const Grain& gi = grain_[i];
    const Vec3 xi = gi.position, vi = gi.velocity, wi = gi.angular_velocity;
    const double ri = gi.radius, mi = gi.mass;
    for (std::uint32_t e = row.walls_begin; e < offset[i + 1]; ++e) {
      const std::uint32_t wall = other[e] - n;
      ContactKinematics kin;
      const double distance = container_.plane_distance(wall, xi, kin.normal);
      if (distance >= ri) {
        spring[e] = {};
        continue;
      }
      kin.overlap = ri - distance;
      // The wall's own motion (at rest today; a tapped container moves) enters the contact.
      kin.velocity = vi - Container::plane_velocity(wall, motion_, force_time_) + cross(ri * wi, kin.normal);
      kin.spin = wi;
      kin.r_eff = ri;
      kin.m_eff = mi;
      const ContactForce c = wall_law.evaluate(kin, spring[e], dt);
      f += c.force;
      t += ri * cross(kin.normal, c.tangential) + c.rolling_torque;
    }
    load[i].force += f;
    load[i].torque += t;
  }
}

template <class Law>
void DemSystem::compute_forces(const Law& particle_law, const Law& wall_law) {
  const std::uint32_t n = n_;
  const std::uint32_t blocks = (n + kForceBlock - 1) / kForceBlock;
  const bool spin_needed = particle_law.c.rolling != 0.0;  // only rolling resistance reads w_i - w_j
#pragma omp parallel if (threaded_) num_threads(threads_)
  {
    ContactBatch& batch = batches_[static_cast<std::size_t>(omp_get_thread_num())];
#pragma omp for schedule(dynamic, 1)
    for (std::uint32_t b = 0; b < blocks; ++b) {
      const std::uint32_t begin = b * kForceBlock, end = std::min(n, begin + kForceBlock);
      for (std::uint32_t i = begin; i < end; ++i)
        load_[i] = {frozen_[i] ? Vec3{} : grain_[i].mass * settings_.gravity, {}};
      // Whole rows at a time: gather their contacts, evaluate the law on all of them, then
      // add the results in row and entry order, the fixed order of every sum.
      for (std::uint32_t first_row = begin; first_row < end;) {
        const std::uint32_t last_row = gather_contacts(batch, first_row, end, spin_needed);
        evaluate(particle_law, batch, settings_.time_step);
        scatter_contacts(batch, first_row, last_row, wall_law);
        first_row = last_row;
      }
    }
    // Every slot gathers what earlier blocks put on it, in ascending order of their rows.
#pragma omp for schedule(static)
    for (std::uint32_t j = 0; j < n; ++j) {
      if (frozen_[j]) {
        load_[j] = {};
        continue;
      }
      Vec3 f{}, t{};
      for (std::uint32_t r = reverse_offset_[j]; r < reverse_offset_[j + 1]; ++r) {
        f += cross_[reverse_[r]].force;
        t += cross_[reverse_[r]].torque;
      }
      load_[j].force += f;
      load_[j].torque += t;
    }
  }
}

void DemSystem::compute_forces() {
  std::visit(
      [&](const auto& particle_law) {
        using Law = std::decay_t<decltype(particle_law)>;
        compute_forces(particle_law, std::get<Law>(model_.wall));
      },
      model_.particle);
}

void DemSystem::kick(double half_step) {
#pragma omp parallel for schedule(static) if (threaded_) num_threads(threads_)
  for (std::uint32_t i = 0; i < n_; ++i) {
    if (frozen_[i]) continue;
    Grain& g = grain_[i];
    g.velocity += load_[i].force * (half_step / g.mass);
    g.angular_velocity += load_[i].torque * (half_step * g.inverse_inertia);
  }
}

bool DemSystem::drift(double slack) {
  const double dt = settings_.time_step;
  // Moved more than half the skin (less what the container moved: a wall may come closer).
  const double reach = 0.5 * skin_ - slack;
  const double limit = reach > 0.0 ? reach * reach : -1.0;  // -1: rebuild now
  bool stale = false, lost = false;
#pragma omp parallel for schedule(static) reduction(|| : stale, lost) if (threaded_) num_threads(threads_)
  for (std::uint32_t i = 0; i < n_; ++i) {
    grain_[i].position += grain_[i].velocity * dt;
    const double moved = norm2(grain_[i].position - listed_position_[i]);
    if (moved > limit) stale = true;
    if (!std::isfinite(moved)) lost = true;
  }
  // A position that is no longer a number cannot be sorted or put in a cell (a cast of NaN).
  if (lost)
    throw DemBlowUp(fmt::format("the DEM diverged at {:.6g} s simulated (a sphere's position is no longer finite): "
                                 "its time step is too large for its contacts, or it started from a state no run "
                                 "reaches",
                                 time_));
  return stale;
}

void DemSystem::run(std::size_t steps) {
  const double half = 0.5 * settings_.time_step;
  for (std::size_t s = 0; s < steps; ++s) {
    kick(half);
    // The forces of the new positions are those at the end of the step, with the container
    // (when it moves) where it is then.
    force_time_ = static_cast<double>(steps_ + 1) * settings_.time_step;
    double slack = 0.0;
    if (motion_.amplitude != 0.0) {
      place_container(force_time_);
      slack = std::abs(container_offset() - listed_offset_);
    }
    if (drift(slack)) build_neighbour_list();
    compute_forces();
    kick(half);
    ++steps_;
    time_ = static_cast<double>(steps_) * settings_.time_step;
  }
  write_back();
}

DemSystem::KineticEnergy DemSystem::kinetic_energy() const {
  const std::size_t blocks = (n_ + kSumBlock - 1) / kSumBlock;
  std::vector<KineticEnergy> partial(blocks);
#pragma omp parallel for schedule(static) if (threaded_) num_threads(threads_)
  for (std::size_t b = 0; b < blocks; ++b) {
    KineticEnergy sum;
    const std::size_t end = std::min<std::size_t>(n_, (b + 1) * kSumBlock);
    for (std::size_t i = b * kSumBlock; i < end; ++i) {
      if (frozen_[i]) continue;
      const Grain& g = grain_[i];
      sum.translational += 0.5 * g.mass * norm2(g.velocity);
      sum.rotational += 0.5 * norm2(g.angular_velocity) / g.inverse_inertia;
    }
    partial[b] = sum;
  }
  KineticEnergy total;
  for (const KineticEnergy& s : partial) {
    total.translational += s.translational;
    total.rotational += s.rotational;
  }
  return total;
}

ContactStatistics DemSystem::contact_statistics() const {
  // Sums over fixed blocks, then in block order: independent of the thread count.
  struct Partial {
    double overlap_sum = 0.0, max_overlap = 0.0;
    std::size_t contacts = 0;
  };
  const std::size_t blocks = (n_ + kSumBlock - 1) / kSumBlock;
  std::vector<Partial> partial(blocks);
#pragma omp parallel for schedule(static) if (threaded_) num_threads(threads_)
  for (std::size_t b = 0; b < blocks; ++b) {
    Partial s;
    const std::size_t end = std::min<std::size_t>(n_, (b + 1) * kSumBlock);
    for (std::size_t i = b * kSumBlock; i < end; ++i) {
      const double ri = grain_[i].radius;
      const Vec3& xi = grain_[i].position;
      for (std::uint32_t e = offset_[i]; e < offset_[i + 1]; ++e) {
        const std::uint32_t j = other_[e];
        double overlap, diameter;
        if (j < n_) {
          diameter = ri + grain_[j].radius;
          overlap = diameter - norm(separation(xi, grain_[j].position));
        } else {
          Vec3 towards;
          diameter = 2.0 * ri;
          overlap = ri - container_.plane_distance(j - n_, xi, towards);
        }
        if (overlap <= 0.0) continue;
        s.max_overlap = std::max(s.max_overlap, overlap / diameter);
        if (j < n_) {
          // Once for each free grain of the pair (the frozen layers below are not counted).
          const std::size_t sides = (frozen_[i] ? 0 : 1) + (frozen_[j] ? 0 : 1);
          s.overlap_sum += static_cast<double>(sides) * (overlap / diameter);
          s.contacts += sides;
        }
      }
    }
    partial[b] = s;
  }
  Partial total;
  for (const Partial& s : partial) {
    total.overlap_sum += s.overlap_sum;
    total.max_overlap = std::max(total.max_overlap, s.max_overlap);
    total.contacts += s.contacts;
  }
  ContactStatistics stats;
  stats.contacts = total.contacts;
  stats.max_overlap = total.max_overlap;
  if (total.contacts > 0) stats.mean_overlap = total.overlap_sum / static_cast<double>(total.contacts);
  if (free_count_ > 0) stats.coordination = static_cast<double>(total.contacts) / static_cast<double>(free_count_);
  return stats;
}

std::size_t DemSystem::memory_bytes() const {
  std::size_t batches = 0;
  for (const ContactBatch& b : batches_) batches += b.memory_bytes();
  return grain_.capacity() * sizeof(Grain) + frozen_.capacity() +
         (listed_position_.capacity() + spring_.capacity()) * sizeof(Vec3) +
         (load_.capacity() + cross_.capacity()) * sizeof(ForceTorque) +
         (user_index_.capacity() + slot_of_.capacity() + offset_.capacity() + cross_begin_.capacity() +
          other_.capacity() + slot_base_.capacity() + reverse_offset_.capacity() + reverse_.capacity()) *
             sizeof(std::uint32_t) +
         batches;
}

void DemSystem::finish() {
  if (container_.periodic)
    for (std::uint32_t i = 0; i < n_; ++i) p_.position[i] = container_.wrapped(p_.position[i]);
}

namespace {
constexpr std::uint32_t kStateFormat = 2;  // raise when the members below change
}  // namespace

// The members in one list for saving and restoring. Not saved: the model and the settings
// (the scenario's), the thread count and the per-thread batches (they do not change results),
// and what follows from the list (its cross-block slots: index_cross_block_entries()).
template <class Archive, class System>
void DemSystem::archive_state(Archive& ar, System& s) {
  ar(raw_value(s.container_), s.skin_, s.grid_bed_volume_, s.morton_cell_, s.n_, s.listed_count_, s.free_count_);
  ar(raw(s.grain_), raw(s.user_index_), raw(s.slot_of_), raw(s.frozen_), raw(s.load_), raw(s.listed_position_));
  ar(raw(s.offset_), raw(s.other_), raw(s.spring_));
  ar(s.time_, s.force_time_, raw_value(s.motion_), s.rest_floor_, s.rest_top_, s.listed_offset_, s.steps_,
     s.rebuilds_);
}

void DemSystem::save_state(std::ostream& out) const {
  cereal::BinaryOutputArchive ar(out);
  ar(kStateFormat, static_cast<std::uint64_t>(p_.size()));
  archive_state(ar, *this);
}

void DemSystem::restore_state(std::string_view bytes) {
  // What the system was made with (the scenario's container and settings, the store's
  // particles): the restored state must agree with it.
  MadeWith made{container_, skin_, grid_bed_volume_, morton_cell_, rest_floor_, rest_top_,
                std::vector<std::uint8_t>(n_)};
  for (std::uint32_t s = 0; s < n_; ++s) made.frozen_by_index[user_index_[s]] = frozen_[s];
  try {
    CheckedInputArchive ar(bytes);
    std::uint32_t format = 0;
    std::uint64_t particles = 0;
    ar(format, particles);
    if (format != kStateFormat || particles != p_.size())
      throw InputError(fmt::format("the DEM state is of format {} for {} particles; this system is of format {} "
                                   "with {}", format, particles, kStateFormat, p_.size()));
    archive_state(ar, *this);
    if (ar.left() > 0) throw InputError(fmt::format("the DEM state has {} bytes after its end", ar.left()));
  } catch (const cereal::Exception& e) {
    throw InputError(fmt::format("the DEM state is truncated or damaged ({})", e.what()));
  }
  check_restored(made);
  index_cross_block_entries();
  threaded_ = n_ >= kThreadedFrom;
  batches_.assign(threaded_ ? static_cast<std::size_t>(std::max(1, threads_)) : 1, ContactBatch{});
}

void DemSystem::check_restored(const MadeWith& made) const {
  const auto fail = [](std::string_view what) {
    throw InputError(fmt::format("the DEM state does not fit its run: {}", what));
  };
  const auto finite = [](const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  const std::uint32_t n = n_;
  // The container: the scenario's, moved up or down by its motion only. Its flag is read as a
  // byte first: any other value than 0 or 1 in a bool is undefined behaviour.
  unsigned char periodic = 0;
  std::memcpy(&periodic, &container_.periodic, 1);
  const Box &box = container_.bounds, &made_box = made.container.bounds;
  if (periodic != (made.container.periodic ? 1 : 0) || box.lo.x != made_box.lo.x || box.hi.x != made_box.hi.x ||
      box.lo.y != made_box.lo.y || box.hi.y != made_box.hi.y || rest_floor_ != made.rest_floor ||
      rest_top_ != made.rest_top)
    fail("its container is not the scenario's");
  if (!std::isfinite(motion_.start) || !std::isfinite(motion_.amplitude) || !std::isfinite(motion_.angular_frequency) ||
      !std::isfinite(motion_.cycles) || !std::isfinite(listed_offset_))
    fail("the container's motion");
  // Time is counted in steps; the container stands where its motion has it then.
  if (time_ != static_cast<double>(steps_) * settings_.time_step || force_time_ != time_)
    fail(fmt::format("its time, {} s, is not its {} steps of {} s", time_, steps_, settings_.time_step));
  const double offset = motion_.offset(time_);
  if (box.lo.z != rest_floor_ + offset || box.hi.z != rest_top_ + offset) fail("the container's height");
  // The sizes the system chose from the store's radii (summed in another order: nearly equal).
  const auto near = [](double a, double b) { return std::abs(a - b) <= 1e-9 * std::abs(b); };
  if (skin_ != made.skin || !near(grid_bed_volume_, made.bed_volume) || !near(morton_cell_, made.morton_cell))
    fail("its skin or grid sizes are not those of its particles");

  // The records: one per particle, each slot a particle of the store, the inverse table its
  // inverse, and each record the store's particle (the store is written back at every safe point).
  if (listed_count_ != n || grain_.size() != n || user_index_.size() != n || slot_of_.size() != n ||
      frozen_.size() != n || load_.size() != n || listed_position_.size() != n)
    fail("its tables are not one entry per particle");
  std::size_t free = 0;
  for (std::uint32_t s = 0; s < n; ++s) {
    const std::uint32_t i = user_index_[s];
    if (i >= n || slot_of_[i] != s) fail(fmt::format("slot {} names particle {}, not a permutation", s, i));
    if (frozen_[s] != made.frozen_by_index[i]) fail(fmt::format("particle {} is frozen where the run has it free, or the reverse", i));
    free += frozen_[s] ? 0 : 1;
    const Grain& g = grain_[s];
    const double inverse_inertia = frozen_[s] ? 0.0 : 1.0 / (0.4 * p_.mass[i] * p_.radius[i] * p_.radius[i]);
    if (!finite(g.position) || !(g.position == p_.position[i] || g.position == made.container.wrapped(p_.position[i])) ||
        !(g.velocity == p_.velocity[i]) || !(g.angular_velocity == p_.angular_velocity[i]) ||
        g.radius != p_.radius[i] || g.mass != p_.mass[i] || g.inverse_inertia != inverse_inertia)
      fail(fmt::format("the record of particle {} is not the particle", i));
    if (!finite(listed_position_[s]) || !finite(load_[s].force) || !finite(load_[s].torque))
      fail(fmt::format("the forces or the listed position of particle {}", i));
  }
  if (free != free_count_) fail("its count of free particles");

  // The half neighbour list: rows of ascending entries, each a later slot or a wall.
  const std::uint32_t walls = container_.plane_count();
  if (offset_.size() != std::size_t{n} + 1 || offset_[0] != 0 || offset_[n] != other_.size() ||
      spring_.size() != other_.size())
    fail("its neighbour list's rows");
  for (std::uint32_t i = 0; i < n; ++i) {
    if (offset_[i + 1] < offset_[i]) fail(fmt::format("its neighbour list's row {}", i));
    for (std::uint32_t k = offset_[i]; k < offset_[i + 1]; ++k) {
      const std::uint32_t j = other_[k];
      const bool both_frozen = j < n ? frozen_[i] && frozen_[j] : frozen_[i] != 0;
      if (j <= i || j >= n + walls || (k > offset_[i] && j < other_[k - 1]) || both_frozen || !finite(spring_[k]))
        fail(fmt::format("its neighbour list's entry {} of row {}", k - offset_[i], i));
    }
  }
}

}  // namespace aggpack
