#pragma once
#include <cstdint>

namespace aggpack {

// xoshiro256** seeded through SplitMix64. Sampling goes through our own uniform()
// so that a seed gives the same numbers with every standard library.
class Rng {
 public:
  // One independent stream per (seed, purpose): stages never share a stream.
  Rng(std::uint64_t seed, std::uint64_t purpose);

  std::uint64_t next_u64();
  // Uniform in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(next_u64() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  // Uniform integer in [0, n), n > 0, without modulo bias.
  std::uint64_t below(std::uint64_t n);
  // In xoshiro's one state that never leaves itself (all zero: every number 0); no seed
  // gives it, a damaged checkpoint might.
  [[nodiscard]] bool stuck() const { return (s_[0] | s_[1] | s_[2] | s_[3]) == 0; }

 private:
  std::uint64_t s_[4];
};

// Named purposes, so that adding a stage never shifts another stage's numbers.
enum class RngPurpose : std::uint64_t {
  Sizes = 1,
  Deposition = 2,
  Dynamics = 3,
  Analysis = 4,
  Pour = 5,
  Shapes = 6,
  GrainTemplates = 7,  // which template each grain of a run is
};

inline Rng make_rng(std::uint64_t seed, RngPurpose purpose) {
  return Rng(seed, static_cast<std::uint64_t>(purpose));
}

}  // namespace aggpack
