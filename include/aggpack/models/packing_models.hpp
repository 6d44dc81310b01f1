#pragma once
// Analytic packing models: the density of a size distribution in milliseconds, beside every
// simulation (README, "Analytic packing models"). Depends on sizes only.
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "aggpack/sizes/grading.hpp"

namespace aggpack {

// One size class of a model: the spheres of a sieve fraction [d_lo, d_hi] (d_lo = d_hi for
// one size), standing at `diameter`, and their share of the solid volume.
struct ModelClass {
  double diameter = 0.0;          // m: the equivalent diameter
  double d_lo = 0.0, d_hi = 0.0;  // m
  double volume_fraction = 0.0;   // of the solids; the classes of a distribution sum to 1
  bool fine = false;              // from the fine aggregate of a blend
};

// A size distribution as the models see it: classes from the coarsest to the finest.
struct ModelDistribution {
  std::vector<ModelClass> classes;
  std::string rule;  // how the classes were made, for the output
};

// The sieve fractions of a grading between d_min and d_max (none: the whole curve), each at the
// geometric mean of its two sieves (de Larrard's equivalent diameter), renormalised to 1. The
// whole curve keeps what passes its smallest sieve as one class [smallest / 2, smallest].
ModelDistribution grading_classes(const Grading& grading, std::optional<double> d_min = std::nullopt,
                                  std::optional<double> d_max = std::nullopt);
// Coarse and fine at a coarse/fine volume ratio.
ModelDistribution blend(const ModelDistribution& coarse, const ModelDistribution& fine, double coarse_to_fine);
// Spheres of given diameters (m): equal diameters (within 1e-9) are one class; a distribution
// of more than `max_classes` distinct sizes is binned into classes of ratio 2^(1/4) in diameter.
ModelDistribution diameter_classes(std::span<const double> diameters, std::size_t max_classes = 64);

// --- de Larrard's Compressible Packing Model (CPM) ---
// F. de Larrard, Concrete Mixture Proportioning: A Scientific Approach, E & FN Spon 1999, ch. 1.
// Classes i = 1..n from coarse to fine, volume fractions y_i, residual packing densities beta_i
// (the virtual packing density of class i alone). With class i dominant, the virtual packing
// density is
//   gamma_i = beta_i / (1 - sum_{j<i} [1 - beta_i + b_ij beta_i (1 - 1/beta_j)] y_j
//                         - sum_{j>i} [1 - a_ij beta_i / beta_j] y_j),
// with the loosening effect of the finer class j on i, a_ij = sqrt(1 - (1 - d_j/d_i)^1.02), and
// the wall effect of the coarser class j on i, b_ij = 1 - (1 - d_i/d_j)^1.50. The virtual
// packing density of the mix is gamma = min_i gamma_i. The actual density phi of a packing made
// by a process of compaction index K solves
//   K = sum_i (y_i / beta_i) / (1/phi - 1/gamma_i),
// so that one class packs at beta / (1 + 1/K), and K -> infinity gives the virtual packing.
// K by process (de Larrard 1999, Table 1.2): 4.1 poured, 4.5 rodded, 4.75 vibrated, 9 vibrated
// and compressed under 10 kPa.
// The exponents of the two interaction functions: de Larrard's published 1.02 and 1.50 (fitted on
// lab blends of rounded and crushed aggregates), or others (aggpack blend --interaction).
struct CpmInteraction {
  double loosening_exponent = 1.02;
  double wall_exponent = 1.50;
};
[[nodiscard]] double cpm_loosening(double d_fine, double d_coarse, double exponent = 1.02);  // a_ij, d_fine <= d_coarse
[[nodiscard]] double cpm_wall(double d_fine, double d_coarse, double exponent = 1.50);       // b_ij, d_fine <= d_coarse
struct CpmResult {
  double density = 0.0;          // phi
  double virtual_density = 0.0;  // gamma
  std::size_t dominant = 0;      // the class whose gamma_i is gamma
  std::vector<double> gamma;     // gamma_i
};
// InputError for an empty distribution, beta outside (0, 1) or K <= 0. `beta` has one value per
// class, or one for all.
CpmResult cpm(const ModelDistribution& distribution, std::span<const double> beta, double compaction_index,
              const CpmInteraction& interaction = {});
// The K that gives density `phi` (0 < phi < gamma): the model's own relation read backwards,
// for calibration.
[[nodiscard]] double cpm_compaction_index(const ModelDistribution& distribution, std::span<const double> beta,
                                          double phi);
// The residual packing density that gives one class density `phi` at index K: phi (1 + 1/K).
[[nodiscard]] double cpm_beta_from_monosized(double phi, double compaction_index);

// The compaction index of a named process (de Larrard 1999, Table 1.2): "poured" 4.1, "rodded"
// 4.5, "vibrated" 4.75, "vibrated_compressed" 9; none for another name.
[[nodiscard]] std::optional<double> compaction_index_of(std::string_view process);

// --- Furnas's binary limit ---
// C. C. Furnas, Grading aggregates I, Ind. Eng. Chem. 23 (1931) 1052: at an infinite size
// ratio the fine spheres fill the coarse packing's voids without disturbing it, so the bulk
// volume per unit of solid is the larger of y_c / phi_c (the coarse skeleton holds it) and
// y_c + y_f / phi_f (the coarse spheres sit in the fine packing). The density of a binary mix
// of fine volume fraction y_f, with each size alone packing at phi_c and phi_f; the densest is
// phi_c + phi_f - phi_c phi_f, at y_f = (1 - phi_c) phi_f / (phi_c + phi_f - phi_c phi_f).
[[nodiscard]] double furnas_binary(double phi_coarse, double phi_fine, double fine_fraction);
[[nodiscard]] double furnas_densest(double phi_coarse, double phi_fine);
[[nodiscard]] double furnas_densest_fine_fraction(double phi_coarse, double phi_fine);

// --- Desmond and Weeks's random close packing ---
// K. W. Desmond and E. R. Weeks, Influence of particle size distribution on random close
// packing of spheres, Phys. Rev. E 90 (2014) 022204: phi_rcp = 0.634 + 0.0658 delta + 0.0857 S
// delta^2, with delta the polydispersity (standard deviation of the radius / its mean) and S
// the skewness of the radius distribution by number; an empirical fit to simulated packings of
// moderate polydispersity (delta up to about 0.4; beyond, an extrapolation).
struct RadiusMoments {
  double polydispersity = 0.0;  // delta
  double skewness = 0.0;        // S
};
// By number, each sieve fraction spread uniformly in log diameter by volume (as the grading
// sampler draws it: number density ~ d^-4), each single size as it is.
RadiusMoments radius_moments(const ModelDistribution& distribution);
RadiusMoments radius_moments(std::span<const double> diameters);
[[nodiscard]] double desmond_weeks_rcp(const RadiusMoments& moments);
inline constexpr double kDesmondWeeksValidPolydispersity = 0.4;

}  // namespace aggpack
