#pragma once

#include "aggpack/dynamics/contact_law.hpp"
#include "aggpack/dynamics/dem_system.hpp"
#include "aggpack/io/scenario.hpp"

namespace aggpack {

// What every DEM run of a scenario shares: the contact model and the settings, with the time
// step for the smallest free sphere of radius r_min (its Rayleigh time kept for the report; of
// several materials, the shortest of any at that radius).
struct DemSetup {
  ContactModel model;
  DemSettings settings;
  double rayleigh = 0.0;
};
DemSetup dem_setup(const Scenario& sc, double r_min, int threads);
// The contact law's stable time scale for the scenario's materials at radius r_min: the
// shortest of any material a component is made of.
double stable_time_scale(const Scenario& sc, double r_min);
// The deepest overlap of a sphere of radius r_min hitting the floor at `speed` (Hertz), of
// any material a component is made of.
double largest_impact_overlap(const Scenario& sc, double r_min, double speed);

}  // namespace aggpack
