#pragma once
// The check of a blend's prediction against the DEM of the blend: two materials in a periodic bed
// by the procedure their betas were simulated by, at the fine volume percents asked, over seeds,
// beside CPM's packing at that procedure's K (docs/validation.md, "Blends: predicted against
// simulated"). `aggpack blend --check 30,40` and scripts/validate_blends.sh run it.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <ostream>
#include <span>
#include <string>
#include <vector>

#include "aggpack/blends/simulated_betas.hpp"
#include "aggpack/studies/campaign.hpp"

namespace aggpack {

// A material's betas for its classes above `d_min` (m) only, renormalised: the part of a sand a
// DEM of the blend can afford. A class that `d_min` cuts keeps its part above it (by volume,
// uniform in log size within the class, as the generator draws it).
MaterialBetas cut_below(const MaterialBetas& betas, double d_min);

struct BlendCheckOptions {
  std::filesystem::path coarse, fine;
  std::vector<double> percents;   // the fine's volume percent of the solid, each point
  double fine_d_min = 0.0;        // m: the fine cut there in the bed and in the prediction (0: none)
  double coarse_particles = 400;  // about, in each bed
  SimulatedBetaOptions betas;     // seeds, threads and bed size of the materials' betas; quiet
  CpmInteraction interaction;     // of the prediction (published: de Larrard's)
};

struct BlendCheckPoint {
  double percent = 0.0;
  std::vector<double> packing;  // each seed's bed
  SeedStatistics simulated;
  double predicted = 0.0, predicted_low = 0.0, predicted_high = 0.0;  // CPM, betas -+ sd
  double predicted_published = 0.0;                                   // CPM with de Larrard's interaction exponents
  std::size_t particles = 0;                                          // of the last seed's bed
  double wall_clock_s = 0.0;                                          // of its beds
};

struct BlendCheck {
  TestProcess process;         // of the beds: CPM is taken at its K
  std::string procedure;       // what was done to the beds
  MaterialBetas coarse, fine;  // as predicted with (the fine cut)
  CpmInteraction interaction;
  std::vector<BlendCheckPoint> points;
  std::vector<std::string> modelling;
  [[nodiscard]] double largest_difference() const;  // |predicted - simulated mean| over the points
};

// InputError before any run for a percent outside (0, 100), a cut above the fine's largest size,
// or materials whose betas were simulated by different procedures.
BlendCheck check_blend(const BlendCheckOptions& options, std::ostream& log);

// A check as to_json wrote it (a blend.json's "check"): its simulated points, materials and K,
// predicted again with `interaction`. InputError naming `file` for anything else.
BlendCheck read_blend_check(const nlohmann::json& check, const CpmInteraction& interaction,
                            const std::filesystem::path& file);
// The check's predictions made again with `interaction` (the simulated points kept).
void predict_again(BlendCheck& check, const CpmInteraction& interaction);

// The interaction exponents that bring CPM closest to the checks' simulated means (the largest
// difference over every point the least), searched on a grid of loosening exponents 0.02-3 and
// wall exponents 0.1-6, then refined: CPM's interaction functions fitted on DEM blends (never
// on a lab's). InputError for no point.
CpmInteraction fit_interaction(std::span<const BlendCheck> checks);
// The largest difference of the checks' points with `interaction`.
[[nodiscard]] double largest_difference(std::span<const BlendCheck> checks, const CpmInteraction& interaction);

nlohmann::json to_json(const BlendCheck& check);
std::string describe(const BlendCheck& check);

}  // namespace aggpack
