#include "aggpack/analysis/sphere_cylinder_volume.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <utility>
#include <vector>

#include "aggpack/core/gauss_kronrod.hpp"

namespace aggpack {

namespace {
constexpr double kPi = std::numbers::pi;

// A circular segment's area over its radius squared, for the half-angle t at the centre:
// t - sin t cos t, by its series where the difference would cancel (t small).
double segment_over_r2(double t) {
  if (t < 1e-2) {
    const double t2 = t * t;
    return t * t2 * (2.0 / 3.0 - t2 * (2.0 / 15.0 - t2 * 4.0 / 315.0));
  }
  return t - std::sin(t) * std::cos(t);
}

// The area where two discs meet: radii a and b, centres d apart; the two circular segments
// that make the lens, each half-angle by atan2 of the triangle's sides. (The textbook
// a^2 alpha + b^2 beta - sqrt(kite) / 2 cancels when one disc is far smaller than the other,
// a grain of sand at a core's rim: roundoff then kept the quadrature below from ever meeting
// its tolerance, hundreds of seconds a specimen.)
double lens_area(double a, double b, double d) {
  if (a <= 0.0 || b <= 0.0 || d >= a + b) return 0.0;
  if (d <= std::abs(a - b)) return kPi * std::min(a, b) * std::min(a, b);
  const double root = std::sqrt(std::max((-d + a + b) * (d + a - b) * (d - a + b) * (d + a + b), 0.0));
  const double alpha = std::atan2(root, (d - b) * (d + b) + a * a);  // (d^2 + a^2 - b^2), less cancelling
  const double beta = std::atan2(root, (d - a) * (d + a) + b * b);
  return a * a * segment_over_r2(alpha) + b * b * segment_over_r2(beta);
}

// Gauss-Kronrod 7/15 on [lo, hi]: the Kronrod estimate and its difference from Gauss's.
std::pair<double, double> gauss_kronrod(const std::function<double(double)>& f, double lo, double hi) {
  using gauss_kronrod15::kGaussWeight, gauss_kronrod15::kKronrodWeight, gauss_kronrod15::kNode;
  const double mid = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
  double kronrod = kKronrodWeight[7] * f(mid), gauss = kGaussWeight[3] * f(mid);
  for (std::size_t k = 0; k < 7; ++k) {
    const double pair = f(mid - half * kNode[k]) + f(mid + half * kNode[k]);
    kronrod += kKronrodWeight[k] * pair;
    if (k % 2 == 1) gauss += kGaussWeight[k / 2] * pair;
  }
  return {kronrod * half, std::abs(kronrod - gauss) * half};
}

double adaptive_integral(const std::function<double(double)>& f, double lo, double hi, double tolerance, int depth = 0) {
  const auto [value, error] = gauss_kronrod(f, lo, hi);
  if (error <= tolerance || depth >= 40) return value;
  const double mid = 0.5 * (lo + hi);
  return adaptive_integral(f, lo, mid, 0.5 * tolerance, depth + 1) +
         adaptive_integral(f, mid, hi, 0.5 * tolerance, depth + 1);
}

double ball_volume(double r) { return 4.0 / 3.0 * kPi * r * r * r; }
}  // namespace

double VerticalCylinder::volume() const { return kPi * radius * radius * (z_hi - z_lo); }

bool VerticalCylinder::contains(const Vec3& p) const {
  const double dx = p.x - x, dy = p.y - y;
  return p.z >= z_lo && p.z < z_hi && dx * dx + dy * dy < radius * radius;
}

double sphere_cylinder_volume(const Vec3& centre, double radius, const VerticalCylinder& cylinder,
                              double relative_tolerance) {
  const double lo = std::max(centre.z - radius, cylinder.z_lo), hi = std::min(centre.z + radius, cylinder.z_hi);
  if (!(hi > lo)) return 0.0;
  const double d = std::hypot(centre.x - cylinder.x, centre.y - cylinder.y);
  if (d >= cylinder.radius + radius) return 0.0;
  if (d + radius <= cylinder.radius) {
    // Every slice inside the cylinder's circle: the ball between the two planes, in closed
    // form (the slices' area pi (r^2 - t^2) integrated over t = z - centre.z).
    const auto primitive = [&](double z) {
      const double t = z - centre.z;
      return kPi * (radius * radius * t - t * t * t / 3.0);
    };
    return primitive(hi) - primitive(lo);
  }
  const auto slice_radius = [&](double z) {
    const double dz = z - centre.z;
    return std::sqrt(std::max(radius * radius - dz * dz, 0.0));
  };
  // The heights where the lens changes form: the slice's disc just touching the cylinder's
  // circle from outside (a = d + R) or from inside (a = |d - R|).
  std::vector<double> cuts{lo, hi};
  for (const double a : {d + cylinder.radius, std::abs(d - cylinder.radius)})
    if (a < radius)
      for (const double sign : {-1.0, 1.0}) {
        const double z = centre.z + sign * std::sqrt(radius * radius - a * a);
        if (z > lo && z < hi) cuts.push_back(z);
      }
  std::sort(cuts.begin(), cuts.end());
  const auto area = [&](double z) { return lens_area(slice_radius(z), cylinder.radius, d); };
  const double tolerance = relative_tolerance * ball_volume(radius) / static_cast<double>(cuts.size());
  double volume = 0.0;
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k) volume += adaptive_integral(area, cuts[k], cuts[k + 1], tolerance);
  return volume;
}

}  // namespace aggpack
