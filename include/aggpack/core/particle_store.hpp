#pragma once
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "aggpack/core/quaternion.hpp"
#include "aggpack/core/vec3.hpp"

namespace aggpack {

inline constexpr std::uint32_t kNoBody = 0xFFFFFFFFu;  // a sphere of no rigid body

// Rigid bodies of several spheres (grains), one entry per body. A body's member spheres are
// spheres of the store, contiguous, and move with it. The body frame has its origin at the
// centre of mass and its axes along the principal axes of inertia.
struct RigidBodies {
  std::vector<std::uint32_t> first_member;  // the store index of its first member sphere
  std::vector<std::uint32_t> member_count;
  std::vector<Vec3> position;               // of the centre of mass, m
  std::vector<Quaternion> orientation;      // body frame to space
  std::vector<Vec3> velocity;               // of the centre of mass, m/s
  std::vector<Vec3> angular_velocity;       // rad/s, in space
  std::vector<double> mass;                 // kg, of the members' union (each point once)
  std::vector<double> volume;               // m^3, of the members' union
  std::vector<Vec3> principal_inertia;      // kg m^2, about the body frame's axes
  std::vector<std::uint32_t> shape;         // its shape's id (RigidBodyShape::id: a run's template)
  [[nodiscard]] std::size_t size() const { return mass.size(); }
  [[nodiscard]] bool empty() const { return mass.empty(); }
};

// A rigid body's shape in its body frame (centre of mass at the origin, principal axes of
// inertia along x, y and z): its member spheres and the mass properties of their union,
// every length multiplied by `scale` (the volume by its cube, the moments by its fifth power).
struct RigidBodyShape {
  std::span<const Vec3> member_centres;  // m
  std::span<const double> member_radii;  // m
  double volume = 0.0;                   // of the members' union, m^3
  Vec3 principal_inertia_per_density;    // m^5
  double scale = 1.0;
  std::uint32_t id = 0;  // what the caller calls this shape (a run: its template's index)
  // The farthest point of its members from its centre of mass, m (scaled).
  [[nodiscard]] double reach() const;
};

// Every stage reads and writes this one store. Index i is the same grain in every
// array; i is also the placement order and the particle id in output files.
struct ParticleStore {
  std::vector<Vec3> position;          // m
  std::vector<Vec3> velocity;          // m/s
  std::vector<Vec3> angular_velocity;  // rad/s
  std::vector<double> radius;          // m
  std::vector<double> mass;            // kg
  std::vector<std::uint32_t> layer;    // deposition layer, 0 for a single pass
  std::vector<std::uint8_t> material;  // index into the run's materials (0: the scenario's [material])
  // Per sphere, once the store has a rigid body (empty before): the body it is a member of
  // (kNoBody for a sphere of its own), and its centre in that body's frame. A member's mass
  // is that of its own sphere; its body's is the union's (bodies.mass).
  std::vector<std::uint32_t> body;
  std::vector<Vec3> body_offset;  // m
  RigidBodies bodies;

  // The only way to grow the store. Solid sphere of the given density (kg/m^3).
  std::size_t add(const Vec3& pos, double r, double density, std::uint32_t layer_index = 0,
                  std::uint8_t material_index = 0);
  // Adds a rigid body of `shape` and `density` (kg/m^3), its centre of mass at `centre` and
  // turned by `orientation`, at rest: its member spheres go to the end of the store, the body
  // to the end of `bodies`. Returns the body's index. Throws std::invalid_argument for a shape
  // without members, of member lists of two lengths, or of a volume, a moment or a scale not
  // positive.
  std::size_t add_body(const Vec3& centre, const Quaternion& orientation, const RigidBodyShape& shape, double density,
                       std::uint32_t layer_index = 0, std::uint8_t material_index = 0);
  // The mass add() gives a sphere of radius r, kg.
  [[nodiscard]] static double sphere_mass(double r, double density);

  [[nodiscard]] std::size_t size() const { return radius.size(); }
  [[nodiscard]] bool empty() const { return radius.empty(); }
  void reserve(std::size_t n);
};

// What the spheres of a sequence (a drop sequence, a pour's part) are made of: a material
// index per sphere and each material's density. How a stage adds spheres of several materials.
struct SphereMaterials {
  std::span<const std::uint8_t> of;  // per sphere of the sequence; empty: all material 0
  std::span<const double> density;   // kg/m^3, per material
  [[nodiscard]] std::uint8_t material(std::size_t k) const { return of.empty() ? 0 : of[k]; }
  [[nodiscard]] double density_of(std::size_t k) const { return density[material(k)]; }
  // Spheres all of one material of this density (which must outlive the view).
  [[nodiscard]] static SphereMaterials all_of(const double& density) { return {{}, {&density, 1}}; }
  // The spheres [begin, begin + count) of the sequence.
  [[nodiscard]] SphereMaterials part(std::size_t begin, std::size_t count) const {
    return {of.empty() ? of : of.subspan(begin, count), density};
  }
};

}  // namespace aggpack
