#include "aggpack/sizes/grading_sampler.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"

namespace aggpack {

namespace {
double volume(double d) { return std::numbers::pi / 6.0 * d * d * d; }
}  // namespace

double GradingCut::renormalised_passing(double d) const {
  if (d <= d_lo) return 0.0;
  if (d >= d_hi) return 100.0;
  const double lo = percent_passing_at(grading, d_lo), hi = percent_passing_at(grading, d_hi);
  return 100.0 * (percent_passing_at(grading, d) - lo) / (hi - lo);
}

GradingCut cut_grading(const Grading& grading, std::optional<double> d_min, std::optional<double> d_max,
                       const std::string& source) {
  GradingCut cut{grading, grading.smallest(), grading.largest(), 0.0, 0.0};
  if (d_min) cut.d_lo = std::max(cut.d_lo, *d_min);
  if (d_max) cut.d_hi = std::min(cut.d_hi, *d_max);
  const double p_lo = percent_passing_at(grading, cut.d_lo), p_hi = percent_passing_at(grading, cut.d_hi);
  if (!(cut.d_lo < cut.d_hi) || !(p_hi > p_lo))
    throw InputError(fmt::format("{}: the cut-offs d_min = {:g} m and d_max = {:g} m leave nothing of grading '{}' "
                                 "(it has material between {:g} m and {:g} m)",
                                 source, d_min.value_or(cut.d_lo), d_max.value_or(cut.d_hi), grading.name,
                                 grading.smallest(), grading.largest()));
  cut.cut_below = p_lo / 100.0;
  cut.cut_above = (100.0 - p_hi) / 100.0;
  return cut;
}

GradingSampler::GradingSampler(GradingCut cut, SamplingMode mode) : cut_(std::move(cut)), mode_(mode) {
  // Interval bounds: d_lo, the sieves inside (d_lo, d_hi), d_hi.
  std::vector<double> bounds{cut_.d_lo};
  for (const Sieve& s : cut_.grading.sieves)
    if (s.opening > cut_.d_lo && s.opening < cut_.d_hi) bounds.push_back(s.opening);
  bounds.push_back(cut_.d_hi);
  double total = 0.0;
  for (std::size_t i = 1; i < bounds.size(); ++i) {
    Interval in{bounds[i - 1], bounds[i], cut_.renormalised_passing(bounds[i - 1]),
                cut_.renormalised_passing(bounds[i]), 0.0};
    const double fraction = (in.p_hi - in.p_lo) / 100.0;
    const double a = in.lo, b = in.hi;
    double interval_mean_volume = 0.0;
    if (mode_ == SamplingMode::Number) {
      in.weight = fraction;  // the curve read as a number fraction
      interval_mean_volume = std::numbers::pi / 6.0 * (std::pow(b, 4) - std::pow(a, 4)) / (4.0 * (b - a));
    } else {
      // Volume uniform in log d: number density ~ d^-4, mean particle volume
      // (pi/6) ln(b/a) / ((a^-3 - b^-3) / 3).
      interval_mean_volume = std::numbers::pi / 6.0 * std::log(b / a) * 3.0 / (std::pow(a, -3) - std::pow(b, -3));
      in.weight = fraction / interval_mean_volume;
    }
    if (in.weight <= 0.0) continue;
    total += in.weight;
    mean_volume_ += in.weight * interval_mean_volume;
    intervals_.push_back(in);
    cumulative_.push_back(total);
  }
  for (double& c : cumulative_) c /= total;
  mean_volume_ /= total;
}

double GradingSampler::draw(Rng& rng) const {
  const double u = rng.uniform();
  const std::size_t i = std::min<std::size_t>(
      static_cast<std::size_t>(std::upper_bound(cumulative_.begin(), cumulative_.end(), u) - cumulative_.begin()),
      intervals_.size() - 1);
  const Interval& in = intervals_[i];
  const double v = rng.uniform();
  if (mode_ == SamplingMode::Number) return in.lo + v * (in.hi - in.lo);  // Eq. (11): linear in d
  // Inverse of the number CDF for density ~ d^-4 on [a, b].
  const double a3 = std::pow(in.lo, -3), b3 = std::pow(in.hi, -3);
  return std::pow(a3 - v * (a3 - b3), -1.0 / 3.0);
}

std::vector<double> sample_diameters(const GradingSampler& sampler, const Amount& amount, Rng& rng) {
  std::vector<double> d;
  if (amount.count) {
    d.reserve(*amount.count);
    for (std::size_t i = 0; i < *amount.count; ++i) d.push_back(sampler.draw(rng));
    return d;
  }
  double total = 0.0;
  while (total < amount.solid_volume.value_or(0.0)) {
    d.push_back(sampler.draw(rng));
    total += volume(d.back());
  }
  return d;
}

std::vector<double> sample_mix(const GradingSampler& coarse, const GradingSampler& fine, double coarse_to_fine,
                               const Amount& amount, MixOrder order, Rng& rng, std::vector<std::uint8_t>* is_fine) {
  std::vector<double> d;
  std::vector<std::uint8_t> fine_flags;
  double coarse_volume = 0.0, fine_volume = 0.0;
  const auto done = [&] {
    if (amount.count) return d.size() >= *amount.count;
    return coarse_volume + fine_volume >= amount.solid_volume.value_or(0.0);
  };
  while (!done()) {
    d.push_back(coarse.draw(rng));
    fine_flags.push_back(0);
    coarse_volume += volume(d.back());
    while (!done() && fine_volume < coarse_volume / coarse_to_fine) {
      d.push_back(fine.draw(rng));
      fine_flags.push_back(1);
      fine_volume += volume(d.back());
    }
  }
  if (order == MixOrder::Shuffled)
    for (std::size_t i = d.size(); i > 1; --i) {
      const std::size_t j = rng.below(i);
      std::swap(d[i - 1], d[j]);
      std::swap(fine_flags[i - 1], fine_flags[j]);
    }
  if (is_fine) *is_fine = std::move(fine_flags);
  return d;
}

GradingReport report_generated(const std::vector<double>& diameters, const GradingCut& target) {
  GradingReport r;
  r.count = diameters.size();
  if (diameters.empty()) return r;
  std::vector<double> sorted(diameters);
  std::sort(sorted.begin(), sorted.end());
  r.d_min = sorted.front();
  r.d_max = sorted.back();
  std::vector<double> cumulative(sorted.size());
  double total = 0.0;
  for (std::size_t i = 0; i < sorted.size(); ++i) cumulative[i] = (total += volume(sorted[i]));
  r.solid_volume = total;
  const auto passing = [&](double opening) {
    const auto it = std::upper_bound(sorted.begin(), sorted.end(), opening);
    return it == sorted.begin() ? 0.0 : 100.0 * cumulative[static_cast<std::size_t>(it - sorted.begin()) - 1] / total;
  };
  const auto size_at = [&](double percent) {
    const auto it = std::lower_bound(cumulative.begin(), cumulative.end(), percent / 100.0 * total);
    return sorted[std::min(sorted.size() - 1, static_cast<std::size_t>(it - cumulative.begin()))];
  };
  r.d10 = size_at(10);
  r.d50 = size_at(50);
  r.d90 = size_at(90);
  for (const Sieve& s : target.grading.sieves) {
    Sieve t = s;
    t.percent_passing = target.renormalised_passing(s.opening);
    const double g = passing(s.opening);
    r.rows.push_back({t, g});
    r.largest_deviation = std::max(r.largest_deviation, std::abs(g - t.percent_passing));
  }
  double fm = 0.0;
  for (double opening : fineness_modulus_sieves()) fm += 100.0 - passing(opening);
  r.fineness_modulus = fm / 100.0;
  return r;
}

}  // namespace aggpack
