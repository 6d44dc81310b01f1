// The HertzMindlin law over a ContactBatch with Highway vectors, compiled for every target
// of Highway's list and dispatched at run time. Each line mirrors one step of
// evaluate_each + HertzMindlin::evaluate (contact_batch.hpp, contact_law.hpp), in the same
// order, so that the results are the same bits: keep the two in step.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "contact_batch.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "aggpack/dynamics/contact_batch.hpp"

HWY_BEFORE_NAMESPACE();
namespace aggpack::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
static_assert(HWY_MAX_BYTES / sizeof(double) <= ContactBatch::kGroup, "a vector must fit in a group of contacts");

// The kernel's parts, each one step of the scalar law. They are HWY_INLINE (always inlined
// into EvaluateHertzMindlin) and inside this per-target namespace, which HWY_BEFORE_NAMESPACE
// compiles with the target's instruction set. Vectors pass one by one (by value or by
// reference): a struct of vectors would not compile for the scalable targets (SVE, RVV).
using D = hn::ScalableTag<double>;
using V = hn::Vec<D>;
using C = ContactBatch;

HWY_INLINE V Load(D d, const ContactBatch& b, C::Column col, std::size_t k) {
  return hn::LoadU(d, b.contact(k) + col * C::kGroup);
}

HWY_INLINE void Store(D d, V v, ContactBatch& b, C::Column col, std::size_t k) {
  hn::StoreU(v, d, b.contact(k) + col * C::kGroup);
}

HWY_INLINE V MaxOf(V a, V b) { return hn::IfThenElse(hn::Lt(a, b), b, a); }  // std::max(a, b)

// Kinematics (evaluate_each): the unit normal n, the overlap, the relative velocity v at the
// contact point, and the effective radius and mass of the contacts k .. k + lanes.
HWY_INLINE void Kinematics(D d, const ContactBatch& b, std::size_t k, V ri, V rj, V& nx, V& ny, V& nz, V& overlap,
                           V& vx, V& vy, V& vz, V& r_eff, V& m_eff) {
  const V one = hn::Set(d, 1.0);
  const V dx = Load(d, b, C::kDx, k), dy = Load(d, b, C::kDy, k), dz = Load(d, b, C::kDz, k);
  const V mi = Load(d, b, C::kMassI, k), mj = Load(d, b, C::kMassJ, k);
  const V distance = hn::Sqrt(Load(d, b, C::kDistance2, k));
  const V reach = ri + rj;
  const V mass_sum = mi + mj;
  const V reach_mass = reach * mass_sum;
  const V q = one / (distance * reach_mass);
  const V scale = reach_mass * q;
  nx = dx * scale, ny = dy * scale, nz = dz * scale;
  overlap = reach - distance;
  const V sx = Load(d, b, C::kSx, k), sy = Load(d, b, C::kSy, k), sz = Load(d, b, C::kSz, k);
  vx = Load(d, b, C::kVx, k) + (sy * nz - sz * ny);
  vy = Load(d, b, C::kVy, k) + (sz * nx - sx * nz);
  vz = Load(d, b, C::kVz, k) + (sx * ny - sy * nx);
  r_eff = ri * rj * mass_sum * distance * q;
  m_eff = mi * mj * reach * distance * q;
}

// Coulomb's cap on the tangential force f (HertzMindlin::evaluate): where |f| exceeds `cap`,
// f shrinks to it and the spring u becomes the one that gives it. Sliding is rare in a bed at
// rest: its square root and two divisions (the costliest operations here) are taken only when
// a lane slides. The lanes that do not slide keep their values either way, so the bits do not
// depend on it.
HWY_INLINE void CapAtFriction(D d, V cap, V kt, V eta_t, V tx, V ty, V tz, V& ux, V& uy, V& uz, V& fx, V& fy,
                              V& fz) {
  const V ft2 = fx * fx + fy * fy + fz * fz;
  const auto sliding = hn::Gt(ft2, cap * cap);
  if (hn::AllFalse(d, sliding)) return;
  const V shrink = cap / hn::Sqrt(ft2);
  const V slid_x = fx * shrink, slid_y = fy * shrink, slid_z = fz * shrink;
  const V inverse = hn::Set(d, -1.0) / kt;
  ux = hn::IfThenElse(sliding, (slid_x + tx * eta_t) * inverse, ux);
  uy = hn::IfThenElse(sliding, (slid_y + ty * eta_t) * inverse, uy);
  uz = hn::IfThenElse(sliding, (slid_z + tz * eta_t) * inverse, uz);
  fx = hn::IfThenElse(sliding, slid_x, fx);
  fy = hn::IfThenElse(sliding, slid_y, fy);
  fz = hn::IfThenElse(sliding, slid_z, fz);
}

// Rolling resistance (contact_detail::rolling_torque) of the contacts k .. k + lanes.
HWY_INLINE void RollingTorque(D d, const ContactBatch& b, std::size_t k, V minus_rolling, V regularisation, V r_eff,
                              V fn, V& rx, V& ry, V& rz) {
  const V wx = Load(d, b, C::kWx, k), wy = Load(d, b, C::kWy, k), wz = Load(d, b, C::kWz, k);
  const V spin_scale = MaxOf(hn::Sqrt(wx * wx + wy * wy + wz * wz) * r_eff, regularisation);
  const V factor = minus_rolling * r_eff * fn * r_eff / spin_scale;
  rx = wx * factor;
  ry = wy * factor;
  rz = wz * factor;
}

// The spring-dashpot rolling resistance (contact_detail::spring_dashpot_rolling_torque) of the
// contacts k .. k + lanes: updates their histories h and gives the torque on i.
HWY_INLINE void RollingSpringDashpot(D d, ContactBatch& b, std::size_t k, V k_roll, V gamma_roll, V minus_inverse_k,
                                     V step, V cap, V r_eff, V nx, V ny, V nz, hn::Mask<D> rolling_lanes, V& rx, V& ry,
                                     V& rz) {
  const V zero = hn::Zero(d);
  const V wx = Load(d, b, C::kWx, k), wy = Load(d, b, C::kWy, k), wz = Load(d, b, C::kWz, k);
  const V lx = r_eff * (ny * wz - nz * wy), ly = r_eff * (nz * wx - nx * wz), lz = r_eff * (nx * wy - ny * wx);
  const V old_hx = Load(d, b, C::kHx, k), old_hy = Load(d, b, C::kHy, k), old_hz = Load(d, b, C::kHz, k);
  V hx = old_hx, hy = old_hy, hz = old_hz;
  // Into the contact plane, the length kept, where the normal part is not negligible.
  const V along = hx * nx + hy * ny + hz * nz;
  const auto tilted = hn::Gt(hn::Abs(along) * k_roll, hn::Set(d, 1e-10) * cap);
  if (!hn::AllFalse(d, tilted)) {
    const V length = hn::Sqrt(hx * hx + hy * hy + hz * hz);
    const V px = hx - along * nx, py = hy - along * ny, pz = hz - along * nz;
    const V projected = hn::Sqrt(px * px + py * py + pz * pz);
    const V scale = hn::IfThenElse(hn::Gt(projected, zero), length / projected, zero);
    hx = hn::IfThenElse(tilted, px * scale, hx);
    hy = hn::IfThenElse(tilted, py * scale, hy);
    hz = hn::IfThenElse(tilted, pz * scale, hz);
  }
  hx = hx + lx * step;
  hy = hy + ly * step;
  hz = hz + lz * step;
  const V minus_k = hn::Neg(k_roll);
  V fx = minus_k * hx - gamma_roll * lx, fy = minus_k * hy - gamma_roll * ly, fz = minus_k * hz - gamma_roll * lz;
  // At the cap: the capped torque and its history, or none without a history (rare: masked).
  const V fr2 = fx * fx + fy * fy + fz * fz;
  const auto rolling = hn::Gt(fr2, cap * cap);
  if (!hn::AllFalse(d, rolling)) {
    const auto held = hn::Ne(hx * hx + hy * hy + hz * hz, zero);
    const V shrink = cap / hn::Sqrt(fr2);
    const V cx = fx * shrink, cy = fy * shrink, cz = fz * shrink;
    const auto capped = hn::And(rolling, held);
    hx = hn::IfThenElse(capped, (cx + gamma_roll * lx) * minus_inverse_k, hx);
    hy = hn::IfThenElse(capped, (cy + gamma_roll * ly) * minus_inverse_k, hy);
    hz = hn::IfThenElse(capped, (cz + gamma_roll * lz) * minus_inverse_k, hz);
    fx = hn::IfThenElse(rolling, hn::IfThenElseZero(held, cx), fx);
    fy = hn::IfThenElse(rolling, hn::IfThenElseZero(held, cy), fy);
    fz = hn::IfThenElse(rolling, hn::IfThenElseZero(held, cz), fz);
  }
  // A lane without rolling resistance (a pair of materials with none) keeps its history.
  Store(d, hn::IfThenElse(rolling_lanes, hx, old_hx), b, C::kHx, k);
  Store(d, hn::IfThenElse(rolling_lanes, hy, old_hy), b, C::kHy, k);
  Store(d, hn::IfThenElse(rolling_lanes, hz, old_hz), b, C::kHz, k);
  rx = r_eff * (fy * nz - fz * ny);
  ry = r_eff * (fz * nx - fx * nz);
  rz = r_eff * (fx * ny - fy * nx);
}

// HertzMindlin::evaluate on the contacts k .. k + lanes, each lane with its own coefficients
// (the same in every lane for one law). `constant_torque` and `spring_dashpot` say which rolling
// law some lane has; `rolling_lanes`, which lanes have rolling resistance (the others give no
// torque and keep their rolling history, as the scalar law does).
HWY_INLINE void EvaluateLanes(D d, ContactBatch& b, std::size_t k, V step, V stiffness_factor, V shear_factor,
                              V damping, V friction, V damping_ratio, V rolling_friction, V k_roll, V gamma_roll,
                              V minus_inverse_k, bool constant_torque, bool spring_dashpot,
                              hn::Mask<D> rolling_lanes) {
  const V zero = hn::Zero(d);
  const V ri = Load(d, b, C::kRadiusI, k), rj = Load(d, b, C::kRadiusJ, k);
  V nx, ny, nz, overlap, vx, vy, vz, r_eff, m_eff;
  Kinematics(d, b, k, ri, rj, nx, ny, nz, overlap, vx, vy, vz, r_eff, m_eff);
  // HertzMindlin::evaluate: normal force.
  const V sqrt_r_overlap = hn::Sqrt(r_eff * overlap);
  const V stiffness = stiffness_factor * sqrt_r_overlap;
  const V approach = vx * nx + vy * ny + vz * nz;
  const V damping_n = damping * hn::Sqrt(m_eff * stiffness);
  const V fn = MaxOf(zero, stiffness * overlap + damping_n * approach);
  const V tx = vx - nx * approach, ty = vy - ny * approach, tz = vz - nz * approach;
  // The spring follows the contact plane, grows with the sliding, and is capped.
  V ux = Load(d, b, C::kUx, k), uy = Load(d, b, C::kUy, k), uz = Load(d, b, C::kUz, k);
  const V normal_part = ux * nx + uy * ny + uz * nz;
  ux = ux - nx * normal_part;
  uy = uy - ny * normal_part;
  uz = uz - nz * normal_part;
  ux = ux + tx * step;
  uy = uy + ty * step;
  uz = uz + tz * step;
  const V kt = shear_factor * sqrt_r_overlap;
  const V eta_t = damping_n * damping_ratio;
  const V minus_kt = hn::Neg(kt);
  V fx = ux * minus_kt - tx * eta_t, fy = uy * minus_kt - ty * eta_t, fz = uz * minus_kt - tz * eta_t;
  CapAtFriction(d, friction * fn, kt, eta_t, tx, ty, tz, ux, uy, uz, fx, fy, fz);
  // Rolling resistance, zero (+0, as the scalar law's) in the lanes that have none.
  V rx = zero, ry = zero, rz = zero;
  if (spring_dashpot)
    RollingSpringDashpot(d, b, k, k_roll, gamma_roll, minus_inverse_k, step, rolling_friction * fn, r_eff, nx, ny, nz,
                         rolling_lanes, rx, ry, rz);
  else if (constant_torque)
    RollingTorque(d, b, k, hn::Neg(rolling_friction), hn::Set(d, kFrictionRegularisation), r_eff, fn, rx, ry, rz);
  rx = hn::IfThenElseZero(rolling_lanes, rx);
  ry = hn::IfThenElseZero(rolling_lanes, ry);
  rz = hn::IfThenElseZero(rolling_lanes, rz);
  // Outputs: the spring, the force on i, and both torques (n x F_t is the same for j).
  Store(d, ux, b, C::kUx, k);
  Store(d, uy, b, C::kUy, k);
  Store(d, uz, b, C::kUz, k);
  Store(d, fx - nx * fn, b, C::kFx, k);
  Store(d, fy - ny * fn, b, C::kFy, k);
  Store(d, fz - nz * fn, b, C::kFz, k);
  const V ax = ny * fz - nz * fy, ay = nz * fx - nx * fz, az = nx * fy - ny * fx;
  // The lever arms: the contact point is the middle of the overlap (evaluate_each).
  const V half_overlap = hn::Set(d, 0.5) * overlap;
  const V arm_i = ri - half_overlap, arm_j = rj - half_overlap;
  Store(d, ax * arm_i + rx, b, C::kTix, k);
  Store(d, ay * arm_i + ry, b, C::kTiy, k);
  Store(d, az * arm_i + rz, b, C::kTiz, k);
  Store(d, ax * arm_j - rx, b, C::kTjx, k);
  Store(d, ay * arm_j - ry, b, C::kTjy, k);
  Store(d, az * arm_j - rz, b, C::kTjz, k);
}

void EvaluateHertzMindlin(const HertzMindlin& law, ContactBatch& b, double dt) {
  const D d;
  // The coefficients, read in this one place (the same for every contact of the batch).
  const ContactCoefficients& c = law.c;
  const V stiffness_factor = hn::Set(d, (4.0 / 3.0) * c.e_star);
  const V shear_factor = hn::Set(d, 8.0 * c.g_star);
  const V damping = hn::Set(d, c.damping), friction = hn::Set(d, c.friction), step = hn::Set(d, dt);
  const V damping_ratio = hn::Set(d, law.tangential_damping_ratio);
  const V rolling_friction = hn::Set(d, c.rolling), k_roll = hn::Set(d, c.rolling_stiffness);
  const V gamma_roll = hn::Set(d, c.rolling_damping), minus_inverse_k = hn::Set(d, -1.0 / c.rolling_stiffness);
  const bool rolling = c.rolling != 0.0, spring_dashpot = c.rolling_history();
  const auto every_lane = hn::Eq(step, step);
  const std::size_t lanes = hn::Lanes(d);
  for (std::size_t k = 0; k < b.size; k += lanes)
    EvaluateLanes(d, b, k, step, stiffness_factor, shear_factor, damping, friction, damping_ratio, rolling_friction,
                  k_roll, gamma_roll, minus_inverse_k, rolling && !spring_dashpot, spring_dashpot, every_lane);
}

// A run of several materials: each lane takes the coefficients of its contact's pair of
// materials, `pair_laws[b.pair[k]]` (all HertzMindlin), computed as EvaluateHertzMindlin
// computes them from one law, so each lane gives the bits of its pair's law alone.
void EvaluateHertzMindlinPairs(std::span<const ContactLaw> pair_laws, ContactBatch& b, double dt) {
  const D d;
  const V step = hn::Set(d, dt), zero = hn::Zero(d);
  bool constant_torque = false, spring_dashpot = false;
  for (const ContactLaw& law : pair_laws) {
    const ContactCoefficients& c = std::get<HertzMindlin>(law).c;
    spring_dashpot = spring_dashpot || c.rolling_history();
    constant_torque = constant_torque || (c.rolling != 0.0 && !c.rolling_history());
  }
  enum Coefficient { kStiffness, kShear, kDamping, kFriction, kRatio, kRolling, kRollStiffness, kRollDamping,
                     kMinusInverseK, kCoefficients };
  HWY_ALIGN double lane[kCoefficients][C::kGroup];
  const std::size_t lanes = hn::Lanes(d);
  for (std::size_t k = 0; k < b.size; k += lanes) {
    for (std::size_t j = 0; j < lanes; ++j) {
      // The padding after the last contact takes the first pair's law (its results are ignored).
      const HertzMindlin& law = std::get<HertzMindlin>(pair_laws[k + j < b.size ? b.pair[k + j] : 0]);
      const ContactCoefficients& c = law.c;
      const bool has_rolling = c.rolling != 0.0;
      lane[kStiffness][j] = (4.0 / 3.0) * c.e_star;
      lane[kShear][j] = 8.0 * c.g_star;
      lane[kDamping][j] = c.damping;
      lane[kFriction][j] = c.friction;
      lane[kRatio][j] = law.tangential_damping_ratio;
      lane[kRolling][j] = c.rolling;
      // A lane without rolling resistance computes with a harmless spring (and is masked out).
      lane[kRollStiffness][j] = has_rolling && spring_dashpot ? c.rolling_stiffness : 1.0;
      lane[kRollDamping][j] = has_rolling && spring_dashpot ? c.rolling_damping : 0.0;
      lane[kMinusInverseK][j] = has_rolling && spring_dashpot ? -1.0 / c.rolling_stiffness : -1.0;
    }
    const auto column = [&](Coefficient c) { return hn::Load(d, lane[c]); };
    const V rolling_friction = column(kRolling);
    EvaluateLanes(d, b, k, step, column(kStiffness), column(kShear), column(kDamping), column(kFriction),
                  column(kRatio), rolling_friction, column(kRollStiffness), column(kRollDamping),
                  column(kMinusInverseK), constant_torque, spring_dashpot, hn::Ne(rolling_friction, zero));
  }
}

}  // namespace aggpack::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include "core/highway_target.hpp"
#include <algorithm>
#include <stdexcept>

namespace aggpack {

HWY_EXPORT(EvaluateHertzMindlin);
HWY_EXPORT(EvaluateHertzMindlinPairs);

void ContactBatch::grow(std::size_t contacts) {
  const std::size_t groups = (std::max(contacts, 2 * entry.size()) + kGroup - 1) / kGroup;
  values_.resize(groups * kGroupValues);  // whole groups: the contacts keep their places
  entry.resize(groups * kGroup);
}

void ContactBatch::pad() {
  // Unit contacts: 1 m apart, radii 1 m, masses 1 kg, at rest. They overlap, so every
  // square root and division of the kernels stays finite.
  const std::size_t rest = (kGroup - size % kGroup) % kGroup;
  reserve_more(rest);
  for (std::size_t c = 0; c < kColumns; ++c) {
    const bool unit = c == kDx || c == kDistance2 || (c >= kRadiusI && c <= kMassJ);
    std::fill_n(contact(size) + c * kGroup, rest, unit ? 1.0 : 0.0);  // within one group
  }
}

void evaluate(const HertzMindlin& law, ContactBatch& batch, double dt) {
  batch.pad();
  HWY_DYNAMIC_DISPATCH(EvaluateHertzMindlin)(law, batch, dt);
}

void evaluate(const SlidingFrictionFu2003& law, ContactBatch& batch, double dt) { evaluate_each(law, batch, dt); }

void evaluate_hertz_pairs(std::span<const ContactLaw> pair_laws, ContactBatch& batch, double dt) {
  batch.pad();
  HWY_DYNAMIC_DISPATCH(EvaluateHertzMindlinPairs)(pair_laws, batch, dt);
}

std::vector<std::string> contact_kernel_targets() { return highway::target_names(); }

std::string contact_kernel_target() {
  // The dispatch picks the best supported target, the first of the list.
  const std::vector<std::int64_t> targets = hwy::SupportedAndGeneratedTargets();
  return targets.empty() ? std::string("none") : std::string(hwy::TargetName(targets.front()));
}

void evaluate_with_target(const std::string& target, const HertzMindlin& law, ContactBatch& batch, double dt) {
  highway::on_target(target, "evaluate_with_target", [&] { evaluate(law, batch, dt); });
}

void evaluate_hertz_pairs_with_target(const std::string& target, std::span<const ContactLaw> pair_laws,
                                      ContactBatch& batch, double dt) {
  highway::on_target(target, "evaluate_hertz_pairs_with_target", [&] { evaluate_hertz_pairs(pair_laws, batch, dt); });
}

}  // namespace aggpack
#endif  // HWY_ONCE
