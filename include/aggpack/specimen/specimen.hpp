#pragma once
// A concrete specimen cut out of a packed bed, for finite-element and lattice meso-models: the
// region (a box or a vertical cylinder), the aggregate (the bed's particles that reach into it,
// those below a size left to the mortar, as modellers treat fines), an interfacial transition
// zone (ITZ) of a given thickness around each kept particle, and the exact volumes the
// exports are checked against (voxel_image.hpp, gmsh_geometry.hpp).
#include <cstddef>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "aggpack/analysis/sphere_cylinder_volume.hpp"
#include "aggpack/core/box.hpp"
#include "aggpack/core/vec3.hpp"
#include "aggpack/grains/union_mass_properties.hpp"

namespace aggpack {

using SpecimenRegion = std::variant<Box, VerticalCylinder>;
[[nodiscard]] Box region_bounds(const SpecimenRegion& region);
[[nodiscard]] double region_volume(const SpecimenRegion& region);
[[nodiscard]] bool region_contains(const SpecimenRegion& region, const Vec3& p);
// "box [..] x [..] x [..] m" or "cylinder of radius .. m about (x, y), z from .. to .. m", for messages.
[[nodiscard]] std::string region_text(const SpecimenRegion& region);

// The particles of a bed: spheres, each of its particle (a grain's members share one).
struct PackedParticles {
  std::vector<MemberSphere> spheres;
  std::vector<std::size_t> particle_of_sphere;
  // Per particle: its size as a sieve sees it (a sphere's diameter; a grain's intermediate
  // dimension I, the one a sieve's square opening passes).
  std::vector<double> particle_size;
};

struct SpecimenOptions {
  SpecimenRegion region;
  double min_size = 0.0;       // m: smaller particles are left to the mortar
  double itz_thickness = 0.0;  // m; 0: no ITZ
  // m: each kept sphere's radius less half of it, so that touching particles stand this far
  // apart (a mesher cannot follow two spheres that touch at a point); 0: as packed.
  double gap = 0.0;
};

struct Specimen {
  SpecimenRegion region;
  double min_size = 0.0, itz_thickness = 0.0, gap = 0.0;
  // The kept particles' spheres that reach into the region (with their ITZ), each radius less gap / 2.
  std::vector<MemberSphere> spheres;
  // Each sphere's particle (0 up, in the order kept; a grain's spheres next to each other).
  std::vector<std::size_t> particle_of_sphere;
  std::size_t kept_particles = 0;
  std::size_t dropped_particles = 0;  // below min_size, reaching into the region
  // Kept particles that reached into the region (with their ITZ) by less than gap / 2: shrunk
  // by the gap they reach in no more, and are in no export.
  std::size_t left_out_by_gap = 0;
  // The kept and the dropped particles' volume inside the region: exact for spheres (and for
  // grains in a box, each grain's union to 1e-9); in a cylinder a grain counts by its spheres'
  // shares (its union's volume times the fraction of its spheres' summed volume inside).
  double aggregate_volume = 0.0, dropped_volume = 0.0;
  std::string volume_method;
  [[nodiscard]] double aggregate_fraction() const { return aggregate_volume / region_volume(region); }
};

// The specimen the options cut from `bed`. Throws InputError when the region is degenerate or
// holds no kept particle.
[[nodiscard]] Specimen cut_specimen(const PackedParticles& bed, const SpecimenOptions& options);

}  // namespace aggpack
