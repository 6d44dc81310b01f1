#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "aggpack/core/container.hpp"
#include "aggpack/core/particle_store.hpp"
#include "aggpack/dynamics/dem_system.hpp"
#include "aggpack/io/dem_setup.hpp"

namespace aggpack {

// The DEM system that a run's consecutive DEM steps continue (a pour then its taps, a settling
// then taps), contact history and all, as LAMMPS keeps one system through an input deck: a tap
// starts from the springs the pour built. A step that changes the bed outside the DEM (a
// deposition, an import) drops it, and so does a DEM step whose own system would be made
// otherwise (another time step or skin, other frozen particles): that step starts a new one.
class CarriedDem {
 public:
  // The system for a DEM step on `particles`: the carried one when a system made now with
  // `settings` and `frozen` (empty: none frozen) would be made alike, else a new one, carried
  // from then on.
  struct ForStep {
    DemSystem& system;
    bool continued;  // the system of the steps before
  };
  ForStep system_for(ParticleStore& particles, const Container& container, const ContactModel& model,
                     const DemSettings& settings, std::vector<std::uint8_t> frozen = {});
  // The bed was changed outside the DEM: the next DEM step starts afresh.
  void drop() { system_.reset(); }
  [[nodiscard]] bool holds() const { return system_ != nullptr; }

  // For a checkpoint between steps: the carried system (none: an empty state), and back onto
  // `particles` (the bed as the checkpoint holds it). DamagedCheckpoint-worthy InputError when
  // the bytes do not fit.
  [[nodiscard]] std::string save() const;
  // `setup_for` gives the model and settings a step would make a system with, for the
  // frozen flags the state holds (by particle; empty: none): the state's own settings must
  // be those, its skin that settings' or the default for the bed's smallest sphere.
  using SetupFor = std::function<DemSetup(const std::vector<std::uint8_t>& frozen)>;
  void restore(std::string_view bytes, ParticleStore& particles, const Container& container,
               const SetupFor& setup_for);

 private:
  std::unique_ptr<DemSystem> system_;
};

}  // namespace aggpack
