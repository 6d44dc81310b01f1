#pragma once
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "aggpack/dynamics/contact_law.hpp"

namespace aggpack {

// The one table of contact laws: the scenario's choice list (dynamics.friction_model), the
// modelling notes, make_contact_model and the LAMMPS bridge all read it. A new law is a new
// value type in contact_law.hpp and one entry here.
struct ContactLawEntry {
  std::string_view name;     // dynamics.friction_model
  std::string_view summary;  // a phrase for lists and help
  ContactLaw (*make)(const ContactCoefficients& coefficients);
  // The modelling note: the law and the parameters it was given, in words.
  std::string (*describe)(const ContactParameters& parameters);
  // The equivalent LAMMPS `pair_style granular` coefficients (`pair_coeff * *` for
  // particles; the same keywords after `fix wall/gran ... granular` for walls, which take the
  // wall's E and nu), and how the two codes' definitions differ.
  std::string (*lammps_keywords)(const ContactParameters& parameters, bool wall);
  std::string_view lammps_differences;
};

[[nodiscard]] std::span<const ContactLawEntry> contact_laws();
// Throws InputError naming the known laws.
[[nodiscard]] const ContactLawEntry& contact_law(std::string_view name);

// Both Hertz laws resolve a contact in a fraction of the Rayleigh-wave time of the smallest
// sphere; the time step's default is dynamics.time_step_safety times this.
[[nodiscard]] double stable_time_scale(const ContactParameters& parameters, double smallest_radius, double density);

// How a run's time step is chosen: given (dynamics.time_step), or a safety factor times the
// law's stable time scale.
struct TimeStepRule {
  std::optional<double> fixed;  // s
  double safety = 0.2;
  // The largest step, as a fraction of the stable time scale, that a run takes unless told
  // to (dynamics.allow_unstable_time_step). The paper's 1e-5 s is 0.49 of it for Example 2's
  // 1/2 in spheres and settles as LAMMPS does; at 0.75 a settled bed is already 5 % too dense.
  static constexpr double kStableFraction = 0.5;
  [[nodiscard]] double step(double time_scale) const { return fixed.value_or(safety * time_scale); }
};

}  // namespace aggpack
