#include "aggpack/io/dem_setup.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/dynamics/contact_law_registry.hpp"

namespace aggpack {

DemSetup dem_setup(const Scenario& sc, double r_min, int threads) {
  const DynamicsStage& stage = *sc.dynamics;
  if (!std::isfinite(r_min))
    throw InputError(fmt::format("{}: [dynamics]: there are no particles to settle", sc.file.string()));
  const std::vector<ContactParameters> contacts = material_contacts(sc);
  // Each material's parameters, checked first so that an error names its table.
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    try {
      check_contact_parameters(contacts[k]);
    } catch (const InputError& e) {
      throw InputError(fmt::format("{}: [{}]: {}", sc.file.string(),
                                   k == 0 ? std::string("material") : fmt::format("materials.{}", material_name(sc, k)), e.what()));
    }
  }
  DemSetup setup{make_contact_model(contacts, sc.material_pairs),
                 stage.dem, stable_time_scale(sc, r_min)};
  setup.settings.time_step = stage.time_step.step(setup.rayleigh);
  setup.settings.threads = threads;
  return setup;
}

double stable_time_scale(const Scenario& sc, double r_min) {
  double scale = std::numeric_limits<double>::infinity();
  for (const std::size_t k : used_materials(sc))
    scale = std::min(scale, stable_time_scale(material_of(sc, k).contact, r_min, material_of(sc, k).density));
  return scale;
}

double largest_impact_overlap(const Scenario& sc, double r_min, double speed) {
  const ContactParameters& walls = sc.material.contact;
  double overlap = 0.0;
  for (const std::size_t k : used_materials(sc)) {
    const Material& m = material_of(sc, k);
    const double e_star = effective_youngs_modulus(m.contact.youngs_modulus, m.contact.poisson_ratio,
                                                   walls.wall_youngs_modulus, walls.wall_poisson_ratio);
    const double mass = ParticleStore::sphere_mass(r_min, m.density);
    overlap = std::max(overlap, std::pow(15.0 * mass * speed * speed / (16.0 * e_star * std::sqrt(r_min)), 0.4));
  }
  return overlap;
}

}  // namespace aggpack
