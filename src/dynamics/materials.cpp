#include "aggpack/dynamics/materials.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/dynamics/contact_law_registry.hpp"

namespace aggpack {

namespace {

const MaterialPairCoefficients* given_pair(std::span<const MaterialPairCoefficients> pairs, std::size_t a,
                                           std::size_t b) {
  const auto [lo, hi] = std::minmax(a, b);
  for (const MaterialPairCoefficients& p : pairs)
    if (p.first == lo && p.second == hi) return &p;
  return nullptr;
}

// The pair's own value where it gives one, else the mixing rule's.
double coefficient(const std::optional<double>* given, double a, double b) {
  return given != nullptr && given->has_value() ? **given : mixed_coefficient(a, b);
}

// The rolling law's kind is the run's (material 0's); its spring the material's or the pair's.
void set_rolling(ContactCoefficients& c, const ContactParameters& run, double stiffness, double damping) {
  const bool spring_dashpot = run.rolling_model == RollingModel::SpringDashpot;
  c.rolling_model = run.rolling_model;
  c.rolling_stiffness = spring_dashpot ? stiffness : 0.0;
  c.rolling_damping = spring_dashpot ? damping : 0.0;
}

}  // namespace

PairValues pair_values(std::span<const ContactParameters> materials, std::span<const MaterialPairCoefficients> pairs,
                       std::size_t a, std::size_t b) {
  const ContactParameters &pa = materials[a], &pb = materials[b];
  const MaterialPairCoefficients* given = given_pair(pairs, a, b);
  const auto value = [&](const std::optional<double> MaterialPairCoefficients::*member, double of_a, double of_b) {
    return coefficient(given != nullptr ? &(given->*member) : nullptr, of_a, of_b);
  };
  using P = MaterialPairCoefficients;
  return {value(&P::restitution, pa.restitution, pb.restitution),
          value(&P::friction, pa.friction_particle, pb.friction_particle),
          value(&P::rolling_friction, pa.rolling_friction, pb.rolling_friction),
          value(&P::rolling_stiffness, pa.rolling_stiffness, pb.rolling_stiffness),
          value(&P::rolling_damping, pa.rolling_damping, pb.rolling_damping)};
}

ContactCoefficients pair_coefficients(std::span<const ContactParameters> materials,
                                      std::span<const MaterialPairCoefficients> pairs, std::size_t a, std::size_t b) {
  const ContactParameters &pa = materials[a], &pb = materials[b];
  const PairValues v = pair_values(materials, pairs, a, b);
  ContactCoefficients c;
  c.e_star = effective_youngs_modulus(pa.youngs_modulus, pa.poisson_ratio, pb.youngs_modulus, pb.poisson_ratio);
  c.g_star = effective_shear_modulus(pa.youngs_modulus, pa.poisson_ratio, pb.youngs_modulus, pb.poisson_ratio);
  c.damping = damping_for_restitution(v.restitution);
  c.friction = v.friction;
  c.rolling = v.rolling_friction;
  set_rolling(c, materials[0], v.rolling_stiffness, v.rolling_damping);
  return c;
}

ContactCoefficients wall_coefficients(std::span<const ContactParameters> materials, std::size_t a) {
  const ContactParameters &pa = materials[a], &run = materials[0];
  ContactCoefficients c;
  c.e_star = effective_youngs_modulus(pa.youngs_modulus, pa.poisson_ratio, run.wall_youngs_modulus,
                                      run.wall_poisson_ratio);
  c.g_star = effective_shear_modulus(pa.youngs_modulus, pa.poisson_ratio, run.wall_youngs_modulus,
                                     run.wall_poisson_ratio);
  c.damping = damping_for_restitution(pa.restitution);
  c.friction = pa.friction_wall;
  c.rolling = pa.rolling_friction;
  // LAMMPS's fix wall/gran takes the particles' sds coefficients: the wall has none of its own.
  set_rolling(c, run, pa.rolling_stiffness, pa.rolling_damping);
  return c;
}

ContactModel make_contact_model(std::span<const ContactParameters> materials,
                                std::span<const MaterialPairCoefficients> pairs) {
  for (std::size_t k = 0; k < materials.size(); ++k) {
    try {
      check_contact_parameters(materials[k]);
    } catch (const InputError& e) {
      if (materials.size() == 1) throw;
      throw InputError(fmt::format("material {}: {}", k, e.what()));
    }
  }
  const ContactLawEntry& law = contact_law(materials[0].friction_model);
  const std::size_t n = materials.size();
  ContactModel model{law.make(pair_coefficients(materials, pairs, 0, 0)), law.make(wall_coefficients(materials, 0)), 1,
                     {}, {}};
  if (n == 1) return model;
  model.materials = n;
  for (std::size_t a = 0; a < n; ++a) {
    model.walls.push_back(law.make(wall_coefficients(materials, a)));
    for (std::size_t b = 0; b < n; ++b) model.pairs.push_back(law.make(pair_coefficients(materials, pairs, a, b)));
  }
  return model;
}

}  // namespace aggpack
