#include "aggpack/grains/union_mass_properties.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "aggpack/core/gauss_kronrod.hpp"

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

using Intervals = std::vector<std::pair<double, double>>;

// The union of intervals, sorted and merged.
Intervals merged_intervals(Intervals intervals) {
  std::sort(intervals.begin(), intervals.end());
  Intervals merged;
  for (const auto& c : intervals) {
    if (!merged.empty() && c.first <= merged.back().second)
      merged.back().second = std::max(merged.back().second, c.second);
    else
      merged.push_back(c);
  }
  return merged;
}

// The angles of disc i's circle that lie inside some other disc, as sorted, merged
// intervals within [0, 2 pi]; `hidden` when the whole disc lies inside another one (of two
// identical discs the first is kept).
Intervals covered_arcs(const std::vector<Disc>& discs, std::size_t i, bool& hidden) {
  Intervals covered;
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
  return merged_intervals(std::move(covered));
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

// `Slice` gives a slice's moments at a height: slice_moments's, or a clipped slice's area.
template <class Slice>
struct Quadrature {
  Slice slice;
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
        const Moments f = slice(spheres, centre + (side == 0 ? 1.0 : -1.0) * gauss_kronrod15::kNode[k] * half);
        kronrod += f * gauss_kronrod15::kKronrodWeight[k];
        if (k % 2 == 1) gauss += f * gauss_kronrod15::kGaussWeight[k / 2];
        for (int m = 0; m < kMoments; ++m) magnitude[m] += std::abs(f[m]) * gauss_kronrod15::kKronrodWeight[k];
      }
    }
    slices += 15;
    if (slices > kMaxSlices)
      throw std::runtime_error("a union of spheres' quadrature did not converge (more than 4e6 slices)");
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

// The part of a union of discs inside a rectangle: the area within [x0, x1] x [y0, y1].
struct Rectangle {
  double x0, x1, y0, y1;
};

// Adds the arc [lo, hi] (hi - lo <= 2 pi, lo from -2 pi on) to `arcs`, in [0, 2 pi).
void add_arc(Intervals& arcs, double lo, double hi) {
  const double from = std::fmod(lo + 2.0 * kTwoPi, kTwoPi), to = from + (hi - lo);
  if (to > kTwoPi) {
    arcs.emplace_back(from, kTwoPi);
    arcs.emplace_back(0.0, to - kTwoPi);
  } else {
    arcs.emplace_back(from, to);
  }
}

// Adds the angles of disc d's circle outside the rectangle to `arcs`; false when it is all
// outside. (Each side's: where its coordinate passes the side's line, by acos or asin.)
bool add_outside_rectangle(const Disc& d, const Rectangle& r, Intervals& arcs) {
  const double r_inv = 1.0 / d.radius;
  const double left = (r.x0 - d.x) * r_inv, right = (r.x1 - d.x) * r_inv;
  const double below = (r.y0 - d.y) * r_inv, above = (r.y1 - d.y) * r_inv;
  if (left >= 1.0 || right <= -1.0 || below >= 1.0 || above <= -1.0) return false;
  if (left > -1.0) add_arc(arcs, std::acos(left), kTwoPi - std::acos(left));               // cos t < left
  if (right < 1.0) add_arc(arcs, -std::acos(right), std::acos(right));                     // cos t > right
  if (below > -1.0) add_arc(arcs, std::numbers::pi - std::asin(below), kTwoPi + std::asin(below));  // sin t < below
  if (above < 1.0) add_arc(arcs, std::asin(above), std::numbers::pi - std::asin(above));  // sin t > above
  return true;
}

// ½ ∮ (x dy - y dx) over the arc [t0, t1] of d, anticlockwise: its share of the area.
double arc_area(const Disc& d, double t0, double t1) {
  return 0.5 * (d.radius * d.radius * (t1 - t0) + d.radius * d.x * (std::sin(t1) - std::sin(t0)) -
                d.radius * d.y * (std::cos(t1) - std::cos(t0)));
}

// How much of the segment `across` ∈ [lo, hi] at `at` on the other axis the discs cover
// (`vertical`: the segment x = at, y ∈ [lo, hi]; else y = at, x ∈ [lo, hi]).
double covered_length(const std::vector<Disc>& discs, bool vertical, double at, double lo, double hi) {
  Intervals chords;
  for (const Disc& d : discs) {
    const double offset = vertical ? at - d.x : at - d.y, centre = vertical ? d.y : d.x;
    if (std::abs(offset) >= d.radius) continue;
    const double half = std::sqrt(d.radius * d.radius - offset * offset);
    const double a = std::max(lo, centre - half), b = std::min(hi, centre + half);
    if (b > a) chords.emplace_back(a, b);
  }
  double length = 0.0;
  for (const auto& [a, b] : merged_intervals(std::move(chords))) length += b - a;
  return length;
}

// The area of a slice of the union inside the rectangle, by Green's theorem over the clipped
// region's boundary: the discs' arcs outside the other discs and inside the rectangle, and
// the parts of the rectangle's sides inside the union (anticlockwise: the left side down, the
// bottom rightwards, the right side up, the top leftwards).
double clipped_slice_area(std::span<const MemberSphere> spheres, const Rectangle& rect, double z) {
  std::vector<Disc> discs;
  for (const MemberSphere& s : spheres) {
    const double h = z - s.centre.z, r2 = s.radius * s.radius - h * h;
    if (r2 > 0.0) discs.push_back({s.centre.x, s.centre.y, std::sqrt(r2)});
  }
  double area = 0.0;
  for (std::size_t i = 0; i < discs.size(); ++i) {
    bool hidden = false;
    Intervals covered = covered_arcs(discs, i, hidden);
    if (hidden || !add_outside_rectangle(discs[i], rect, covered)) continue;
    double from = 0.0;
    for (const auto& [lo, hi] : merged_intervals(std::move(covered))) {
      if (lo > from) area += arc_area(discs[i], from, lo);
      from = std::max(from, hi);
    }
    if (from < kTwoPi) area += arc_area(discs[i], from, kTwoPi);
  }
  area += 0.5 * (rect.x1 * covered_length(discs, true, rect.x1, rect.y0, rect.y1) -
                 rect.x0 * covered_length(discs, true, rect.x0, rect.y0, rect.y1) -
                 rect.y0 * covered_length(discs, false, rect.y0, rect.x0, rect.x1) +
                 rect.y1 * covered_length(discs, false, rect.y1, rect.x0, rect.x1));
  return area;
}

// Heights where a clipped slice's topology can change besides the union's own: where a
// sphere's circle touches a side's line or passes a corner, and where a pair's
// intersection circle crosses a side's plane.
void add_clipping_breaks(std::span<const MemberSphere> spheres, const Rectangle& rect, std::vector<double>& breaks) {
  const auto add_pair = [&](double centre, double reach2) {
    if (reach2 <= 0.0) return;
    breaks.push_back(centre - std::sqrt(reach2));
    breaks.push_back(centre + std::sqrt(reach2));
  };
  for (std::size_t i = 0; i < spheres.size(); ++i) {
    const MemberSphere& a = spheres[i];
    const double r2 = a.radius * a.radius;
    for (const double x : {rect.x0, rect.x1}) {
      add_pair(a.centre.z, r2 - (x - a.centre.x) * (x - a.centre.x));
      for (const double y : {rect.y0, rect.y1})
        add_pair(a.centre.z, r2 - (x - a.centre.x) * (x - a.centre.x) - (y - a.centre.y) * (y - a.centre.y));
    }
    for (const double y : {rect.y0, rect.y1}) add_pair(a.centre.z, r2 - (y - a.centre.y) * (y - a.centre.y));
    for (std::size_t j = i + 1; j < spheres.size(); ++j) {
      const MemberSphere& b = spheres[j];
      const Vec3 axis = b.centre - a.centre;
      const double d = norm(axis);
      if (!(d < a.radius + b.radius) || !(d > std::abs(a.radius - b.radius))) continue;
      // The ring: centre c, radius rho, in the plane of normal n, spanned by u and v.
      const Vec3 n = axis * (1.0 / d);
      const double along = (d * d + r2 - b.radius * b.radius) / (2.0 * d);
      const double rho = std::sqrt(std::max(0.0, r2 - along * along));
      const Vec3 c = a.centre + along * n;
      const Vec3 u = normalized(std::abs(n.x) < 0.9 ? cross(n, Vec3{1, 0, 0}) : cross(n, Vec3{0, 1, 0}));
      const Vec3 v = cross(n, u);
      // Where c + rho (u cos t + v sin t) meets x = side (axis 0) or y = side (axis 1).
      for (int axis_index = 0; axis_index < 2; ++axis_index)
        for (const double side : axis_index == 0 ? std::array{rect.x0, rect.x1} : std::array{rect.y0, rect.y1}) {
          const double p = rho * u[axis_index], q = rho * v[axis_index], amplitude = std::hypot(p, q);
          const double want = side - c[axis_index];
          if (!(amplitude > std::abs(want))) continue;
          const double phase = std::atan2(q, p), spread = std::acos(want / amplitude);
          for (const double t : {phase - spread, phase + spread})
            breaks.push_back(c.z + rho * (u.z * std::cos(t) + v.z * std::sin(t)));
        }
    }
  }
}

// A clump in units of its reach from its spheres' mean centre: the moments of every order are
// then of the size of the volume, whatever the clump's size. Throws std::invalid_argument,
// prefixed by `who`, for a radius not positive and finite or a centre not finite.
struct UnitClump {
  std::vector<MemberSphere> spheres;
  Vec3 origin;
  double reach = 0.0, volume_sum = 0.0;  // volume_sum: the unit spheres' summed volume
};
UnitClump unit_clump(std::span<const MemberSphere> spheres, const char* who) {
  UnitClump c;
  for (const MemberSphere& s : spheres) {
    if (!(s.radius > 0.0) || !std::isfinite(s.radius))
      throw std::invalid_argument(std::string(who) + ": a member sphere's radius must be positive and finite");
    if (!std::isfinite(s.centre.x) || !std::isfinite(s.centre.y) || !std::isfinite(s.centre.z))
      throw std::invalid_argument(std::string(who) + ": a member sphere's centre must be finite");
    c.origin += s.centre * (1.0 / static_cast<double>(spheres.size()));
  }
  for (const MemberSphere& s : spheres) c.reach = std::max(c.reach, norm(s.centre - c.origin) + s.radius);
  c.spheres.assign(spheres.begin(), spheres.end());
  for (MemberSphere& s : c.spheres) {
    s.centre = (s.centre - c.origin) * (1.0 / c.reach), s.radius /= c.reach;
    c.volume_sum += 4.0 / 3.0 * std::numbers::pi * s.radius * s.radius * s.radius;
  }
  return c;
}

}  // namespace

double union_volume_in_box(std::span<const MemberSphere> spheres, const Box& box, double relative_tolerance) {
  if (spheres.empty()) throw std::invalid_argument("union_volume_in_box: no spheres");
  if (!(relative_tolerance >= 1e-13 && relative_tolerance <= 1e-2))
    throw std::invalid_argument("union_volume_in_box: the relative tolerance must lie in [1e-13, 1e-2]");
  const Vec3 size = box.size();
  if (!(size.x >= 0.0 && size.y >= 0.0 && size.z >= 0.0) || !std::isfinite(size.x + size.y + size.z))
    throw std::invalid_argument("union_volume_in_box: a box's sides must be finite and not negative");
  const UnitClump clump = unit_clump(spheres, "union_volume_in_box");
  const std::vector<MemberSphere>& unit = clump.spheres;
  const Vec3 origin = clump.origin;
  const double reach = clump.reach, volume_sum = clump.volume_sum;
  const Vec3 lo = (box.lo - origin) * (1.0 / reach), hi = (box.hi - origin) * (1.0 / reach);
  const Rectangle rect{lo.x, hi.x, lo.y, hi.y};
  std::vector<double> breaks = panel_breaks(unit);
  // Only the heights within both the union's and the box's.
  const double bottom = std::max(lo.z, breaks.front()), top = std::min(hi.z, breaks.back());
  if (!(top > bottom) || rect.x1 <= rect.x0 || rect.y1 <= rect.y0) return 0.0;
  add_clipping_breaks(unit, rect, breaks);
  breaks.push_back(bottom);
  breaks.push_back(top);
  std::erase_if(breaks, [&](double z) { return z < bottom || z > top; });
  std::sort(breaks.begin(), breaks.end());
  breaks.erase(std::unique(breaks.begin(), breaks.end()), breaks.end());
  const auto slice = [&](std::span<const MemberSphere> members, double z) {
    Moments m{};
    m[kArea] = clipped_slice_area(members, rect, z);
    return m;
  };
  const Quadrature q{slice, unit, volume_sum, relative_tolerance, top - bottom};
  double volume = 0.0;
  for (std::size_t k = 0; k + 1 < breaks.size(); ++k) volume += q.integrate(breaks[k], breaks[k + 1], 0)[kArea];
  return volume * reach * reach * reach;
}

MassProperties union_mass_properties(std::span<const MemberSphere> spheres, double relative_tolerance) {
  if (spheres.empty()) throw std::invalid_argument("union_mass_properties: no spheres");
  if (!(relative_tolerance >= 1e-13 && relative_tolerance <= 1e-2))
    throw std::invalid_argument("union_mass_properties: the relative tolerance must lie in [1e-13, 1e-2]");
  const UnitClump clump = unit_clump(spheres, "union_mass_properties");
  const std::vector<MemberSphere>& unit = clump.spheres;
  const Vec3 origin = clump.origin;
  const double reach = clump.reach, volume_sum = clump.volume_sum;
  const std::vector<double> breaks = panel_breaks(unit);
  const Quadrature q{slice_moments, unit, volume_sum, relative_tolerance, breaks.back() - breaks.front()};
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
