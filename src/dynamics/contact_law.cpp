#include "aggpack/dynamics/contact_law.hpp"

#include "aggpack/dynamics/contact_law_registry.hpp"
#include "aggpack/dynamics/materials.hpp"

#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"

namespace aggpack {

double effective_youngs_modulus(double e_a, double nu_a, double e_b, double nu_b) {
  return 1.0 / ((1.0 - nu_a * nu_a) / e_a + (1.0 - nu_b * nu_b) / e_b);
}

double effective_shear_modulus(double e_a, double nu_a, double e_b, double nu_b) {
  const double g_a = e_a / (2.0 * (1.0 + nu_a));
  const double g_b = e_b / (2.0 * (1.0 + nu_b));
  return 1.0 / ((2.0 - nu_a) / g_a + (2.0 - nu_b) / g_b);
}

double hertz_static_overlap(double weight, double e_star, double r_star) {
  return std::pow(3.0 * weight / (4.0 * e_star * std::sqrt(r_star)), 2.0 / 3.0);
}

double hertz_contact_time(double m_star, double r_star, double e_star, double speed) {
  // Dimensionless elastic impact x'' = -x^(3/2), x'(0) = 1: it lasts
  // 2 x_max int_0^1 du / sqrt(1 - u^(5/2)) with x_max = (5/4)^(2/5); the integral is
  // (2/5) B(2/5, 1/2). Time unit (m / k)^(2/5) v^(-1/5), k = (4/3) E* sqrt(R*).
  const double integral = 0.4 * std::tgamma(0.4) * std::tgamma(0.5) / std::tgamma(0.9);
  const double tau = 2.0 * std::pow(1.25, 0.4) * integral;
  const double k = (4.0 / 3.0) * e_star * std::sqrt(r_star);
  return tau * std::pow(m_star / k, 0.4) * std::pow(speed, -0.2);
}

double rayleigh_time(double radius, double density, double youngs_modulus, double poisson_ratio) {
  const double shear_modulus = youngs_modulus / (2.0 * (1.0 + poisson_ratio));
  return std::numbers::pi * radius * std::sqrt(density / shear_modulus) / (0.1631 * poisson_ratio + 0.8766);
}

double restitution_of_damping(double a) {
  // x'' = f(x, v) = -x^(3/2) - a x^(1/4) v from x = 0, v = 1, by RK4; the contact ends
  // when the (clamped) force would pull, or when x returns to 0.
  const auto accel = [a](double x, double v) {
    const double xp = std::max(x, 0.0);
    return -xp * std::sqrt(xp) - a * std::sqrt(std::sqrt(xp)) * v;
  };
  const double h = 2e-4;  // e to about 1e-6
  double x = 0.0, v = 1.0;
  for (int step = 0; step < 10'000'000; ++step) {
    const double k1x = v, k1v = accel(x, v);
    const double k2x = v + 0.5 * h * k1v, k2v = accel(x + 0.5 * h * k1x, v + 0.5 * h * k1v);
    const double k3x = v + 0.5 * h * k2v, k3v = accel(x + 0.5 * h * k2x, v + 0.5 * h * k2v);
    const double k4x = v + h * k3v, k4v = accel(x + h * k3x, v + h * k3v);
    const double x_next = x + h / 6.0 * (k1x + 2 * k2x + 2 * k3x + k4x);
    const double v_next = v + h / 6.0 * (k1v + 2 * k2v + 2 * k3v + k4v);
    if (v_next < 0.0) {
      // Force = x^(1/4) (x^(5/4) + a v) in magnitude terms; it changes sign where g does.
      const auto g = [a](double xx, double vv) { return std::pow(std::max(xx, 0.0), 1.25) + a * vv; };
      const double g0 = g(x, v), g1 = g(x_next, v_next);
      if (g1 <= 0.0) {
        const double t = g0 > 0.0 ? g0 / (g0 - g1) : 0.0;
        return -(v + t * (v_next - v));
      }
      if (x_next <= 0.0) {
        const double t = x / (x - x_next);
        return -(v + t * (v_next - v));
      }
    }
    x = x_next;
    v = v_next;
  }
  return 0.0;
}

double damping_for_restitution(double e) {
  if (!(e > 0.0 && e <= 1.0))
    throw InputError(fmt::format("restitution {} is outside (0, 1]", e));
  if (e == 1.0) return 0.0;
  double lo = 0.0, hi = 1.0;
  while (restitution_of_damping(hi) > e) hi *= 2.0;
  for (int iteration = 0; iteration < 40; ++iteration) {
    const double mid = 0.5 * (lo + hi);
    (restitution_of_damping(mid) > e ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

namespace {

void require(bool ok, const char* name, double value, const char* range) {
  if (!ok) throw InputError(fmt::format("{} = {} is out of range: expected {}", name, value, range));
}

}  // namespace

void check_contact_parameters(const ContactParameters& p) {
  require(p.youngs_modulus > 0.0, "youngs_modulus", p.youngs_modulus, "> 0 Pa");
  require(p.wall_youngs_modulus > 0.0, "wall_youngs_modulus", p.wall_youngs_modulus, "> 0 Pa");
  require(p.poisson_ratio > -1.0 && p.poisson_ratio < 0.5, "poisson_ratio", p.poisson_ratio, "in (-1, 0.5)");
  require(p.wall_poisson_ratio > -1.0 && p.wall_poisson_ratio < 0.5, "wall_poisson_ratio", p.wall_poisson_ratio,
          "in (-1, 0.5)");
  require(p.friction_particle >= 0.0, "friction_particle", p.friction_particle, ">= 0");
  require(p.friction_wall >= 0.0, "friction_wall", p.friction_wall, ">= 0");
  require(p.restitution > 0.0 && p.restitution <= 1.0, "restitution", p.restitution, "in (0, 1]");
  require(p.rolling_friction >= 0.0, "rolling_friction", p.rolling_friction, ">= 0");
  if (p.rolling_model == RollingModel::SpringDashpot) {
    require(p.rolling_stiffness > 0.0, "rolling_stiffness", p.rolling_stiffness, "> 0 N/m with rolling_model spring_dashpot");
    require(p.rolling_damping >= 0.0, "rolling_damping", p.rolling_damping, ">= 0 N s/m");
  }
}

ContactModel make_contact_model(const ContactParameters& p) { return make_contact_model(std::span(&p, 1), {}); }

}  // namespace aggpack
