#include "aggpack/io/dem_setup.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/dynamics/contact_law_registry.hpp"

namespace aggpack {

DemSetup dem_setup(const Scenario& sc, double r_min, int threads) {
  const DynamicsStage& stage = *sc.dynamics;
  if (!std::isfinite(r_min))
    throw InputError(fmt::format("{}: [dynamics]: there are no particles to settle", sc.file.string()));
  const std::vector<ContactParameters> contacts = material_contacts(sc);
  DemSetup setup{[&] {
                   try {
                     return make_contact_model(contacts, sc.material_pairs);
                   } catch (const InputError& e) {
                     throw InputError(fmt::format("{}: [material]: {}", sc.file.string(), e.what()));
                   }
                 }(),
                 stage.dem, stable_time_scale(sc, r_min)};
  setup.settings.time_step = stage.time_step.step(setup.rayleigh);
  setup.settings.threads = threads;
  return setup;
}

double stable_time_scale(const Scenario& sc, double r_min) {
  double scale = stable_time_scale(sc.material.contact, r_min, sc.material.density);
  for (const NamedMaterial& m : sc.materials)
    scale = std::min(scale, stable_time_scale(m.material.contact, r_min, m.material.density));
  return scale;
}

}  // namespace aggpack
