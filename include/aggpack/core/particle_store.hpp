#pragma once
#include <cstddef>
#include <cstdint>
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

  // The only way to grow the store. Solid sphere of the given density (kg/m^3).
  std::size_t add(const Vec3& pos, double r, double density, std::uint32_t layer_index = 0);
  // The mass add() gives a sphere of radius r, kg.
  [[nodiscard]] static double sphere_mass(double r, double density);

  [[nodiscard]] std::size_t size() const { return radius.size(); }
  [[nodiscard]] bool empty() const { return radius.empty(); }
  void reserve(std::size_t n);
};

}  // namespace aggpack
