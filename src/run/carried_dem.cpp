#include "aggpack/run/carried_dem.hpp"

#include <algorithm>
#include <limits>
#include <sstream>

#include <fmt/format.h>

#include "core/archive.hpp"

namespace aggpack {

namespace {

// Whether `system` is what a system made now on `particles` with `settings` and `frozen` would
// be: the same particles, time step, skin, gravity and frozen ones (threads do not change results).
bool made_alike(const DemSystem& system, const ParticleStore& particles, const DemSettings& settings,
                const std::vector<std::uint8_t>& frozen) {
  if (system.particle_count() != particles.size()) return false;
  double r_min = std::numeric_limits<double>::infinity();
  for (const double r : particles.radius) r_min = std::min(r_min, r);
  const double skin = settings.skin > 0.0 ? settings.skin : DemSystem::default_skin(r_min);
  const DemSettings& made = system.settings();
  if (made.time_step != settings.time_step || system.skin() != skin || !(made.gravity == settings.gravity))
    return false;
  for (std::size_t i = 0; i < particles.size(); ++i)
    if (system.is_frozen(i) != (!frozen.empty() && frozen[i] != 0)) return false;
  return true;
}

}  // namespace

CarriedDem::ForStep CarriedDem::system_for(ParticleStore& particles, const Container& container,
                                           const ContactModel& model, const DemSettings& settings,
                                           std::vector<std::uint8_t> frozen) {
  if (system_ && made_alike(*system_, particles, settings, frozen)) return {*system_, true};
  system_.reset();  // before the new one is made: two systems of a large bed need not fit
  system_ = std::make_unique<DemSystem>(particles, container, model, settings, std::move(frozen));
  return {*system_, false};
}

std::string CarriedDem::save() const {
  std::ostringstream out;
  {
    cereal::BinaryOutputArchive ar(out);
    const bool held = holds();
    ar(held);
    if (!held) return out.str();
    // What the system was made with: its settings (its skin as chosen) and frozen particles.
    DemSettings made = system_->settings();
    made.skin = system_->skin();
    std::vector<std::uint8_t> frozen(system_->particle_count());
    for (std::size_t i = 0; i < frozen.size(); ++i) frozen[i] = system_->is_frozen(i) ? 1 : 0;
    ar(raw_value(made.gravity), made.time_step, made.skin, frozen);
  }
  system_->save_state(out);
  return out.str();
}

void CarriedDem::restore(std::string_view bytes, ParticleStore& particles, const Container& container,
                         const SetupFor& setup_for) {
  system_.reset();
  DemSettings saved;
  std::vector<std::uint8_t> frozen;
  std::size_t state_at = 0;
  try {
    CheckedInputArchive ar(bytes);
    bool held = false;
    ar(held);
    if (!held) {
      if (ar.left() > 0) throw InputError("bytes after an empty DEM state");
      return;
    }
    ar(raw_value(saved.gravity), saved.time_step, saved.skin, frozen);
    state_at = ar.position();
  } catch (const cereal::Exception& e) {
    throw InputError(fmt::format("the carried DEM state: {}", e.what()));
  }
  if (frozen.size() != particles.size()) throw InputError("the carried DEM state does not fit the bed");
  for (const std::uint8_t f : frozen)
    if (f > 1) throw InputError("the carried DEM state's frozen flags");
  // The settings a step of this scenario makes, never the bytes' own: a skin or a time step
  // from damaged bytes would size the neighbour grid and the lists beyond any bound.
  DemSetup setup = setup_for(frozen);
  double r_min = std::numeric_limits<double>::infinity();
  for (const double r : particles.radius) r_min = std::min(r_min, r);
  const double skin = setup.settings.skin > 0.0 ? setup.settings.skin : DemSystem::default_skin(r_min);
  if (!(saved.gravity == setup.settings.gravity) || saved.time_step != setup.settings.time_step || saved.skin != skin)
    throw InputError("the carried DEM state's settings are not the scenario's");
  setup.settings.skin = skin;
  try {
    system_ = std::make_unique<DemSystem>(particles, container, setup.model, setup.settings, std::move(frozen));
    system_->restore_state(bytes.substr(state_at));
  } catch (...) {
    system_.reset();  // nothing half-restored is carried on
    throw;
  }
}

}  // namespace aggpack
