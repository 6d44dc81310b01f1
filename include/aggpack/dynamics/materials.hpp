#pragma once
#include <cmath>
#include <cstdint>
#include <optional>
#include <span>

#include "aggpack/dynamics/contact_law.hpp"

namespace aggpack {

// Contacts between grains of two materials (a stone and a sand) take E* and G* from both
// materials by Hertz's and Mindlin's formulas, and the coefficients below from the mixing rule
// (the geometric mean of the two materials' values, LAMMPS's own rule for friction and
// rolling resistance), unless a pair gives them, as LAMMPS's
// `pair_coeff I J` does. Materials are indices of the run's list (0 the scenario's [material]).
struct MaterialPairCoefficients {
  std::uint8_t first = 0, second = 0;
  std::optional<double> friction;          // Coulomb mu of the pair
  std::optional<double> restitution;       // in (0, 1]
  std::optional<double> rolling_friction;  // mu_r
  std::optional<double> rolling_stiffness; // k_roll, N/m (rolling_model = "spring_dashpot")
  std::optional<double> rolling_damping;   // gamma_roll, N s/m (the same)
};

// The mixing rule for a coefficient of two materials: their geometric mean.
[[nodiscard]] inline double mixed_coefficient(double a, double b) { return a == b ? a : std::sqrt(a * b); }

// The coefficients of a contact of materials a and b that are not moduli: the pair's own where
// [[material_pairs]] gives them, else the mixing rule's.
struct PairValues {
  double restitution = 0.0, friction = 0.0, rolling_friction = 0.0, rolling_stiffness = 0.0, rolling_damping = 0.0;
};
PairValues pair_values(std::span<const ContactParameters> materials, std::span<const MaterialPairCoefficients> pairs,
                       std::size_t a, std::size_t b);

// The contact model of a run whose materials are `materials` (index order; the law, the walls'
// E and nu and the rolling model are material 0's), with the pairs that give their own
// coefficients. One material and no pairs: make_contact_model(materials[0]). Throws
// InputError naming the material's parameter and its range.
ContactModel make_contact_model(std::span<const ContactParameters> materials,
                                std::span<const MaterialPairCoefficients> pairs);

// The coefficients of a contact of grains of materials a and b, and of a grain of material a
// with the walls (whose E and nu are material 0's).
ContactCoefficients pair_coefficients(std::span<const ContactParameters> materials,
                                      std::span<const MaterialPairCoefficients> pairs, std::size_t a, std::size_t b);
ContactCoefficients wall_coefficients(std::span<const ContactParameters> materials, std::size_t a);

}  // namespace aggpack
