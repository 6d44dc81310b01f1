#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "aggpack/core/enum_names.hpp"
#include "aggpack/core/rng.hpp"
#include "aggpack/sizes/grading.hpp"

namespace aggpack {

// How a grading becomes particle diameters (docs/method.md section 2):
//   Mass   (default): the generated volume per sieve interval matches the curve. Within an
//          interval the volume is uniform in log diameter, the same law as the curve between
//          sieves, so the number density there goes as d^-4.
//   Number: the paper's Eq. (11): a uniform percentage inverts the curve, read as a number
//          fraction, linearly in diameter within the interval. For reproducing the paper only:
//          it makes far too few fines by volume.
enum class SamplingMode { Mass, Number };
inline constexpr std::array kSamplingModeNames{EnumName<SamplingMode>{SamplingMode::Mass, "mass"},
                                               EnumName<SamplingMode>{SamplingMode::Number, "number"}};

// The part of a grading that is generated: [d_lo, d_hi] after the cut-offs, with the volume
// fractions cut off below d_min (including anything finer than the smallest sieve) and above
// d_max. The remaining curve is renormalised proportionally to 100 % over [d_lo, d_hi].
struct GradingCut {
  Grading grading;            // the input curve
  double d_lo = 0.0, d_hi = 0.0;  // m
  double cut_below = 0.0;     // volume fraction removed below d_lo (0..1)
  double cut_above = 0.0;     // volume fraction removed above d_hi (0..1)
  // Percent passing of the renormalised curve (0 at d_lo, 100 at d_hi).
  [[nodiscard]] double renormalised_passing(double d) const;
};
// Throws InputError (naming `source`) when the cut-offs leave nothing.
GradingCut cut_grading(const Grading& grading, std::optional<double> d_min, std::optional<double> d_max,
                       const std::string& source);

// Draws diameters one at a time.
class GradingSampler {
 public:
  GradingSampler(GradingCut cut, SamplingMode mode);
  double draw(Rng& rng) const;
  [[nodiscard]] const GradingCut& cut() const { return cut_; }
  // Expected volume of one drawn particle (m^3): how many particles a solid volume takes.
  [[nodiscard]] double mean_particle_volume() const { return mean_volume_; }

 private:
  struct Interval {
    double lo, hi;        // diameters, m
    double p_lo, p_hi;    // renormalised percent passing at lo and hi
    double weight;        // probability of drawing a particle from this interval
  };
  GradingCut cut_;
  SamplingMode mode_;
  std::vector<Interval> intervals_;
  std::vector<double> cumulative_;  // of the weights
  double mean_volume_ = 0.0;
};

// How much to generate: a number of particles, or a solid volume (m^3; generation stops at
// the first particle that reaches it).
struct Amount {
  std::optional<std::size_t> count;
  std::optional<double> solid_volume;
};
std::vector<double> sample_diameters(const GradingSampler& sampler, const Amount& amount, Rng& rng);

// Coarse and fine aggregate at a coarse/fine volume ratio. Interleaved (the paper's order):
// one coarse particle, then fine particles until the running fine volume reaches the coarse
// volume / ratio, repeated; the amount counts both. Shuffled: the same particles, shuffled.
enum class MixOrder { Interleaved, Shuffled };
inline constexpr std::array kMixOrderNames{EnumName<MixOrder>{MixOrder::Interleaved, "interleaved"},
                                           EnumName<MixOrder>{MixOrder::Shuffled, "shuffled"}};
// `is_fine`, when given, receives 1 for each fine particle, in the same order.
std::vector<double> sample_mix(const GradingSampler& coarse, const GradingSampler& fine, double coarse_to_fine,
                               const Amount& amount, MixOrder order, Rng& rng,
                               std::vector<std::uint8_t>* is_fine = nullptr);

// What was generated, against the target: percent passing by mass at every input sieve.
struct GradingReportRow {
  Sieve sieve;             // the target (renormalised to the generated range)
  double generated = 0.0;  // percent passing by mass of the generated particles
};
struct GradingReport {
  std::size_t count = 0;
  double solid_volume = 0.0;
  double d_min = 0.0, d_max = 0.0;   // of the generated particles
  double d10 = 0.0, d50 = 0.0, d90 = 0.0;  // by mass, of the generated particles
  double fineness_modulus = 0.0;      // of the generated particles
  std::vector<GradingReportRow> rows;
  double largest_deviation = 0.0;     // percentage points, over the rows
};
GradingReport report_generated(const std::vector<double>& diameters, const GradingCut& target);

}  // namespace aggpack
