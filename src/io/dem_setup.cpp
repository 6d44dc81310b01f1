#include "aggpack/io/dem_setup.hpp"

#include <cmath>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/dynamics/contact_law_registry.hpp"

namespace aggpack {

DemSetup dem_setup(const Scenario& sc, double r_min, int threads) {
  const DynamicsStage& stage = *sc.dynamics;
  if (!std::isfinite(r_min))
    throw InputError(fmt::format("{}: [dynamics]: there are no particles to settle", sc.file.string()));
  DemSetup setup{[&] {
                   try {
                     return make_contact_model(sc.material.contact);
                   } catch (const InputError& e) {
                     throw InputError(fmt::format("{}: [material]: {}", sc.file.string(), e.what()));
                   }
                 }(),
                 stage.dem, stable_time_scale(sc.material.contact, r_min, sc.material.density)};
  setup.settings.time_step = stage.time_step.step(setup.rayleigh);
  setup.settings.threads = threads;
  return setup;
}

}  // namespace aggpack
