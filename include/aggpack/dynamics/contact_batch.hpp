#pragma once
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "aggpack/dynamics/contact_law.hpp"

namespace aggpack {

// A block of particle-particle contacts in groups of structure-of-arrays (see kGroup): the DEM gathers the
// kinematics of the contacts of a few rows of its neighbour list, a law evaluates them all
// at once (with SIMD where it has a vector kernel), and the DEM scatters the results in a
// fixed order. Contact k is between grains i (the row's) and j; `d` = x_j - x_i. Each thread
// has its own; they are cache-line aligned so that two threads' counters never share a line.
struct alignas(64) ContactBatch {
  enum Column : std::uint8_t {
    // inputs
    kDx, kDy, kDz,           // separation x_j - x_i (minimum image), m
    kDistance2,              // |d|^2, below (r_i + r_j)^2
    kRadiusI, kRadiusJ, kMassI, kMassJ,
    kVx, kVy, kVz,           // v_i - v_j
    kSx, kSy, kSz,           // r_i w_i + r_j w_j (the contact point's speed is this x n)
    kWx, kWy, kWz,           // w_i - w_j (the DEM fills it only for a law with rolling resistance)
    kUx, kUy, kUz,           // tangential spring: in, and updated in place
    kHx, kHy, kHz,           // rolling history, the same (the DEM fills it only for a law that keeps one)
    // outputs
    kFx, kFy, kFz,           // force on i (j gets the opposite)
    kTix, kTiy, kTiz,        // torque on i
    kTjx, kTjy, kTjz,        // torque on j
    kColumns
  };
  // Contacts are stored in groups of kGroup, column by column within a group (contact k's
  // column c at group k / kGroup, offset c * kGroup + k % kGroup): a vector of up to kGroup
  // lanes loads a column of consecutive contacts in one go, and the DEM writes a contact's
  // columns at fixed distances from one address.
  static constexpr std::size_t kGroup = 8;  // lanes of the widest vector kernel (AVX-512)
  static constexpr std::size_t kGroupValues = kColumns * kGroup;

  std::size_t size = 0;
  std::vector<std::uint32_t> entry;  // the neighbour-list entry of each contact
  // The pair of materials of each contact (a * materials + b), in a run of several materials.
  std::vector<std::uint16_t> pair;
  // Per gathered row, in order: the end of its contacts in the batch and the row's first
  // wall entry of the neighbour list (the DEM's bookkeeping for the scatter).
  struct Row {
    std::uint32_t contacts_end = 0;
    std::uint32_t walls_begin = 0;
  };
  std::vector<Row> rows;

  // Contact k's column c is contact(k)[c * kGroup]; a vector kernel of L lanes (L divides
  // kGroup, k a multiple of L) loads column c of contacts k .. k + L - 1 from there.
  double* contact(std::size_t k) { return values_.data() + k / kGroup * kGroupValues + k % kGroup; }
  [[nodiscard]] const double* contact(std::size_t k) const {
    return values_.data() + k / kGroup * kGroupValues + k % kGroup;
  }
  double& at(Column c, std::size_t k) { return contact(k)[c * kGroup]; }
  [[nodiscard]] double at(Column c, std::size_t k) const { return contact(k)[c * kGroup]; }
  // The three columns from c on of the contact at `contact` (as contact(k) gives it).
  static void put3(double* contact, Column c, const Vec3& v) {
    contact[c * kGroup] = v.x;
    contact[(c + 1) * kGroup] = v.y;
    contact[(c + 2) * kGroup] = v.z;
  }
  static Vec3 get3(const double* contact, Column c) {
    return {contact[c * kGroup], contact[(c + 1) * kGroup], contact[(c + 2) * kGroup]};
  }
  [[nodiscard]] std::size_t memory_bytes() const {
    return values_.capacity() * sizeof(double) + entry.capacity() * sizeof(std::uint32_t) +
           pair.capacity() * sizeof(std::uint16_t) + rows.capacity() * sizeof(Row);
  }
  void clear() {
    size = 0;
    rows.clear();
  }
  // Makes room for `more` contacts beyond size, in whole groups; the values may move.
  void reserve_more(std::size_t more) {
    if (size + more > entry.size()) grow(size + more);
  }
  // Fills the rest of the last group with a harmless contact (vector kernels read whole
  // vectors; the padding's results are ignored).
  void pad();

 private:
  void grow(std::size_t contacts);
  std::vector<double> values_;  // groups of kGroupValues values
};

// Evaluates every contact of the batch with the law: the reference, one contact at a time
// through Law::evaluate.
template <class Law>
void evaluate_each(const Law& law, ContactBatch& batch, double dt);
// Contact k of the batch with the law: evaluate_each's step.
template <class Law>
void evaluate_contact(const Law& law, ContactBatch& batch, std::size_t k, double dt);
// A run of several materials: each contact with the law of its pair of materials,
// `pair_laws[batch.pair[k]]` (all of kind Law), one at a time (the reference path, no vector kernel).
template <class Law>
void evaluate_pairs(std::span<const ContactLaw> pair_laws, ContactBatch& batch, double dt);

// The same with the law's vector kernel where it has one (HertzMindlin: Highway, dispatched
// at run time to the best instruction set of the machine), otherwise evaluate_each. The
// results are bit-identical to evaluate_each: IEEE square roots and divisions, no fused
// multiply-add (the dynamics library is built with -ffp-contract=off), the same operations
// in the same order.
void evaluate(const HertzMindlin& law, ContactBatch& batch, double dt);
void evaluate(const SlidingFrictionFu2003& law, ContactBatch& batch, double dt);
// evaluate_pairs<HertzMindlin> with the vector kernel, each lane taking its pair's
// coefficients: the same bits as evaluate_pairs, one pair's law alone per contact.
void evaluate_hertz_pairs(std::span<const ContactLaw> pair_laws, ContactBatch& batch, double dt);

// The instruction sets the HertzMindlin vector kernel was compiled for that this machine
// runs, best first, and the one evaluate() uses; evaluate_with_target() forces one (tests).
std::vector<std::string> contact_kernel_targets();
std::string contact_kernel_target();
void evaluate_with_target(const std::string& target, const HertzMindlin& law, ContactBatch& batch, double dt);
void evaluate_hertz_pairs_with_target(const std::string& target, std::span<const ContactLaw> pair_laws,
                                      ContactBatch& batch, double dt);

// ---- implementation of the reference ----------------------------------------------------

template <class Law>
void evaluate_each(const Law& law, ContactBatch& b, double dt) {
  for (std::size_t k = 0; k < b.size; ++k) evaluate_contact(law, b, k, dt);
}

template <class Law>
void evaluate_pairs(std::span<const ContactLaw> pair_laws, ContactBatch& b, double dt) {
  for (std::size_t k = 0; k < b.size; ++k) evaluate_contact(std::get<Law>(pair_laws[b.pair[k]]), b, k, dt);
}

template <class Law>
void evaluate_contact(const Law& law, ContactBatch& b, std::size_t k, double dt) {
  using C = ContactBatch;
  const auto in = [&](C::Column c) { return b.at(c, k); };
  const Vec3 d{in(C::kDx), in(C::kDy), in(C::kDz)};
  const double ri = in(C::kRadiusI), rj = in(C::kRadiusJ), mi = in(C::kMassI), mj = in(C::kMassJ);
  // One division for 1/distance, R* and m*: q = 1 / (distance (r_i + r_j) (m_i + m_j)).
  const double distance = std::sqrt(in(C::kDistance2));
  const double reach = ri + rj;
  const double reach_mass = reach * (mi + mj);
  const double q = 1.0 / (distance * reach_mass);
  ContactKinematics kin;
  kin.normal = d * (reach_mass * q);
  kin.overlap = reach - distance;
  kin.velocity = Vec3{in(C::kVx), in(C::kVy), in(C::kVz)} + cross(Vec3{in(C::kSx), in(C::kSy), in(C::kSz)}, kin.normal);
  kin.spin = {in(C::kWx), in(C::kWy), in(C::kWz)};
  kin.r_eff = ri * rj * (mi + mj) * distance * q;
  kin.m_eff = mi * mj * reach * distance * q;
  Vec3 spring{in(C::kUx), in(C::kUy), in(C::kUz)};
  Vec3 rolling{in(C::kHx), in(C::kHy), in(C::kHz)};
  const ContactForce c = law.evaluate(kin, spring, rolling, dt);
  // j sees the opposite normal and tangential force, so the same n x F_t, and the
  // opposite rolling torque. The tangential force acts at the contact point, the middle of
  // the overlap: R - d/2 from each centre (LAMMPS's pair granular, dist_to_contact).
  const Vec3 arm = cross(kin.normal, c.tangential);
  const double arm_i = ri - 0.5 * kin.overlap, arm_j = rj - 0.5 * kin.overlap;
  const Vec3 ti = arm_i * arm + c.rolling_torque, tj = arm_j * arm - c.rolling_torque;
  double* const slot = b.contact(k);
  C::put3(slot, C::kUx, spring);
  C::put3(slot, C::kHx, rolling);
  C::put3(slot, C::kFx, c.force);
  C::put3(slot, C::kTix, ti);
  C::put3(slot, C::kTjx, tj);
}

}  // namespace aggpack
