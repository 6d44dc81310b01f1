#pragma once
#include <string>

#include <fmt/format.h>

namespace aggpack {

// What a concrete lab reports of a compacted or loose aggregate (ASTM C29/C29M, EN 1097-3): the
// dry bulk density, the packing density times the particles' density (the "relative density"
// of the grains, oven-dry), and the voids content, the volume between the grains, 100 (1 - phi) %.
struct BulkDensity {
  double packing_density = 0.0;   // solid fraction phi
  double particle_density = 0.0;  // kg/m3
  double voids_percent = 0.0;
  double kg_per_m3 = 0.0;
  double lb_per_ft3 = 0.0;
};

inline constexpr double kKgPerM3InLbPerFt3 = 0.45359237 / (0.3048 * 0.3048 * 0.3048);  // 16.018 kg/m3

inline BulkDensity bulk_density(double packing_density, double particle_density) {
  const double kg = packing_density * particle_density;
  return {packing_density, particle_density, 100.0 * (1.0 - packing_density), kg, kg / kKgPerM3InLbPerFt3};
}

// "voids 39.6 %, dry bulk density 1600 kg/m3 (99.9 lb/ft3)"
inline std::string describe(const BulkDensity& b) {
  return fmt::format("voids {:.1f} %, dry bulk density {:.0f} kg/m3 ({:.1f} lb/ft3)", b.voids_percent, b.kg_per_m3,
                     b.lb_per_ft3);
}

}  // namespace aggpack
