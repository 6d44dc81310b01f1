#include "aggpack/dynamics/contact_law_registry.hpp"

#include <array>
#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "aggpack/core/error.hpp"

namespace aggpack {

namespace {

std::string rolling_text(const ContactParameters& p) {
  if (!(p.rolling_friction > 0)) return {};
  if (p.rolling_model == RollingModel::SpringDashpot)
    return fmt::format(", spring-dashpot rolling resistance (LAMMPS's sds: k_roll {:g} N/m, gamma_roll {:g} N s/m, "
                       "torque capped at {:g} R* F_n)",
                       p.rolling_stiffness, p.rolling_damping, p.rolling_friction);
  return fmt::format(", constant-torque rolling resistance {:g} (torque {:g} R* F_n against the relative spin)",
                     p.rolling_friction, p.rolling_friction);
}

// LAMMPS's hertz/material takes E, the damping coefficient (with `damping tsuji`, the
// restitution e) and nu of the material. limit_damping keeps the damped normal force from
// pulling, as aggpack's does. A wall (fix wall/gran, LAMMPS 2022) takes one E and nu for the
// contact, E* = E / (2 (1 - nu)) and G* = E / (4 (2 - nu)(1 + nu)) (checked: a sphere resting on
// the floor sinks by Hertz's overlap at that E*), not the sphere's and the wall's moduli
// together as aggpack's E* and G* do: the wall gets the E and nu that give aggpack's E* and G*.
// (Given the steel's own E, a wall of E/1000 spheres was 5000 times stiffer in LAMMPS.)
std::string lammps_normal(const ContactParameters& p, bool wall) {
  double e = p.youngs_modulus, nu = p.poisson_ratio;
  if (wall) {
    const double e_star = effective_youngs_modulus(p.youngs_modulus, p.poisson_ratio, p.wall_youngs_modulus,
                                                   p.wall_poisson_ratio);
    const double g_star = effective_shear_modulus(p.youngs_modulus, p.poisson_ratio, p.wall_youngs_modulus,
                                                  p.wall_poisson_ratio);
    // G*/E* = r = (1 - nu) / (2 (2 - nu)(1 + nu)): 2 r nu^2 - (2 r + 1) nu - (4 r - 1) = 0, the root below 1/2.
    const double r = g_star / e_star;
    nu = ((2.0 * r + 1.0) - std::sqrt((2.0 * r + 1.0) * (2.0 * r + 1.0) + 8.0 * r * (4.0 * r - 1.0))) / (4.0 * r);
    e = 2.0 * e_star * (1.0 - nu);
  }
  return fmt::format("hertz/material {:.9g} {:.9g} {:.9g} damping tsuji limit_damping", e, p.restitution, nu);
}

std::string lammps_rolling(const ContactParameters& p) {
  if (!(p.rolling_friction > 0)) return {};
  // sds: k_roll, gamma_roll, mu_roll. The spring-dashpot model is sds itself.
  if (p.rolling_model == RollingModel::SpringDashpot)
    return fmt::format(" rolling sds {:.9g} {:.9g} {:.9g}", p.rolling_stiffness, p.rolling_damping,
                       p.rolling_friction);
  // The constant torque mu_r R* F_n has no LAMMPS form: the closest is a stiff spring capped
  // at mu_roll, which reaches the cap at once.
  return fmt::format(" rolling sds 1e12 0 {:.9g}", p.rolling_friction);
}

// Said by every law's differences (lammps_differences).
#define AGGPACK_ROLLING_DIFFERENCES                                                                              \
  "; rolling resistance: with rolling_model = \"spring_dashpot\" both codes run LAMMPS's sds law (the same "  \
  "history, projection and cap), except that LAMMPS 2022 negates a contact's rolling history when the pair's " \
  "order in its neighbour list changes (as it does the tangential one), where the rolling history is the same " \
  "seen from either sphere (aggpack keeps it; on one rank a pour gave the same densities with LAMMPS's atom " \
  "sort on and off, docs/validation.md); with \"constant_torque\" " \
  "aggpack's torque is mu_r R* F_n against the relative spin at once, and LAMMPS's sds 1e12 0 mu_r a very stiff " \
  "spring that reaches the same cap within a step; LIGGGHTS's epsd2 is the same spring-dashpot form with its " \
  "k_r taken from the normal stiffness (2.25 mu_r^2 R*^2 k_n) where sds takes a constant"

const std::array<ContactLawEntry, 2> kLaws{{
    {"mindlin", "Hertz-Mindlin with history, restitution damping, Coulomb cap (recommended)",
     [](const ContactCoefficients& c) -> ContactLaw { return HertzMindlin{c}; },
     [](const ContactParameters& p) {
       return fmt::format(
           "dynamics: DEM with Hertz normal force, restitution damping (Tsuji form, e = {:g} solved exactly), Mindlin "
           "tangential spring with history capped by Coulomb friction (particle {:g}, wall {:g}){}; velocity Verlet",
           p.restitution, p.friction_particle, p.friction_wall, rolling_text(p));
     },
     [](const ContactParameters& p, bool wall) {
       const double g_star = effective_shear_modulus(p.youngs_modulus, p.poisson_ratio,
                                                     wall ? p.wall_youngs_modulus : p.youngs_modulus,
                                                     wall ? p.wall_poisson_ratio : p.poisson_ratio);
       const double e_star = effective_youngs_modulus(p.youngs_modulus, p.poisson_ratio,
                                                      wall ? p.wall_youngs_modulus : p.youngs_modulus,
                                                      wall ? p.wall_poisson_ratio : p.poisson_ratio);
       return fmt::format("{} tangential mindlin NULL {:.9g} {:.9g}{}", lammps_normal(p, wall),
                          std::sqrt(4.0 * g_star / e_star), wall ? p.friction_wall : p.friction_particle,
                          lammps_rolling(p));
     },
     "LAMMPS's tsuji damping maps e to the damping coefficient by a fitted polynomial, aggpack by solving the "
     "dimensionless impact exactly (the restitution differs by up to about 1 %); the tangential damping ratio "
     "sqrt(4 G*/E*) is given explicitly (LAMMPS's own default is 1)" AGGPACK_ROLLING_DIFFERENCES},
    {"fu2003", "the paper's sliding friction: mu F_n against the sliding velocity, no spring (never sticks)",
     [](const ContactCoefficients& c) -> ContactLaw { return SlidingFrictionFu2003{c}; },
     [](const ContactParameters& p) {
       return fmt::format(
           "dynamics: the paper's friction law (fu2003): Hertz normal force with restitution damping (e = {:g}) and "
           "sliding friction mu F_n against the sliding velocity (particle {:g}, wall {:g}), no tangential spring, so "
           "contacts never stick; kept for reproduction, not the recommended model{}",
           p.restitution, p.friction_particle, p.friction_wall, rolling_text(p));
     },
     [](const ContactParameters& p, bool wall) {
       // linear_nohistory: F_t = -min(mu F_n, gamma_t |v_t|) along v_t; a huge gamma_t makes it mu F_n.
       return fmt::format("{} tangential linear_nohistory 1e12 {:.9g}{}", lammps_normal(p, wall),
                          wall ? p.friction_wall : p.friction_particle, lammps_rolling(p));
     },
     "no exact LAMMPS equivalent: tangential linear_nohistory with a very large damping gives mu F_n against the "
     "sliding velocity, but caps at gamma_t |v_t| where aggpack regularises below 1e-6 m/s" AGGPACK_ROLLING_DIFFERENCES},
}};
#undef AGGPACK_ROLLING_DIFFERENCES

}  // namespace

std::span<const ContactLawEntry> contact_laws() { return kLaws; }

const ContactLawEntry& contact_law(std::string_view name) {
  for (const ContactLawEntry& law : kLaws)
    if (law.name == name) return law;
  std::vector<std::string_view> names;
  for (const ContactLawEntry& law : kLaws) names.push_back(law.name);
  throw InputError(fmt::format("friction_model \"{}\" is unknown: expected one of \"{}\"", name,
                               fmt::join(names, "\", \"")));
}

double stable_time_scale(const ContactParameters& parameters, double smallest_radius, double density) {
  return rayleigh_time(smallest_radius, density, parameters.youngs_modulus, parameters.poisson_ratio);
}

}  // namespace aggpack
