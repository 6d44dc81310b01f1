#include "aggpack/models/packing_models.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"

namespace aggpack {

namespace {
void sort_coarse_first(std::vector<ModelClass>& classes) {
  std::stable_sort(classes.begin(), classes.end(),
                   [](const ModelClass& a, const ModelClass& b) { return a.diameter > b.diameter; });
}

void normalise(std::vector<ModelClass>& classes) {
  double total = 0.0;
  for (const ModelClass& c : classes) total += c.volume_fraction;
  if (!(total > 0.0)) throw InputError("the size distribution holds no solid volume");
  for (ModelClass& c : classes) c.volume_fraction /= total;
}
}  // namespace

ModelDistribution grading_classes(const Grading& g, std::optional<double> d_min, std::optional<double> d_max) {
  if (g.sieves.empty()) throw InputError(fmt::format("grading {}: no sieves", g.name));
  const double lo = std::max(d_min.value_or(0.0), g.smallest()), hi = std::min(d_max.value_or(g.largest()), g.largest());
  if (!(lo < hi))
    throw InputError(fmt::format("grading {}: nothing between {:.4g} m and {:.4g} m", g.name, lo, hi));
  // The sieve openings inside the cut, with the cut's own ends.
  std::vector<double> edges{lo};
  for (const Sieve& s : g.sieves)
    if (s.opening > lo && s.opening < hi) edges.push_back(s.opening);
  edges.push_back(hi);
  ModelDistribution out;
  for (std::size_t k = 0; k + 1 < edges.size(); ++k) {
    const double a = edges[k], b = edges[k + 1];
    const double fraction = (percent_passing_at(g, b) - percent_passing_at(g, a)) / 100.0;
    if (fraction > 0.0) out.classes.push_back({std::sqrt(a * b), a, b, fraction});
  }
  const bool whole = !d_min;
  const double pan = percent_passing_at(g, g.smallest()) / 100.0;
  if (whole && pan > 0.0) {
    const double s = g.smallest();
    out.classes.push_back({s / std::numbers::sqrt2, s / 2.0, s, pan});
  }
  sort_coarse_first(out.classes);
  normalise(out.classes);
  out.rule = fmt::format("sieve fractions of {} at the geometric mean of their sieves{}", g.name,
                         whole && pan > 0.0 ? "; what passes the smallest sieve as one class [s/2, s]" : "");
  return out;
}

ModelDistribution blend(const ModelDistribution& coarse, const ModelDistribution& fine, double coarse_to_fine) {
  if (!(coarse_to_fine > 0.0) || !std::isfinite(coarse_to_fine))
    throw InputError(fmt::format("the coarse/fine ratio {} is not a positive number", coarse_to_fine));
  ModelDistribution out;
  const double share = coarse_to_fine / (1.0 + coarse_to_fine);
  for (ModelClass c : coarse.classes) {
    c.volume_fraction *= share;
    out.classes.push_back(c);
  }
  for (ModelClass c : fine.classes) {
    c.volume_fraction *= 1.0 - share;
    c.fine = true;
    out.classes.push_back(c);
  }
  sort_coarse_first(out.classes);
  normalise(out.classes);
  out.rule = fmt::format("coarse ({}) and fine ({}) at a coarse/fine volume ratio of {:g}", coarse.rule, fine.rule,
                         coarse_to_fine);
  return out;
}

ModelDistribution diameter_classes(std::span<const double> diameters, std::size_t max_classes) {
  if (diameters.empty()) throw InputError("no spheres to make size classes of");
  std::vector<double> sorted(diameters.begin(), diameters.end());
  std::sort(sorted.begin(), sorted.end(), std::greater<>());
  ModelDistribution out;
  for (const double d : sorted) {
    const double volume = d * d * d;
    if (!out.classes.empty() && out.classes.back().diameter - d <= 1e-9 * out.classes.back().diameter)
      out.classes.back().volume_fraction += volume;
    else
      out.classes.push_back({d, d, d, volume});
  }
  out.rule = "one class per diameter";
  if (out.classes.size() > max_classes) {
    // Bins of ratio 2^(1/4) down from the largest diameter, each at the geometric mean of its ends.
    const double top = sorted.front();
    std::vector<ModelClass> bins;
    for (const ModelClass& c : out.classes) {
      const auto k = static_cast<int>(std::floor(4.0 * std::log2(top / c.diameter)));
      const double hi = top * std::exp2(-0.25 * k), lo = top * std::exp2(-0.25 * (k + 1));
      if (bins.empty() || bins.back().d_hi != hi) bins.push_back({std::sqrt(lo * hi), lo, hi, 0.0});
      bins.back().volume_fraction += c.volume_fraction;
    }
    out.classes = std::move(bins);
    out.rule = "diameters binned in classes of ratio 2^(1/4), each at the geometric mean of its ends";
  }
  normalise(out.classes);
  return out;
}

double cpm_loosening(double d_fine, double d_coarse, double exponent) {
  return std::sqrt(1.0 - std::pow(1.0 - d_fine / d_coarse, exponent));
}

double cpm_wall(double d_fine, double d_coarse, double exponent) {
  return 1.0 - std::pow(1.0 - d_fine / d_coarse, exponent);
}

namespace {
std::vector<double> betas(const ModelDistribution& dist, std::span<const double> beta) {
  if (dist.classes.empty()) throw InputError("CPM: the size distribution has no classes");
  if (beta.size() != 1 && beta.size() != dist.classes.size())
    throw InputError(fmt::format("CPM: {} residual packing densities for {} classes; expected one for all or one "
                                 "per class",
                                 beta.size(), dist.classes.size()));
  std::vector<double> out(dist.classes.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    out[i] = beta.size() == 1 ? beta[0] : beta[i];
    if (!(out[i] > 0.0 && out[i] < 1.0))
      throw InputError(fmt::format("CPM: residual packing density {} is not between 0 and 1", out[i]));
  }
  return out;
}

std::vector<double> partial_virtual_densities(const ModelDistribution& dist, const std::vector<double>& beta,
                                              const CpmInteraction& interaction = {}) {
  const std::vector<ModelClass>& c = dist.classes;
  std::vector<double> gamma(c.size());
  for (std::size_t i = 0; i < c.size(); ++i) {
    double sum = 0.0;
    for (std::size_t j = 0; j < c.size(); ++j) {
      if (j == i) continue;
      const double y = c[j].volume_fraction;
      if (j < i)  // coarser (or as coarse, listed before): its wall effect on i
        sum += (1.0 - beta[i] +
                cpm_wall(c[i].diameter, c[j].diameter, interaction.wall_exponent) * beta[i] * (1.0 - 1.0 / beta[j])) *
               y;
      else  // finer: loosening effect on i
        sum +=
            (1.0 - cpm_loosening(c[j].diameter, c[i].diameter, interaction.loosening_exponent) * beta[i] / beta[j]) * y;
    }
    gamma[i] = beta[i] / (1.0 - sum);
  }
  return gamma;
}

double compaction_sum(const ModelDistribution& dist, const std::vector<double>& beta, const std::vector<double>& gamma,
                      double phi) {
  double k = 0.0;
  for (std::size_t i = 0; i < dist.classes.size(); ++i)
    k += (dist.classes[i].volume_fraction / beta[i]) / (1.0 / phi - 1.0 / gamma[i]);
  return k;
}
}  // namespace

CpmResult cpm(const ModelDistribution& dist, std::span<const double> beta_in, double compaction_index,
              const CpmInteraction& interaction) {
  if (!(interaction.loosening_exponent > 0.0 && interaction.wall_exponent > 0.0) ||
      !std::isfinite(interaction.loosening_exponent) || !std::isfinite(interaction.wall_exponent))
    throw InputError(fmt::format("CPM: interaction exponents {} and {}; expected positive numbers",
                                 interaction.loosening_exponent, interaction.wall_exponent));
  if (!(compaction_index > 0.0) || !std::isfinite(compaction_index))
    throw InputError(fmt::format("CPM: compaction index K = {} is not a positive number", compaction_index));
  const std::vector<double> beta = betas(dist, beta_in);
  CpmResult r;
  r.gamma = partial_virtual_densities(dist, beta, interaction);
  r.dominant = static_cast<std::size_t>(std::min_element(r.gamma.begin(), r.gamma.end()) - r.gamma.begin());
  r.virtual_density = r.gamma[r.dominant];
  // K(phi) rises from 0 at phi = 0 to infinity at phi = gamma: bisection to the last bit.
  double lo = 0.0, hi = r.virtual_density;
  for (int k = 0; k < 200 && hi - lo > 0.0; ++k) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    (compaction_sum(dist, beta, r.gamma, mid) < compaction_index ? lo : hi) = mid;
  }
  r.density = 0.5 * (lo + hi);
  return r;
}

double cpm_compaction_index(const ModelDistribution& dist, std::span<const double> beta_in, double phi) {
  const std::vector<double> beta = betas(dist, beta_in);
  const std::vector<double> gamma = partial_virtual_densities(dist, beta);
  const double g = *std::min_element(gamma.begin(), gamma.end());
  if (!(phi > 0.0 && phi < g))
    throw InputError(fmt::format("CPM: a density of {:.4f} is not below the virtual packing density {:.4f}: no "
                                 "compaction index gives it (a larger residual packing density would)",
                                 phi, g));
  return compaction_sum(dist, beta, gamma, phi);
}

double cpm_beta_from_monosized(double phi, double compaction_index) { return phi * (1.0 + 1.0 / compaction_index); }

std::optional<double> compaction_index_of(std::string_view process) {
  if (process == "poured") return 4.1;
  if (process == "rodded") return 4.5;
  if (process == "vibrated") return 4.75;
  if (process == "vibrated_compressed") return 9.0;
  return std::nullopt;
}

double furnas_binary(double phi_coarse, double phi_fine, double fine_fraction) {
  const double y_c = 1.0 - fine_fraction, y_f = fine_fraction;
  return 1.0 / std::max(y_c / phi_coarse, y_c + y_f / phi_fine);
}

double furnas_densest(double phi_coarse, double phi_fine) { return phi_coarse + phi_fine - phi_coarse * phi_fine; }

double furnas_densest_fine_fraction(double phi_coarse, double phi_fine) {
  return (1.0 - phi_coarse) * phi_fine / furnas_densest(phi_coarse, phi_fine);
}

namespace {
// Raw moments E[r^k], k = 0..3, of the number distribution, unnormalised.
struct Moments {
  double m[4] = {0.0, 0.0, 0.0, 0.0};
  [[nodiscard]] RadiusMoments shape() const {
    const double mean = m[1] / m[0], mean2 = m[2] / m[0], mean3 = m[3] / m[0];
    const double variance = std::max(0.0, mean2 - mean * mean);
    const double sigma = std::sqrt(variance);
    RadiusMoments out;
    out.polydispersity = sigma / mean;
    const double third = mean3 - 3.0 * mean * mean2 + 2.0 * mean * mean * mean;
    out.skewness = sigma > 1e-12 * mean ? third / (sigma * sigma * sigma) : 0.0;
    return out;
  }
};
}  // namespace

RadiusMoments radius_moments(const ModelDistribution& dist) {
  Moments total;
  for (const ModelClass& c : dist.classes) {
    if (c.d_hi <= c.d_lo * (1.0 + 1e-12)) {  // one size: y / (pi/6 d^3) spheres of radius d/2
      const double n = c.volume_fraction / (std::numbers::pi / 6.0 * std::pow(c.diameter, 3));
      for (int k = 0; k < 4; ++k) total.m[k] += n * std::pow(0.5 * c.diameter, k);
      continue;
    }
    // Volume uniform in log d over [a, b]: number density C d^-4 with C (pi/6) ln(b/a) = y.
    const double a = c.d_lo, b = c.d_hi;
    const double C = c.volume_fraction / (std::numbers::pi / 6.0 * std::log(b / a));
    for (int k = 0; k < 4; ++k) {
      const double integral = k == 3 ? std::log(b / a) : (std::pow(b, k - 3) - std::pow(a, k - 3)) / (k - 3);
      total.m[k] += C * integral * std::pow(0.5, k);
    }
  }
  return total.shape();
}

RadiusMoments radius_moments(std::span<const double> diameters) {
  if (diameters.empty()) throw InputError("no spheres to take the moments of");
  Moments total;
  for (const double d : diameters)
    for (int k = 0; k < 4; ++k) total.m[k] += std::pow(0.5 * d, k);
  return total.shape();
}

double desmond_weeks_rcp(const RadiusMoments& m) {
  return 0.634 + 0.0658 * m.polydispersity + 0.0857 * m.skewness * m.polydispersity * m.polydispersity;
}

}  // namespace aggpack
