#include "aggpack/sizes/size_spec.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

#include "aggpack/core/error.hpp"

namespace aggpack {

namespace {
double sphere_volume(double d) { return std::numbers::pi / 6.0 * d * d * d; }

// Rounds non-negative reals to integers with the given total, keeping each within one.
std::vector<std::size_t> largest_remainder(const std::vector<double>& ideal, std::size_t total) {
  std::vector<std::size_t> out(ideal.size());
  std::vector<std::pair<double, std::size_t>> remainder;
  std::size_t assigned = 0;
  for (std::size_t k = 0; k < ideal.size(); ++k) {
    out[k] = static_cast<std::size_t>(std::floor(ideal[k]));
    assigned += out[k];
    remainder.emplace_back(ideal[k] - std::floor(ideal[k]), k);
  }
  std::stable_sort(remainder.begin(), remainder.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });
  for (std::size_t n = 0; assigned < total && n < remainder.size(); ++n, ++assigned) ++out[remainder[n].second];
  return out;
}
}  // namespace

std::vector<std::size_t> class_counts(const SizeSpec& spec) {
  const bool by_count = std::all_of(spec.classes.begin(), spec.classes.end(),
                                    [](const SizeClass& c) { return c.count.has_value(); });
  std::vector<std::size_t> counts;
  if (by_count) {
    for (const auto& c : spec.classes) counts.push_back(*c.count);
    return counts;
  }
  double fraction_sum = 0.0;
  for (const auto& c : spec.classes) {
    if (!c.volume_fraction) throw InputError("size classes must all give a count or all give a volume_fraction");
    fraction_sum += *c.volume_fraction;
  }
  if (std::abs(fraction_sum - 1.0) > 1e-6)
    throw InputError("size class volume fractions must add up to 1 (they add up to " +
                     std::to_string(fraction_sum) + ")");
  std::vector<double> ideal;
  if (spec.solid_volume) {
    for (const auto& c : spec.classes) ideal.push_back(*spec.solid_volume * *c.volume_fraction / sphere_volume(c.diameter));
    std::vector<std::size_t> out;
    for (double v : ideal) out.push_back(static_cast<std::size_t>(std::llround(v)));
    return out;
  }
  if (!spec.total_count) throw InputError("size classes given by volume_fraction need a total count or a solid volume");
  // n_k proportional to f_k / v_k, scaled to the total count.
  double per_unit = 0.0;
  for (const auto& c : spec.classes) per_unit += *c.volume_fraction / sphere_volume(c.diameter);
  for (const auto& c : spec.classes)
    ideal.push_back(static_cast<double>(*spec.total_count) * (*c.volume_fraction / sphere_volume(c.diameter)) / per_unit);
  return largest_remainder(ideal, *spec.total_count);
}

std::vector<double> generate_diameters(const SizeSpec& spec, Rng& rng) {
  if (spec.classes.empty()) throw InputError("no size classes given");
  const std::vector<std::size_t> counts = class_counts(spec);
  std::vector<double> diameters;
  diameters.reserve(std::accumulate(counts.begin(), counts.end(), std::size_t{0}));
  for (std::size_t k = 0; k < counts.size(); ++k) diameters.insert(diameters.end(), counts[k], spec.classes[k].diameter);
  if (spec.order == SizeOrder::Shuffled)
    for (std::size_t i = diameters.size(); i > 1; --i) std::swap(diameters[i - 1], diameters[rng.below(i)]);
  return diameters;
}

}  // namespace aggpack
