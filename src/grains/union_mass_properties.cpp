#include "aggpack/grains/union_mass_properties.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>
#include <vector>

namespace aggpack {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// What is integrated over z: a slice's area and moments, and those times z and z², which
// give the body's volume, first and second moments. Origin: the spheres' mean centre.
enum Moment { kArea, kX, kY, kZ, kXX, kYY, kZZ, kXY, kXZ, kYZ, kMoments };
using Moments = std::array<double, kMoments>;
// The power of length each moment carries beyond the volume's 3 (to scale it back).
constexpr std::array<int, kMoments> kLengthPower{0, 1, 1, 1, 2, 2, 2, 2, 2, 2};

Moments& operator+=(Moments& a, const Moments& b) {
  for (int k = 0; k < kMoments; ++k) a[k] += b[k];
  return a;
}
Moments operator*(Moments a, double s) {
  for (double& v : a) v *= s;
  return a;
}

struct Disc {
  double x, y, radius;
};

// 8-point Gauss-Legendre on [-1, 1]: a slice boundary's integrands are trigonometric
// polynomials of degree 4 at most, integrated to about 1e-15 on arcs of pi/8 or less.
constexpr std::array<double, 4> kLegendreNode{0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
                                              0.9602898564975363};
constexpr std::array<double, 4> kLegendreWeight{0.3626837833783620, 0.3137066458778873, 0.2223810344533745,
                                                0.1012285362903763};

// The area and in-plane moments enclosed by the arc [t0, t1] of disc d traversed
// anticlockwise, by Green's theorem: A = ∮ (x dy - y dx) / 2, ∫x = ∮ x²/2 dy, ∫y = -∮ y²/2 dx,
// ∫x² = ∮ x³/3 dy, ∫y² = -∮ y³/3 dx, ∫xy = ∮ x² y / 2 dy. Only kArea, kX, kY, kXX, kYY, kXY.
Moments arc_moments(const Disc& d, double t0, double t1) {
  Moments m{};
  const int pieces = std::max(1, static_cast<int>(std::ceil((t1 - t0) / (std::numbers::pi / 8.0))));
  const double half = 0.5 * (t1 - t0) / pieces;
  for (int p = 0; p < pieces; ++p) {
    const double mid = t0 + (2 * p + 1) * half;
    for (int k = 0; k < 8; ++k) {
      const double t = mid + (k < 4 ? -1.0 : 1.0) * kLegendreNode[k % 4] * half;
      const double w = kLegendreWeight[k % 4] * half;
      const double c = std::cos(t), s = std::sin(t);
      const double x = d.x + d.radius * c, y = d.y + d.radius * s;
      const double dx = -d.radius * s, dy = d.radius * c;  // per unit of t
      m[kArea] += w * 0.5 * (x * dy - y * dx);
      m[kX] += w * 0.5 * x * x * dy;
      m[kY] -= w * 0.5 * y * y * dx;
      m[kXX] += w * x * x * x / 3.0 * dy;
      m[kYY] -= w * y * y * y / 3.0 * dx;
      m[kXY] += w * 0.5 * x * x * y * dy;
    }
  }
  return m;
}

// The angles of disc i's circle that lie inside some other disc, as sorted, merged
// intervals within [0, 2 pi]; `hidden` when the whole disc lies inside another one (of two
// identical discs the first is kept).
std::vector<std::pair<double, double>> covered_arcs(const std::vector<Disc>& discs, std::size_t i, bool& hidden) {
  std::vector<std::pair<double, double>> covered;
  hidden = false;
  const Disc& a = discs[i];
  for (std::size_t j = 0; j < discs.size(); ++j) {
    if (j == i) continue;
    const Disc& b = discs[j];
    const double d = std::hypot(b.x - a.x, b.y - a.y);
    if (d >= a.radius + b.radius) continue;                             // apart
    if (d + b.radius <= a.radius && d + a.radius > b.radius) continue;  // b inside a
    if (d + a.radius <= b.radius) {                                     // a inside b (or the same disc)
      if (d + b.radius > a.radius || j < i) {
        hidden = true;
        return {};
      }
      continue;
    }
    const double toward = std::atan2(b.y - a.y, b.x - a.x);
    const double half =
        std::acos(std::clamp((d * d + a.radius * a.radius - b.radius * b.radius) / (2.0 * d * a.radius), -1.0, 1.0));
    double lo = std::fmod(toward - half + 2.0 * kTwoPi, kTwoPi), hi = lo + 2.0 * half;
    if (hi > kTwoPi) {
      covered.emplace_back(lo, kTwoPi);
      covered.emplace_back(0.0, hi - kTwoPi);
    } else {
      covered.emplace_back(lo, hi);
    }
  }
  std::sort(covered.begin(), covered.end());
  std::vector<std::pair<double, double>> merged;
  for (const auto& c : covered) {
    if (!merged.empty() && c.first <= merged.back().second)
      merged.back().second = std::max(merged.back().second, c.second);
    else
      merged.push_back(c);
  }
  return merged;
}

// A slice's moments (kZ, kZZ, kXZ, kYZ from z), at height z of the spheres (in units of their reach).
Moments slice_moments(std::span<const MemberSphere> spheres, double z) {
  std::vector<Disc> discs;
  for (const MemberSphere& s : spheres) {
    const double h = z - s.centre.z, r2 = s.radius * s.radius - h * h;
    if (r2 > 0.0) discs.push_back({s.centre.x, s.centre.y, std::sqrt(r2)});
  }
  Moments m{};
  for (std::size_t i = 0; i < discs.size(); ++i) {
    bool hidden = false;
    const auto covered = covered_arcs(discs, i, hidden);
    if (hidden) continue;
    double from = 0.0;
    for (const auto& [lo, hi] : covered) {
      if (lo > from) m += arc_moments(discs[i], from, lo);
      from = std::max(from, hi);
    }
    if (from < kTwoPi) m += arc_moments(discs[i], from, kTwoPi);
  }
  m[kZ] = m[kArea] * z;
  m[kZZ] = m[kArea] * z * z;
  m[kXZ] = m[kX] * z;
  m[kYZ] = m[kY] * z;
  return m;
}

// Gauss-Kronrod 7/15 (QUADPACK's qk15): the Kronrod abscissae on [0, 1] (every second one,
// from the second, is also a Gauss node) and their weights, and the 7-point Gauss weights.
constexpr std::array<double, 8> kKronrodNode{0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
                                             0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
                                             0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
                                             0.207784955007898467600689403773245, 0.0};
constexpr std::array<double, 8> kKronrodWeight{
    0.022935322010529224963732008058970, 0.063092092629978553290700663189204, 0.104790010322250183839876322541518,
    0.140653259715525918745189590510238, 0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
    0.204432940075298892414161999234649, 0.209482141084727828012999174891714};
constexpr std::array<double, 4> kGaussWeight{0.129484966168869693270611432679082, 0.279705391489276667901467771423780,
                                             0.381830050505118944950369775488975, 0.417959183673469387755102040816327};

struct Quadrature {
  std::span<const MemberSphere> spheres;  // scaled to reach 1 from their mean centre
  double scale;                           // the spheres' summed volume: every moment is measured against it
  double tolerance;                       // relative, per unit of the total height
  double height;
  mutable std::size_t slices = 0;  // evaluated so far, against kMaxSlices

  // Ample for 1e-12 on clumps of a hundred spheres; beyond it the error is rounding, not the rule's.
  static constexpr std::size_t kMaxSlices = 4'000'000;

  // The moments integrated over [a, b], split until the Kronrod-Gauss difference of every
  // moment is below its share of the tolerance, or at the rounding of the sums themselves.
  Moments integrate(double a, double b, int depth) const {
    const double centre = 0.5 * (a + b), half = 0.5 * (b - a);
    Moments kronrod{}, gauss{}, magnitude{};
    for (int k = 0; k < 8; ++k) {
      const int sides = k == 7 ? 1 : 2;
      for (int side = 0; side < sides; ++side) {
        const Moments f = slice_moments(spheres, centre + (side == 0 ? 1.0 : -1.0) * kKronrodNode[k] * half);
        kronrod += f * kKronrodWeight[k];
        if (k % 2 == 1) gauss += f * kGaussWeight[k / 2];
        for (int m = 0; m < kMoments; ++m) magnitude[m] += std::abs(f[m]) * kKronrodWeight[k];
      }
    }
    slices += 15;
    if (slices > kMaxSlices)
      throw std::runtime_error("union_mass_properties: the quadrature did not converge (more than 4e6 slices)");
    bool converged = true;
    for (int m = 0; m < kMoments; ++m) {
      const double error = std::abs(kronrod[m] - gauss[m]) * half;
      converged =
          converged && (error <= tolerance * scale * (b - a) / height || error <= 50.0 * 2.2e-16 * magnitude[m] * half);
    }
    if (converged || depth >= 40) return kronrod * half;
    Moments left = integrate(a, centre, depth + 1);
    return left += integrate(centre, b, depth + 1);
  }
};

// Heights where a slice's topology can change: each sphere's poles and the highest and
// lowest points of each pair's intersection circle (where three surfaces meet it changes
// too; the adaptive splitting finds those).
std::vector<double> panel_breaks(std::span<const MemberSphere> spheres) {
  std::vector<double> breaks;
  for (std::size_t i = 0; i < spheres.size(); ++i) {
    const MemberSphere& a = spheres[i];
    breaks.push_back(a.centre.z - a.radius);
    breaks.push_back(a.centre.z + a.radius);
    for (std::size_t j = i + 1; j < spheres.size(); ++j) {
      const MemberSphere& b = spheres[j];
      const Vec3 axis = b.centre - a.centre;
      const double d = norm(axis);
      if (!(d < a.radius + b.radius) || !(d > std::abs(a.radius - b.radius))) continue;
      const double along = (d * d + a.radius * a.radius - b.radius * b.radius) / (2.0 * d);
      const double ring = std::sqrt(std::max(0.0, a.radius * a.radius - along * along));
      const double nz = axis.z / d, centre_z = a.centre.z + along * nz;
      const double reach = ring * std::sqrt(std::max(0.0, 1.0 - nz * nz));
      breaks.push_back(centre_z - reach);
      breaks.push_back(centre_z + reach);
    }
  }
  std::sort(breaks.begin(), breaks.end());
  breaks.erase(std::unique(breaks.begin(), breaks.end()), breaks.end());
  return breaks;
}

}  // namespace

MassProperties union_mass_properties(std::span<const MemberSphere> spheres, double relative_tolerance) {
  if (spheres.empty()) throw std::invalid_argument("union_mass_properties: no spheres");
  if (!(relative_tolerance >= 1e-13 && relative_tolerance <= 1e-2))
    throw std::invalid_argument("union_mass_properties: the relative tolerance must lie in [1e-13, 1e-2]");
  Vec3 origin{};
  for (const MemberSphere& s : spheres) {
    if (!(s.radius > 0.0) || !std::isfinite(s.radius))
      throw std::invalid_argument("union_mass_properties: a member sphere's radius must be positive and finite");
    if (!std::isfinite(s.centre.x) || !std::isfinite(s.centre.y) || !std::isfinite(s.centre.z))
      throw std::invalid_argument("union_mass_properties: a member sphere's centre must be finite");
    origin += s.centre * (1.0 / static_cast<double>(spheres.size()));
  }
  // Lengths in units of the reach from the mean centre: the moments of every order are then
  // of the size of the volume, whatever the clump's size.
  double reach = 0.0;
  for (const MemberSphere& s : spheres) reach = std::max(reach, norm(s.centre - origin) + s.radius);
  std::vector<MemberSphere> unit(spheres.begin(), spheres.end());
  double volume_sum = 0.0;
  for (MemberSphere& s : unit) {
    s.centre = (s.centre - origin) * (1.0 / reach), s.radius /= reach;
    volume_sum += 4.0 / 3.0 * std::numbers::pi * s.radius * s.radius * s.radius;
  }
  const std::vector<double> breaks = panel_breaks(unit);
  const Quadrature q{unit, volume_sum, relative_tolerance, breaks.back() - breaks.front()};
  Moments total{};
  for (std::size_t k = 0; k + 1 < breaks.size(); ++k) total += q.integrate(breaks[k], breaks[k + 1], 0);
  for (int m = 0; m < kMoments; ++m) total[m] *= std::pow(reach, 3 + kLengthPower[m]);  // back to lengths

  MassProperties p;
  p.volume = total[kArea];
  const Vec3 c{total[kX] / p.volume, total[kY] / p.volume, total[kZ] / p.volume};  // from the mean centre
  p.centre_of_mass = origin + c;
  // Second moments about the centre of mass (parallel axes), then the tensor.
  const double xx = total[kXX] - p.volume * c.x * c.x, yy = total[kYY] - p.volume * c.y * c.y,
               zz = total[kZZ] - p.volume * c.z * c.z;
  const double xy = total[kXY] - p.volume * c.x * c.y, xz = total[kXZ] - p.volume * c.x * c.z,
               yz = total[kYZ] - p.volume * c.y * c.z;
  p.inertia = {yy + zz, xx + zz, xx + yy, -xy, -xz, -yz};
  return p;
}

}  // namespace aggpack
