#pragma once
#include <array>
#include <cstddef>
#include <optional>
#include <vector>

#include "aggpack/core/enum_names.hpp"
#include "aggpack/core/rng.hpp"

namespace aggpack {

// One size class: a diameter with either a particle count or a solid volume fraction.
struct SizeClass {
  double diameter = 0.0;  // m
  std::optional<std::size_t> count;
  std::optional<double> volume_fraction;
};

enum class SizeOrder { Shuffled, AsListed };
inline constexpr std::array kSizeOrderNames{EnumName<SizeOrder>{SizeOrder::Shuffled, "shuffled"},
                                            EnumName<SizeOrder>{SizeOrder::AsListed, "as_listed"}};

// Monosized is a single class with a count. Classes given by volume fraction need
// either total_count or solid_volume to say how much to generate.
struct SizeSpec {
  std::vector<SizeClass> classes;
  std::optional<std::size_t> total_count;
  std::optional<double> solid_volume;  // m^3
  SizeOrder order = SizeOrder::Shuffled;
};

// Particle diameters in drop order. Throws InputError for an inconsistent spec.
std::vector<double> generate_diameters(const SizeSpec& spec, Rng& rng);

// Counts per class for classes given by volume fraction: the generated solid volume per
// class matches the fractions to within one particle (largest-remainder rounding).
std::vector<std::size_t> class_counts(const SizeSpec& spec);

}  // namespace aggpack
