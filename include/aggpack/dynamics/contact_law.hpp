#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "aggpack/core/enum_names.hpp"
#include "aggpack/core/vec3.hpp"

namespace aggpack {

// ---- Formulas, each alone and tested alone ------------------------------------------

// Hertz effective modulus: 1/E* = (1 - nu_a^2)/E_a + (1 - nu_b^2)/E_b (Johnson 1985, eq. 4.22).
double effective_youngs_modulus(double e_a, double nu_a, double e_b, double nu_b);
// Mindlin effective shear modulus: 1/G* = (2 - nu_a)/G_a + (2 - nu_b)/G_b, G = E / (2(1 + nu)).
double effective_shear_modulus(double e_a, double nu_a, double e_b, double nu_b);
// Hertz normal force (4/3) E* sqrt(R*) overlap^(3/2) (Johnson 1985, eq. 4.23).
inline double hertz_normal_force(double e_star, double r_star, double overlap) {
  return (4.0 / 3.0) * e_star * std::sqrt(r_star * overlap) * overlap;
}
// Static overlap of a sphere of weight w resting on a plane: (3 w / (4 E* sqrt R))^(2/3).
double hertz_static_overlap(double weight, double e_star, double r_star);
// Duration of an elastic Hertz impact at approach speed v:
// 2 (5/4)^(2/5) (2/5) B(2/5, 1/2) (3/4)^(2/5) (m*^2 / (R* E*^2 v))^(1/5), about 2.868 (...)^(1/5).
double hertz_contact_time(double m_star, double r_star, double e_star, double speed);
// Rayleigh-wave time of a sphere: pi R sqrt(rho / G) / (0.1631 nu + 0.8766).
double rayleigh_time(double radius, double density, double youngs_modulus, double poisson_ratio);

// Restitution damping (Tsuji et al., Powder Technol. 71, 1992): the normal damping force
// is -a sqrt(m* k_n) overlap^(1/4) v_n with k_n = (4/3) E* sqrt(R*). With this form the
// restitution coefficient depends on the dimensionless a alone, not on the impact speed,
// so we solve the dimensionless impact x'' = -x^(3/2) - a x^(1/4) x' once and invert it
// exactly instead of using the linear-spring approximation most codes use.
double restitution_of_damping(double a);   // e(a), a >= 0
double damping_for_restitution(double e);  // a(e), 0 < e <= 1

// ---- What a law sees of one contact, and what it returns -----------------------------

// Contact of particle i with j (or with a wall). `normal` points from i to j; `velocity`
// is that of i's contact point relative to j's; `spin` is omega_i - omega_j.
struct ContactKinematics {
  Vec3 normal;
  double overlap = 0.0;  // m, > 0
  Vec3 velocity;
  Vec3 spin;
  double r_eff = 0.0;    // R* (R_i for a wall)
  double m_eff = 0.0;    // m* (m_i for a wall)
};

struct ContactForce {
  Vec3 force;          // on i, normal and tangential
  Vec3 tangential;     // on i, the part that makes a torque about i's centre
  Vec3 rolling_torque; // on i
  double normal = 0.0; // magnitude of the normal force, >= 0
};

// Rolling resistance, both capped at the torque mu_r R* F_n: a constant torque against the
// relative spin, or LAMMPS's `rolling sds` spring-dashpot with a history per contact.
enum class RollingModel : std::uint8_t { ConstantTorque, SpringDashpot };
inline constexpr std::array kRollingModelNames{
    EnumName<RollingModel>{RollingModel::ConstantTorque, "constant_torque"},
    EnumName<RollingModel>{RollingModel::SpringDashpot, "spring_dashpot"}};

// The coefficients of one kind of contact (particle-particle or particle-wall).
struct ContactCoefficients {
  double e_star = 0.0;        // Pa
  double g_star = 0.0;        // Pa
  double damping = 0.0;       // the dimensionless a above
  double friction = 0.0;      // Coulomb mu
  double rolling = 0.0;       // rolling resistance mu_r (torque at most mu_r R* F_n), 0 for none
  RollingModel rolling_model = RollingModel::ConstantTorque;
  double rolling_stiffness = 0.0;  // k_roll, N/m (SpringDashpot only, > 0 there)
  double rolling_damping = 0.0;    // gamma_roll, N s/m (SpringDashpot only)
  // Whether a contact keeps a rolling history (the DEM stores one per list entry only then).
  [[nodiscard]] bool rolling_history() const { return rolling != 0.0 && rolling_model == RollingModel::SpringDashpot; }
};

// Sliding and spinning speeds below which friction and rolling resistance are made
// proportional to the speed, so that a sign function does not chatter (m/s).
inline constexpr double kFrictionRegularisation = 1e-6;

namespace contact_detail {
// Normal force magnitude: Hertz plus restitution damping, never attractive. Also gives
// the damping coefficient a sqrt(m* k_n) overlap^(1/4).
inline double normal_force(const ContactCoefficients& c, const ContactKinematics& k, double sqrt_r_overlap,
                           double& damping_coefficient) {
  const double stiffness = (4.0 / 3.0) * c.e_star * sqrt_r_overlap;  // k_n overlap^(1/2)
  const double approach = dot(k.velocity, k.normal);                 // > 0 when i moves into j
  damping_coefficient = c.damping * std::sqrt(k.m_eff * stiffness);
  return std::max(0.0, stiffness * k.overlap + damping_coefficient * approach);
}
inline Vec3 constant_rolling_torque(const ContactCoefficients& c, const ContactKinematics& k, double normal) {
  const double scale = std::max(norm(k.spin) * k.r_eff, kFrictionRegularisation);
  return k.spin * (-c.rolling * k.r_eff * normal * k.r_eff / scale);
}
// LAMMPS 2022's pair granular `rolling sds` (and fix wall/gran, the wall at rest). LAMMPS's
// normal n_L points from j to i, ours from i to j: its rolling velocity R* (w x n_L) is
// R* (n x w) here and its torque R* (n_L x f_r) is R* (f_r x n); the history h is the same
// vector either way, and the same seen from j (both w and n change sign).
inline Vec3 spring_dashpot_rolling_torque(const ContactCoefficients& c, const ContactKinematics& k, double normal,
                                          Vec3& history, double dt) {
  const Vec3 rolling_velocity = k.r_eff * cross(k.normal, k.spin);
  const double cap = c.rolling * normal;
  // The history follows the contact plane, its length kept (LAMMPS skips a negligible tilt).
  const double along = dot(history, k.normal);
  if (std::abs(along) * c.rolling_stiffness > 1e-10 * cap) {
    const double length = std::sqrt(norm2(history));
    history -= along * k.normal;
    const double projected = std::sqrt(norm2(history));
    history = history * (projected > 0.0 ? length / projected : 0.0);
  }
  history += rolling_velocity * dt;
  Vec3 fr = -c.rolling_stiffness * history - c.rolling_damping * rolling_velocity;
  const double fr2 = norm2(fr);
  if (fr2 > cap * cap) {
    // Rolling: the torque at the cap and the history that gives it; none without a history.
    if (norm2(history) != 0.0) {
      fr = fr * (cap / std::sqrt(fr2));
      history = (fr + c.rolling_damping * rolling_velocity) * (-1.0 / c.rolling_stiffness);
    } else {
      fr = {};
    }
  }
  return k.r_eff * cross(fr, k.normal);
}
inline Vec3 rolling_torque(const ContactCoefficients& c, const ContactKinematics& k, double normal, Vec3& history,
                           double dt) {
  if (c.rolling == 0.0) return {};
  if (c.rolling_model == RollingModel::SpringDashpot)
    return spring_dashpot_rolling_torque(c, k, normal, history, dt);
  return constant_rolling_torque(c, k, normal);
}
}  // namespace contact_detail

// Hertz normal force, restitution damping, Mindlin tangential spring k_t = 8 G* sqrt(R* d)
// with stored displacement (rotated into the current tangent plane) and damping of the same
// form as the normal one, capped by Coulomb mu F_n; optional constant rolling resistance.
struct HertzMindlin {
  explicit HertzMindlin(const ContactCoefficients& coefficients)
      : c(coefficients), tangential_damping_ratio(std::sqrt(4.0 * c.g_star / c.e_star)) {}
  ContactCoefficients c;
  // Same form as the normal damping with k_t = 8 G* sqrt(R* d) in place of dF_n/dd = 2 E* sqrt(R* d):
  // eta_t / eta_n = sqrt(4 G* / E*), a constant (computed once: it costs a division and a root).
  double tangential_damping_ratio;

  // `rolling` is the contact's rolling history (read and updated by the spring-dashpot model only).
  ContactForce evaluate(const ContactKinematics& k, Vec3& spring, Vec3& rolling, double dt) const {
    const double sqrt_r_overlap = std::sqrt(k.r_eff * k.overlap);
    double damping_n;
    const double fn = contact_detail::normal_force(c, k, sqrt_r_overlap, damping_n);
    const Vec3 vt = k.velocity - dot(k.velocity, k.normal) * k.normal;
    // The stored displacement follows the contact plane: its normal part is dropped (as in
    // LAMMPS gran/hertz/history; the length lost is second order in the rotation).
    spring -= dot(spring, k.normal) * k.normal;
    spring += vt * dt;
    const double kt = 8.0 * c.g_star * sqrt_r_overlap;
    const double eta_t = damping_n * tangential_damping_ratio;
    Vec3 ft = -kt * spring - eta_t * vt;
    // Sliding: cap at mu F_n and keep the spring that gives just that force (k_t > 0 in contact).
    const double cap = c.friction * fn;
    const double ft2 = norm2(ft);
    if (ft2 > cap * cap) {
      ft = ft * (cap / std::sqrt(ft2));
      spring = (ft + eta_t * vt) * (-1.0 / kt);
    }
    return {ft - fn * k.normal, ft, contact_detail::rolling_torque(c, k, fn, rolling, dt), fn};
  }
  // A contact without rolling history (a law with none, or one step of a fresh contact).
  ContactForce evaluate(const ContactKinematics& k, Vec3& spring, double dt) const {
    Vec3 rolling{};
    return evaluate(k, spring, rolling, dt);
  }
};

// The paper's law (Fu and Dekelbab 2003, eq. 4): Hertz normal force and friction mu F_n
// against the sliding velocity, with no tangential spring, so a contact never sticks. The
// restitution damping of the normal force is kept (set restitution = 1 to drop it).
struct SlidingFrictionFu2003 {
  ContactCoefficients c;

  ContactForce evaluate(const ContactKinematics& k, Vec3& spring, Vec3& rolling, double dt) const {
    const double sqrt_r_overlap = std::sqrt(k.r_eff * k.overlap);
    double damping_n;
    const double fn = contact_detail::normal_force(c, k, sqrt_r_overlap, damping_n);
    const Vec3 vt = k.velocity - dot(k.velocity, k.normal) * k.normal;
    const double speed = std::max(norm(vt), kFrictionRegularisation);
    const Vec3 ft = vt * (-c.friction * fn / speed);
    spring = {};
    return {ft - fn * k.normal, ft, contact_detail::rolling_torque(c, k, fn, rolling, dt), fn};
  }
  ContactForce evaluate(const ContactKinematics& k, Vec3& spring, double dt) const {
    Vec3 rolling{};
    return evaluate(k, spring, rolling, dt);
  }
};

using ContactLaw = std::variant<HertzMindlin, SlidingFrictionFu2003>;

// One law for particle-particle contacts and one for particle-wall contacts, of the same kind.
// A run of several materials (materials > 1) has one of each per pair of materials, all of one
// kind: pairs[a * materials + b] (the same law for (b, a)) and walls[a]; `particle` and `wall`
// are then material 0's.
struct ContactModel {
  ContactLaw particle;
  ContactLaw wall;
  std::size_t materials = 1;
  std::vector<ContactLaw> pairs, walls;
};

// What a user states; the law's name is looked up in contact_laws() (contact_law_registry.hpp).
struct ContactParameters {
  std::string friction_model = "mindlin";  // a name of contact_laws()
  double youngs_modulus = 50e9;            // Pa
  double poisson_ratio = 0.25;
  double wall_youngs_modulus = 200e9;      // Pa (steel)
  double wall_poisson_ratio = 0.3;
  double friction_particle = 0.17;
  double friction_wall = 0.17;
  double restitution = 0.5;
  double rolling_friction = 0.0;
  RollingModel rolling_model = RollingModel::ConstantTorque;
  double rolling_stiffness = 0.0;  // N/m, spring_dashpot only (> 0 there)
  double rolling_damping = 0.0;    // N s/m, spring_dashpot only
};

// Throws InputError naming the parameter, its value and the allowed range.
void check_contact_parameters(const ContactParameters& p);
// The model of one material (materials.hpp has the model of several).
ContactModel make_contact_model(const ContactParameters& p);

}  // namespace aggpack
