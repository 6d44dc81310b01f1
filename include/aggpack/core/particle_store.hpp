#pragma once
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "aggpack/core/vec3.hpp"

namespace aggpack {

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

  // The only way to grow the store. Solid sphere of the given density (kg/m^3).
  std::size_t add(const Vec3& pos, double r, double density, std::uint32_t layer_index = 0,
                  std::uint8_t material_index = 0);
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
