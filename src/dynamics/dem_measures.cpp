// DemSystem's measures of itself: kinetic energy, contact statistics, memory.
#include <omp.h>

#include <algorithm>
#include <vector>

#include "aggpack/dynamics/dem_system.hpp"

namespace aggpack {
namespace {
constexpr std::size_t kSumBlock = 1024;  // fixed blocks make sums independent of thread count
}  // namespace

DemSystem::KineticEnergy DemSystem::kinetic_energy() const {
  const std::size_t blocks = (n_ + kSumBlock - 1) / kSumBlock;
  std::vector<KineticEnergy> partial(blocks);
#pragma omp parallel for schedule(static) if (threaded_) num_threads(threads_)
  for (std::size_t b = 0; b < blocks; ++b) {
    KineticEnergy sum;
    const std::size_t end = std::min<std::size_t>(n_, (b + 1) * kSumBlock);
    for (std::size_t i = b * kSumBlock; i < end; ++i) {
      if (frozen_[i] || is_member(i)) continue;
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
  for (const Body& body : body_) {
    total.translational += 0.5 * body.mass * norm2(body.velocity);
    total.rotational += 0.5 * dot(body.angular_momentum, body.angular_velocity);
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
          overlap = ri - wall_distance(j - n_, xi, towards);
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
  return grain_.capacity() * sizeof(Grain) + frozen_.capacity() + material_.capacity() +
         body_.capacity() * sizeof(Body) + body_load_.capacity() * sizeof(ForceTorque) +
         body_of_.capacity() * sizeof(std::uint32_t) +
         (body_offset_.capacity() + arm_.capacity() + image_.capacity()) * sizeof(Vec3) +
         (listed_position_.capacity() + spring_.capacity() + roll_.capacity()) * sizeof(Vec3) +
         (load_.capacity() + cross_.capacity()) * sizeof(ForceTorque) +
         (user_index_.capacity() + slot_of_.capacity() + offset_.capacity() + cross_begin_.capacity() +
          other_.capacity() + slot_base_.capacity() + reverse_offset_.capacity() + reverse_.capacity()) *
             sizeof(std::uint32_t) +
         batches;
}

}  // namespace aggpack
