#include "aggpack/dynamics/dem_system.hpp"

#include <omp.h>

#include <stdexcept>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <variant>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/spatial/multilevel_grid.hpp"

namespace aggpack {
namespace {


constexpr std::size_t kSumBlock = 1024;  // fixed blocks make sums independent of thread count
// Below this many particles a step is too short to pay for waking threads (and on a busy
// machine each barrier can cost a scheduler tick). Results do not depend on it.
constexpr std::uint32_t kThreadedFrom = 1024;

}  // namespace

DemSystem::DemSystem(ParticleStore& particles, const Container& container, const ContactModel& model,
                     const DemSettings& settings, std::vector<std::uint8_t> frozen)
    : p_(particles), container_(container), model_(model), settings_(settings), frozen_(std::move(frozen)) {
  if (particles.size() >= 0xFFFFFFF0u) throw InputError("the dynamics stage holds at most 4e9 particles");
  if (!(settings.time_step > 0.0)) throw InputError(fmt::format("time step {} s must be > 0", settings.time_step));
  n_ = static_cast<std::uint32_t>(particles.size());
  if (frozen_.empty()) frozen_.assign(n_, 0);
  if (frozen_.size() != n_) throw std::invalid_argument("DemSystem: one frozen flag per particle");
  threaded_ = n_ >= kThreadedFrom;
  threads_ = settings.threads > 0 ? settings.threads : omp_get_max_threads();
  double d_min = 0.0;
  if (n_ > 0) d_min = 2.0 * *std::min_element(p_.radius.begin(), p_.radius.end());
  skin_ = settings.skin > 0.0 ? settings.skin : 0.1 * d_min;
  double solid = 0.0;
  for (std::uint32_t i = 0; i < n_; ++i) solid += std::pow(p_.radius[i], 3);
  grid_bed_volume_ = 4.0 / 3.0 * std::numbers::pi * solid / 0.5 + 1e-300;  // the spheres at a loose 0.5
  inverse_inertia_.assign(n_, 0.0);
  for (std::uint32_t i = 0; i < n_; ++i) {
    if (frozen_[i]) {
      p_.velocity[i] = {};
      p_.angular_velocity[i] = {};
      continue;
    }
    ++free_count_;
    inverse_inertia_[i] = 1.0 / (0.4 * p_.mass[i] * p_.radius[i] * p_.radius[i]);
  }
  force_.assign(n_, {});
  torque_.assign(n_, {});
  offset_.assign(n_ + 1, 0);
  build_neighbour_list();
  compute_forces();
}

Vec3 DemSystem::separation(const Vec3& from, const Vec3& to) const {
  // Positions stay within one period of the box between list builds, so the container's
  // minimum image applies; it is exactly antisymmetric, so b - a is exactly -(a - b).
  return container_.minimum_image(to - from);
}

void DemSystem::build_neighbour_list() {
  ++rebuilds_;
  const std::uint32_t n = n_;
  if (container_.periodic)
    for (std::uint32_t i = 0; i < n; ++i) p_.position[i] = container_.wrapped(p_.position[i]);
  MultilevelGrid grid(container_, p_.radius, grid_bed_volume_);
  grid.reserve(n);
  for (std::uint32_t i = 0; i < n; ++i) grid.insert(i, p_.position[i], p_.radius[i]);
  const std::uint32_t wall_count = container_.plane_count();

  // Calls add(entry) for every neighbour and wall within the skin of free particle i.
  const auto for_each_entry = [&](std::uint32_t i, auto&& add) {
    const Vec3& xi = p_.position[i];
    const double ri = p_.radius[i];
    grid.for_each_near(xi, ri + skin_, [&](std::uint32_t j) {
      if (j == i) return;
      const double reach = ri + p_.radius[j] + skin_;
      if (norm2(separation(xi, p_.position[j])) < reach * reach) add(j);
    });
    for (std::uint32_t w = 0; w < wall_count; ++w) {
      Vec3 towards;
      if (container_.plane_distance(w, xi, towards) < ri + skin_) add(n + w);
    }
  };

  std::vector<std::uint32_t> offset(n + 1, 0);
#pragma omp parallel for schedule(dynamic, 512) if (threaded_) num_threads(threads_)
  for (std::uint32_t i = 0; i < n; ++i) {
    if (frozen_[i]) continue;
    std::uint32_t count = 0;
    for_each_entry(i, [&](std::uint32_t) { ++count; });
    offset[i + 1] = count;
  }
  for (std::uint32_t i = 0; i < n; ++i) offset[i + 1] += offset[i];
  std::vector<std::uint32_t> other(offset[n]);
  std::vector<Vec3> spring(offset[n]);
#pragma omp parallel for schedule(dynamic, 512) if (threaded_) num_threads(threads_)
  for (std::uint32_t i = 0; i < n; ++i) {
    if (frozen_[i]) continue;
    std::uint32_t e = offset[i];
    for_each_entry(i, [&](std::uint32_t j) { other[e++] = j; });
    std::sort(other.begin() + offset[i], other.begin() + offset[i + 1]);
    // Carry each contact's tangential history over (both lists are sorted).
    std::uint32_t old_e = offset_[i];
    const std::uint32_t old_end = offset_[i + 1];
    for (std::uint32_t k = offset[i]; k < offset[i + 1] && old_e < old_end; ++k) {
      while (old_e < old_end && other_[old_e] < other[k]) ++old_e;
      if (old_e < old_end && other_[old_e] == other[k]) spring[k] = spring_[old_e];
    }
  }
  offset_.swap(offset);
  other_.swap(other);
  spring_.swap(spring);
  listed_position_ = p_.position;
}

bool DemSystem::list_is_stale() const {
  const double limit = 0.25 * skin_ * skin_;  // moved more than half the skin
  bool stale = false;
#pragma omp parallel for schedule(static) reduction(|| : stale) if (threaded_) num_threads(threads_)
  for (std::uint32_t i = 0; i < n_; ++i)
    if (norm2(p_.position[i] - listed_position_[i]) > limit) stale = true;
  return stale;
}

template <class Law>
void DemSystem::compute_forces(const Law& particle_law, const Law& wall_law) {
  const std::uint32_t n = n_;
  const double dt = settings_.time_step;
  const Vec3* x = p_.position.data();
  const Vec3* v = p_.velocity.data();
  const Vec3* w = p_.angular_velocity.data();
  const double* radius = p_.radius.data();
  const double* mass = p_.mass.data();
#pragma omp parallel for schedule(dynamic, 256) if (threaded_) num_threads(threads_)
  for (std::uint32_t i = 0; i < n; ++i) {
    if (frozen_[i]) continue;
    const Vec3 xi = x[i], vi = v[i], wi = w[i];
    const double ri = radius[i], mi = mass[i];
    const Vec3 spin_i = ri * wi;
    Vec3 f = mi * settings_.gravity;
    Vec3 t{};
    const std::uint32_t end = offset_[i + 1];
    for (std::uint32_t e = offset_[i]; e < end; ++e) {
      const std::uint32_t j = other_[e];
      ContactKinematics k;
      if (j < n) {
        const Vec3 d = separation(xi, x[j]);
        const double rj = radius[j];
        const double reach = ri + rj;
        const double d2 = norm2(d);
        if (d2 >= reach * reach) {
          spring_[e] = {};
          continue;
        }
        // One division for 1/distance, R* and m*: q = 1 / (distance (r_i + r_j) (m_i + m_j)).
        const double distance = std::sqrt(d2);
        const double mj = mass[j];
        const double reach_mass = reach * (mi + mj);
        const double q = 1.0 / (distance * reach_mass);
        k.normal = d * (reach_mass * q);
        k.overlap = reach - distance;
        k.velocity = vi - v[j] + cross(spin_i + rj * w[j], k.normal);
        k.spin = wi - w[j];
        k.r_eff = ri * rj * (mi + mj) * distance * q;
        k.m_eff = mi * mj * reach * distance * q;
        const ContactForce c = particle_law.evaluate(k, spring_[e], dt);
        f += c.force;
        t += ri * cross(k.normal, c.tangential) + c.rolling_torque;
      } else {
        const double distance = container_.plane_distance(j - n, xi, k.normal);
        if (distance >= ri) {
          spring_[e] = {};
          continue;
        }
        k.overlap = ri - distance;
        // The wall's own motion (at rest today; a tapped container moves) enters the contact.
        k.velocity = vi - container_.plane_velocity(j - n, time_) + cross(spin_i, k.normal);
        k.spin = wi;
        k.r_eff = ri;
        k.m_eff = mi;
        const ContactForce c = wall_law.evaluate(k, spring_[e], dt);
        f += c.force;
        t += ri * cross(k.normal, c.tangential) + c.rolling_torque;
      }
    }
    force_[i] = f;
    torque_[i] = t;
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
    p_.velocity[i] += force_[i] * (half_step / p_.mass[i]);
    p_.angular_velocity[i] += torque_[i] * (half_step * inverse_inertia_[i]);
  }
}

void DemSystem::drift() {
  const double dt = settings_.time_step;
#pragma omp parallel for schedule(static) if (threaded_) num_threads(threads_)
  for (std::uint32_t i = 0; i < n_; ++i) p_.position[i] += p_.velocity[i] * dt;
}

void DemSystem::run(std::size_t steps) {
  const double half = 0.5 * settings_.time_step;
  for (std::size_t s = 0; s < steps; ++s) {
    kick(half);
    drift();
    if (list_is_stale()) build_neighbour_list();
    compute_forces();
    kick(half);
    ++steps_;
    time_ = static_cast<double>(steps_) * settings_.time_step;
  }
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
      sum.translational += 0.5 * p_.mass[i] * norm2(p_.velocity[i]);
      sum.rotational += 0.5 * norm2(p_.angular_velocity[i]) / inverse_inertia_[i];
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
      const double ri = p_.radius[i];
      for (std::uint32_t e = offset_[i]; e < offset_[i + 1]; ++e) {
        const std::uint32_t j = other_[e];
        double overlap, diameter;
        if (j < n_) {
          diameter = ri + p_.radius[j];
          overlap = diameter - norm(separation(p_.position[i], p_.position[j]));
        } else {
          Vec3 towards;
          diameter = 2.0 * ri;
          overlap = ri - container_.plane_distance(j - n_, p_.position[i], towards);
        }
        if (overlap <= 0.0) continue;
        s.max_overlap = std::max(s.max_overlap, overlap / diameter);
        if (j < n_) {
          s.overlap_sum += overlap / diameter;
          ++s.contacts;
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
  return inverse_inertia_.capacity() * sizeof(double) +
         (force_.capacity() + torque_.capacity() + listed_position_.capacity() + spring_.capacity()) * sizeof(Vec3) +
         (offset_.capacity() + other_.capacity()) * sizeof(std::uint32_t);
}

void DemSystem::finish() {
  if (container_.periodic)
    for (std::uint32_t i = 0; i < n_; ++i) p_.position[i] = container_.wrapped(p_.position[i]);
}

}  // namespace aggpack
