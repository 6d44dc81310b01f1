#pragma once
#include <span>
#include <vector>

#include "aggpack/core/box.hpp"
#include "aggpack/core/container.hpp"
#include "aggpack/core/particle_store.hpp"

namespace aggpack {

// The container of a packing made elsewhere: the bounding box of its spheres, with walls.
Container bounding_container(const ParticleStore& particles);

// Exact solid volume of all spheres inside `box`. In a periodic container the images
// of spheres that cross the x or y boundary count too.
double solid_volume_in_box(const ParticleStore& particles, const Container& container, const Box& box);

// Where the bed is: the floor is the container's; the free surface is the equivalent
// height floor + V_solid / (A_footprint * phi_bulk), phi_bulk the median solid fraction of
// horizontal slices one d_max thick (capped at the highest sphere top; a grain split among
// the slices by its spheres' shares of their summed volume). A rough top layer counts by how
// full it is.
struct BedGeometry {
  double floor = 0.0;    // m
  double surface = 0.0;  // m
  double top = 0.0;      // highest sphere top, m
  double d_min = 0.0;    // m
  double d_max = 0.0;    // m
};
BedGeometry measure_bed(const ParticleStore& particles, const Container& container);

// The virtual box of method.md: a cube of side `side`, centred horizontally in the
// container and vertically between the floor and the free surface. Throws InputError
// naming the limit when the cube comes closer than d_max to a side wall (unless
// periodic), the floor or the free surface.
Box place_virtual_cube(double side, const Container& container, const BedGeometry& bed);

struct BoxDensity {
  double side = 0.0;  // m (the x side for a non-cubic box)
  Box box;
  double density = 0.0;
};
struct DensityResult {
  std::vector<BoxDensity> boxes;
  double mean = 0.0;
  double sd = 0.0;  // sample standard deviation (n - 1), 0 for a single box
};
DensityResult measure_density(const ParticleStore& particles, const Container& container,
                              std::span<const Box> boxes);

// Solid fraction in horizontal slices of the footprint, bottom to top, each slice exact.
struct Profile {
  std::vector<double> position;  // slice or shell centre, m
  std::vector<double> solid_fraction;
};
Profile vertical_profile(const ParticleStore& particles, const Container& container, double thickness);

// Solid fraction in square shells by distance from the nearest side wall (walls only),
// between heights z_lo and z_hi, each shell exact; in a cylinder, rings by distance from its
// wall (a sphere's exact, a grain's by its spheres' shares).
Profile wall_distance_profile(const ParticleStore& particles, const Container& container,
                              double thickness, double z_lo, double z_hi);

}  // namespace aggpack
