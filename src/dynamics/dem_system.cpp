#include "aggpack/dynamics/dem_system.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <variant>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/dynamics/contact_batch.hpp"
#include "dem_system_internal.hpp"

namespace aggpack {
namespace {

using dem_internal::kForceBlock;
using dem_internal::kThreadedFrom;
// Contacts gathered before the law is evaluated on them at once (whole rows: a batch may
// hold more). Enough for the vector kernel's loop to run long; few enough to stay in cache.
constexpr std::size_t kBatchContacts = 64;
// How many list entries ahead the gather prefetches the neighbour's record.
constexpr std::size_t kPrefetchAhead = 6;

}  // namespace

DemSystem::DemSystem(ParticleStore& particles, const Container& container, const ContactModel& model,
                     const DemSettings& settings, std::vector<std::uint8_t> frozen)
    : p_(particles), container_(container), model_(model), settings_(settings), frozen_(std::move(frozen)) {
  if (!(settings.time_step > 0.0)) throw InputError(fmt::format("time step {} s must be > 0", settings.time_step));
  if (frozen_.empty()) frozen_.assign(particles.size(), 0);
  if (frozen_.size() != particles.size()) throw std::invalid_argument("DemSystem: one frozen flag per particle");
  governor_ = ThreadGovernor(settings.threads > 0 ? settings.threads : omp_get_max_threads());
  threads_ = governor_.most();
  // Of any pair of materials (one material: its own pair and the walls').
  const auto any_law = [&](auto&& property) {
    bool any = false;
    for (const auto* laws : {&model_.pairs, &model_.walls})
      for (const ContactLaw& law : *laws) any = any || std::visit(property, law);
    return any || std::visit(property, model_.particle) || std::visit(property, model_.wall);
  };
  rolling_history_ = any_law([](const auto& law) { return law.c.rolling_history(); });
  rolling_resistance_ = any_law([](const auto& law) { return law.c.rolling != 0.0; });
  if (model_.materials > 1 && (model_.pairs.size() != model_.materials * model_.materials ||
                               model_.walls.size() != model_.materials))
    throw std::invalid_argument("DemSystem: a model of several materials needs a law per pair and per material");
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
  use_threads(threads_);  // the bed's size decides whether the loops are threaded
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
  read_materials();
  admit_bodies(first);
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
  batches_.resize(static_cast<std::size_t>(governor_.most()));
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
    if (is_new(s)) load_[s] = {frozen_[s] || is_member(s) ? Vec3{} : grain_[s].mass * settings_.gravity, {}};
    for (std::uint32_t k = offset_[s]; k < offset_[s + 1]; ++k) {
      const std::uint32_t j = other_[k];
      if (!is_new(s) && (j >= n_ || !is_new(j))) continue;
      Vec3 towards;
      const double gap = j < n_ ? norm(separation(grain_[s].position, grain_[j].position)) - grain_[s].radius -
                                      grain_[j].radius
                                : wall_distance(j - n_, grain_[s].position, towards) - grain_[s].radius;
      if (gap < 0.0)
        throw std::invalid_argument(fmt::format("DemSystem: admitted particle {} touches another particle or a wall",
                                                is_new(s) ? user_index_[s] : user_index_[j]));
    }
  }
}

void DemSystem::read_materials() {
  if (model_.materials == 1) return;
  material_.resize(n_);
  for (std::uint32_t s = 0; s < n_; ++s) {
    const std::uint32_t i = user_index_[s];
    material_[s] = i < p_.material.size() ? p_.material[i] : 0;
    if (material_[s] >= model_.materials)
      throw std::invalid_argument(fmt::format("DemSystem: particle {} is of material {}, the model has {}", i,
                                              material_[s], model_.materials));
  }
}

void DemSystem::write_back() {
#pragma omp parallel for schedule(static) if (threaded_) num_threads(threads_)
  for (std::uint32_t s = 0; s < n_; ++s) {
    const std::uint32_t i = user_index_[s];
    p_.position[i] = grain_[s].position;
    p_.velocity[i] = grain_[s].velocity;
    p_.angular_velocity[i] = grain_[s].angular_velocity;
  }
  RigidBodies& bodies = p_.bodies;
  for (std::size_t b = 0; b < body_.size(); ++b) {
    bodies.position[b] = body_[b].position;
    bodies.orientation[b] = body_[b].orientation;
    bodies.velocity[b] = body_[b].velocity;
    bodies.angular_velocity[b] = body_[b].angular_velocity;
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
    if (!container_.holds_horizontally(g.position))
      throw DemBlowUp(fmt::format("at {:.4g} s simulated, sphere {} went through a side wall (its centre at x = {:.4g}, y = "
                                  "{:.4g} m)",
                                  time_, user, g.position.x, g.position.y));
  }
}

std::uint32_t DemSystem::gather_contacts(ContactBatch& batch, std::uint32_t first_row, std::uint32_t block_end,
                                         bool spin_needed) {
  using C = ContactBatch;
  const std::uint32_t n = n_;
  const Grain* grain = grain_.data();
  const ForceTorque* load = load_.data();
  Vec3* spring = spring_.data();
  Vec3* roll = roll_.data();  // empty unless the law keeps a rolling history
  const bool rolling_history = rolling_history_;
  const std::uint32_t* offset = offset_.data();
  const std::uint32_t* other = other_.data();
  const std::size_t entries = other_.size();
  const std::uint8_t* material = material_.data();  // several materials only
  batch.clear();
  std::uint32_t i = first_row;
  for (; i < block_end && batch.size < kBatchContacts; ++i) {
    const Grain& gi = grain[i];
    batch.reserve_more(offset[i + 1] - offset[i]);
    if (material != nullptr) batch.pair.resize(batch.entry.size());
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
        if (rolling_history) {
          C::put3(slot, C::kHx, roll[e]);
          roll[e] = {};
        }
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
      if (material != nullptr)
        batch.pair[c] = static_cast<std::uint16_t>(material[i] * model_.materials + material[other[entry[c]]]);
    }
    batch.size = k;
  }
  return i;
}

template <class Law>
void DemSystem::scatter_contacts(const ContactBatch& batch, std::uint32_t first_row, std::uint32_t last_row,
                                 const Law& own_wall_law) {
  using C = ContactBatch;
  const std::uint32_t n = n_;
  const double dt = settings_.time_step;
  ForceTorque* load = load_.data();
  Vec3* spring = spring_.data();
  Vec3* roll = roll_.data();
  const bool rolling_history = rolling_history_;
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
      if (rolling_history) roll[e] = C::get3(slot, C::kHx);
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
    // The walls, one at a time (few, and each with the wall law's coefficients: its material's).
    const Law& wall_law = material_.empty() ? own_wall_law : std::get<Law>(model_.walls[material_[i]]);
    const Grain& gi = grain_[i];
    const Vec3 xi = gi.position, vi = gi.velocity, wi = gi.angular_velocity;
    const double ri = gi.radius, mi = gi.mass;
    const unsigned planes = container_.plane_count();  // the rod's entry follows the planes
    for (std::uint32_t e = row.walls_begin; e < offset[i + 1]; ++e) {
      const std::uint32_t wall = other[e] - n;
      const bool rod = wall == planes;
      ContactKinematics kin;
      const double distance = wall_distance(wall, xi, kin.normal);
      Vec3 no_history{};
      Vec3& rolling = rolling_history ? roll[e] : no_history;
      if (distance >= ri) {
        spring[e] = {};
        rolling = {};
        continue;
      }
      kin.overlap = ri - distance;
      // The wall's own motion (a tapped container, the driven rod) enters the contact.
      const Vec3 wall_velocity = rod ? tool_velocity_ : Container::plane_velocity(wall, motion_, force_time_);
      kin.velocity = vi - wall_velocity + cross(ri * wi, kin.normal);
      kin.spin = wi;
      // The rod: a sphere of its radius at the tip (exact there), an approximation on its shaft;
      // a cylinder's concave wall: its own effective radius.
      kin.r_eff = rod ? ri * tool_->radius / (ri + tool_->radius) : container_.wall_contact_radius(wall, ri);
      kin.m_eff = mi;  // the walls and the rod are infinitely massive
      const ContactForce c = wall_law.evaluate(kin, spring[e], rolling, dt);
      f += c.force;
      t += ri * cross(kin.normal, c.tangential) + c.rolling_torque;
      if (rod) tool_block_force_[i / dem_internal::kForceBlock] += -c.force;
    }
    load[i].force += f;
    load[i].torque += t;
  }
}

template <class Law>
void DemSystem::compute_forces(const Law& particle_law, const Law& wall_law) {
  const std::uint32_t n = n_;
  const std::uint32_t blocks = (n + kForceBlock - 1) / kForceBlock;
  const bool spin_needed = rolling_resistance_;  // only rolling resistance reads w_i - w_j
  if (tool_) tool_block_force_.resize(blocks);
#pragma omp parallel if (threaded_) num_threads(threads_)
  {
    ContactBatch& batch = batches_[static_cast<std::size_t>(omp_get_thread_num())];
#pragma omp for schedule(dynamic, 1)
    for (std::uint32_t b = 0; b < blocks; ++b) {
      const std::uint32_t begin = b * kForceBlock, end = std::min(n, begin + kForceBlock);
      for (std::uint32_t i = begin; i < end; ++i)
        load_[i] = {frozen_[i] || is_member(i) ? Vec3{} : grain_[i].mass * settings_.gravity, {}};
      if (tool_) tool_block_force_[b] = {};
      // Whole rows at a time: gather their contacts, evaluate the law on all of them, then
      // add the results in row and entry order, the fixed order of every sum.
      for (std::uint32_t first_row = begin; first_row < end;) {
        const std::uint32_t last_row = gather_contacts(batch, first_row, end, spin_needed);
        if (material_.empty()) evaluate(particle_law, batch, settings_.time_step);
        else if constexpr (std::is_same_v<Law, HertzMindlin>) evaluate_hertz_pairs(model_.pairs, batch, settings_.time_step);
        else evaluate_pairs<Law>(model_.pairs, batch, settings_.time_step);
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
  if (!body_.empty()) sum_body_loads();
  if (tool_) sum_tool_force();
}

void DemSystem::kick(double half_step) {
#pragma omp parallel for schedule(static) if (threaded_) num_threads(threads_)
  for (std::uint32_t i = 0; i < n_; ++i) {
    if (frozen_[i] || is_member(i)) continue;
    Grain& g = grain_[i];
    g.velocity += load_[i].force * (half_step / g.mass);
    g.angular_velocity += load_[i].torque * (half_step * g.inverse_inertia);
  }
  if (!body_.empty()) kick_bodies(half_step);
}

bool DemSystem::drift(double slack) {
  const double dt = settings_.time_step;
  // Moved more than half the skin (less what the container moved: a wall may come closer).
  const double reach = 0.5 * skin_ - slack;
  const double limit = reach > 0.0 ? reach * reach : -1.0;  // -1: rebuild now
  bool stale = false, lost = false;
  if (!body_.empty()) drift_bodies(dt);  // places the members
#pragma omp parallel for schedule(static) reduction(|| : stale, lost) if (threaded_) num_threads(threads_)
  for (std::uint32_t i = 0; i < n_; ++i) {
    if (!is_member(i)) grain_[i].position += grain_[i].velocity * dt;
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
  using Clock = std::chrono::steady_clock;
  // Below kThreadedFrom the loops run on one thread whatever the count: nothing to choose.
  const bool adapt = settings_.adapt_threads && n_ >= kThreadedFrom;
  for (std::size_t done = 0; done < steps;) {
    const std::size_t count = adapt ? std::min(steps - done, governor_.chunk(n_)) : steps - done;
    use_threads(adapt ? governor_.threads() : governor_.most());
    const double list_seconds = list_seconds_;
    const Clock::time_point start = Clock::now();
    advance(count);
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    if (adapt) governor_.ran(count, n_, std::max(0.0, seconds - (list_seconds_ - list_seconds)));
    if ((threaded_ ? threads_ : 1) < governor_.most()) steps_on_fewer_threads_ += count;
    done += count;
  }
  write_back();
}

void DemSystem::use_threads(int threads) {
  threads_ = threads;
  threaded_ = n_ >= kThreadedFrom && threads_ > 1;
}

void DemSystem::advance(std::size_t steps) {
  const double half = 0.5 * settings_.time_step;
  for (std::size_t s = 0; s < steps; ++s) {
    kick(half);
    // The forces of the new positions are those at the end of the step, with the container
    // (when it moves) where it is then.
    force_time_ = static_cast<double>(steps_ + 1) * settings_.time_step;
    // A wall or the rod that moved since the list build may have come closer by as much.
    double slack = 0.0;
    if (motion_.amplitude != 0.0) {
      place_container(force_time_);
      slack = std::abs(container_offset() - listed_offset_);
    }
    if (tool_) slack += place_tool(force_time_);
    if (drift(slack)) {
      const auto start = std::chrono::steady_clock::now();
      build_neighbour_list();
      list_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    compute_forces();
    kick(half);
    ++steps_;
    time_ = static_cast<double>(steps_) * settings_.time_step;
  }
}

void DemSystem::finish() {
  if (container_.periodic) {
    for (std::uint32_t i = 0; i < n_; ++i) p_.position[i] = container_.wrapped(p_.position[i]);
    for (Vec3& centre : p_.bodies.position) centre = container_.wrapped(centre);
  }
}

}  // namespace aggpack
