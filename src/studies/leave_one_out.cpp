#include "aggpack/studies/leave_one_out.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <tuple>

#include "aggpack/core/error.hpp"
#include "aggpack/studies/whole_grading.hpp"

namespace aggpack {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double standard_error(const SeedStatistics& s) {
  return s.count >= 2 ? s.sd / std::sqrt(static_cast<double>(s.count)) : kNaN;
}

// Every grid interval on which the curve, read as straight, meets `target`, and where, in grid
// order (a crossing at a grid value two intervals share counted once; a NaN never crosses).
std::vector<std::pair<std::size_t, double>> crossings(const GridCurve& c, double target) {
  std::vector<std::pair<std::size_t, double>> found;
  for (std::size_t k = 0; k + 1 < c.values.size(); ++k) {
    const double a = c.density[k].mean, b = c.density[k + 1].mean;
    if (!((a - target) * (b - target) <= 0.0)) continue;
    const double at = a == b ? c.values[k] : c.values[k] + (target - a) * (c.values[k + 1] - c.values[k]) / (b - a);
    const double value = std::clamp(at, c.values[k], c.values[k + 1]);  // rounding stays inside the interval
    if (!found.empty() && found.back().second == value) continue;
    found.emplace_back(k, value);
  }
  return found;
}

// Where the curve first meets `target`, or the grid end whose density is nearer to it.
double crossing_or_nearer_end(const GridCurve& c, double target) {
  if (const auto all = crossings(c, target); !all.empty()) return all.front().second;
  return std::abs(c.density.front().mean - target) <= std::abs(c.density.back().mean - target) ? c.values.front()
                                                                                               : c.values.back();
}

// The lowest and highest density of the curve over [low, high]: at its ends and at every grid
// value between them (a curve that is not monotone may turn inside).
std::pair<double, double> range_on_grid(const GridCurve& c, double low, double high) {
  const double a = density_on_grid(c, low), b = density_on_grid(c, high);
  double lo = std::min(a, b), hi = std::max(a, b);
  for (std::size_t k = 0; k < c.values.size(); ++k)
    if (c.values[k] > low && c.values[k] < high)
      lo = std::min(lo, c.density[k].mean), hi = std::max(hi, c.density[k].mean);
  return {lo, hi};
}

double slope_per_10_points(const std::vector<double>& fa, const std::vector<double>& density) {
  return 10.0 * fit_line(fa, density).slope;
}

}  // namespace

double density_on_grid(const GridCurve& c, double value) {
  for (std::size_t k = 0; k + 1 < c.values.size(); ++k)
    if (value >= c.values[k] && value <= c.values[k + 1]) {
      const double t = (value - c.values[k]) / (c.values[k + 1] - c.values[k]);
      return c.density[k].mean + t * (c.density[k + 1].mean - c.density[k].mean);
    }
  throw InputError(
      fmt::format("mix {}: {:g} lies outside the grid {:g}-{:g}", c.mix, value, c.values.front(), c.values.back()));
}

std::optional<GridCrossing> crossing_on_grid(const GridCurve& c, double target) {
  GridCrossing crossing;
  std::size_t around = 0;  // the grid interval whose two values' scatter makes the band
  if (const auto all = crossings(c, target); !all.empty()) {
    around = all.front().first;
    crossing.value = all.front().second;
    crossing.crossings = all.size();
  } else {
    const std::size_t last = c.values.size() - 1;
    const auto miss = [&](std::size_t k) { return std::abs(target - c.density[k].mean); };
    const auto within = [&](std::size_t k) { return miss(k) <= standard_error(c.density[k]); };
    if (!within(0) && !within(last)) return std::nullopt;
    const bool front = within(0) && (!within(last) || miss(0) <= miss(last));
    crossing.value = front ? c.values.front() : c.values.back();
    around = front ? 0 : last - 1;
    crossing.at_end = true;
  }
  const double noise = std::max(standard_error(c.density[around]), standard_error(c.density[around + 1]));
  if (std::isnan(noise)) {
    crossing.band_low = crossing.band_high = kNaN;
  } else {
    const double a = crossing_or_nearer_end(c, target - noise), b = crossing_or_nearer_end(c, target + noise);
    crossing.band_low = std::min({a, b, crossing.value});
    crossing.band_high = std::max({a, b, crossing.value});
  }
  return crossing;
}

LeaveOneOutStudy leave_one_out(const std::vector<GridCurve>& curves) {
  if (curves.size() < 3)
    throw InputError(fmt::format(
        "calibrating on one blend and predicting the others needs three blends or more, not {}", curves.size()));
  for (const GridCurve& c : curves)
    if (c.values != curves.front().values || c.density.size() != c.values.size() || c.values.size() < 2 ||
        std::adjacent_find(c.values.begin(), c.values.end(), std::greater_equal<>()) != c.values.end())
      throw InputError(fmt::format(
          "mix {}: every blend must be simulated on the same grid of two values or more, strictly ascending", c.mix));
  LeaveOneOutStudy study;
  std::vector<double> all_fa, all_measured;
  for (const GridCurve& c : curves) all_fa.push_back(c.fa_percent), all_measured.push_back(c.measured);
  study.lab_slope_per_10 = slope_per_10_points(all_fa, all_measured);

  for (std::size_t k = 0; k < curves.size(); ++k) {
    const GridCurve& calibration = curves[k];
    LeaveOneOutChoice choice;
    choice.calibration_mix = calibration.mix;
    choice.fa_percent = calibration.fa_percent;
    choice.fitted = crossing_on_grid(calibration, calibration.measured);
    choice.mean_absolute_error = choice.largest_error = choice.slope_per_10 = choice.lab_slope_per_10 = kNaN;
    if (!choice.fitted) {
      choice.why_not_fitted = fmt::format(
          "out of reach: {:.4f} at {:g} to {:.4f} at {:g}, measured {:.3f}", calibration.density.front().mean,
          calibration.values.front(), calibration.density.back().mean, calibration.values.back(), calibration.measured);
      study.choices.push_back(std::move(choice));
      continue;
    }
    const GridCrossing& fit = *choice.fitted;
    std::vector<double> fa, predicted, measured;
    double sum_abs = 0.0;
    choice.largest_error = 0.0;
    for (std::size_t o = 0; o < curves.size(); ++o) {
      if (o == k) continue;
      const GridCurve& other = curves[o];
      PredictedBlend p{other.mix, other.fa_percent, other.measured, density_on_grid(other, fit.value), kNaN, kNaN};
      if (!std::isnan(fit.band_low))
        std::tie(p.band_low, p.band_high) = range_on_grid(other, fit.band_low, fit.band_high);
      const double error = p.density - p.measured;
      sum_abs += std::abs(error);
      if (std::abs(error) > std::abs(choice.largest_error)) choice.largest_error = error;
      fa.push_back(p.fa_percent), predicted.push_back(p.density), measured.push_back(p.measured);
      choice.predicted.push_back(p);
    }
    choice.mean_absolute_error = sum_abs / static_cast<double>(choice.predicted.size());
    choice.slope_per_10 = slope_per_10_points(fa, predicted);
    choice.lab_slope_per_10 = slope_per_10_points(fa, measured);
    study.choices.push_back(std::move(choice));
  }

  std::vector<std::size_t> fitted;
  for (std::size_t k = 0; k < study.choices.size(); ++k)
    if (study.choices[k].fitted) fitted.push_back(k);
  std::stable_sort(fitted.begin(), fitted.end(), [&](std::size_t a, std::size_t b) {
    return study.choices[a].mean_absolute_error < study.choices[b].mean_absolute_error;
  });
  if (!fitted.empty()) study.median = fitted[(fitted.size() - 1) / 2];
  return study;
}

}  // namespace aggpack
