#pragma once
// A blend of materials by CPM, each class of each material at its own beta (material_betas.hpp):
// its packing fraction, voids and bulk density at given proportions, a sweep of them and the
// densest blend with its band. Milliseconds a point (README, "Blends of materials in seconds").
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "aggpack/blends/material_betas.hpp"

namespace aggpack {

// One blend: the materials' shares of the solid volume (absolute volumes, summing to 1).
struct BlendPoint {
  std::vector<double> volume_fractions;
  std::vector<double> mass_fractions;
  double packing = 0.0;                          // CPM's packing fraction at the process's K
  double packing_low = 0.0, packing_high = 0.0;  // every beta one sd lower, one sd higher
  double virtual_packing = 0.0;                  // CPM's gamma
  std::string dominant;                          // the class whose gamma_i is gamma: "material, d_lo-d_hi mm"
  double voids_percent = 0.0;                    // 100 (1 - packing)
  double particle_density_kg_m3 = 0.0;           // of the blend's solid
  double bulk_density_kg_m3 = 0.0;               // packing x particle density (oven-dry)
};

// InputError for fractions that are not one a material, non-negative and summing to 1 (within
// 1e-6), or for no material.
void check_volume_fractions(std::size_t materials, std::span<const double> volume_fractions);
// The blend's packing by CPM; its fractions checked as check_volume_fractions does.
BlendPoint predict_blend(std::span<const MaterialBetas> materials, std::span<const double> volume_fractions,
                         double compaction_index, const CpmInteraction& interaction = {});

// The densest of a curve and how sharp it is.
struct DensestBlend {
  std::size_t index = 0;  // into the curve's points
  // The points that could be the densest given the betas' spread: their packing_high reaches the
  // densest point's packing_low (the first and last such point; the densest alone when the betas
  // have no spread).
  std::size_t spread_first = 0, spread_last = 0;
  // The plateau: the points within kPlateau of the densest packing (the model's and the lab's
  // repeatability are about that).
  std::size_t plateau_first = 0, plateau_last = 0;
  static constexpr double kPlateau = 0.005;
};
DensestBlend densest(std::span<const BlendPoint> curve);

// The blends of two materials with the second at `percent` of the solid volume, each point.
// InputError unless the percents are in [0, 100].
std::vector<BlendPoint> sweep_binary(std::span<const MaterialBetas> materials, std::span<const double> percents,
                                     double compaction_index, const CpmInteraction& interaction = {});

// A sweep's percents from "FROM:TO:STEP" (percent; TO included when on the grid). InputError
// naming `option` for anything else, a step not positive, or more than 10001 points.
std::vector<double> parse_sweep(const std::string& text, const std::string& option);

}  // namespace aggpack
