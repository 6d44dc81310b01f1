#include "aggpack/deposition/contact_geometry.hpp"

#include <algorithm>
#include <numbers>

namespace aggpack {

namespace {
constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr Vec3 kUp{0.0, 0.0, 1.0};

// Into [0, 2 pi); the arguments here are within a few turns of it.
double wrap_angle(double t) {
  while (t < 0.0) t += kTwoPi;
  while (t >= kTwoPi) t -= kTwoPi;
  return t;
}
}  // namespace

std::string support_name(SupportId id) {
  switch (id) {
    case kNoSupport: return "";
    case kFloor: return "floor";
    case kWallXLow: return "wall_x_low";
    case kWallXHigh: return "wall_x_high";
    case kWallYLow: return "wall_y_low";
    case kWallYHigh: return "wall_y_high";
    default: return std::to_string(id);
  }
}

Descent steepest_descent(std::span<const Vec3> normals) {
  // Subsets are tried smallest first and replaced only on a clearly smaller residual, so
  // that a zero coefficient never drags a support into the active set.
  constexpr double kNegativeAlpha = -1e-12, kPushes = 1e-10;
  const int n = static_cast<int>(std::min<std::size_t>(normals.size(), 8));
  Descent best;
  double best_residual = 0.0;
  bool found = false;
  const auto consider = [&](std::array<int, 3> idx, std::array<double, 3> alpha, int count) {
    for (int i = 0; i < count; ++i)
      if (!(alpha[i] >= kNegativeAlpha)) return;
    Vec3 residual = kUp;
    for (int i = 0; i < count; ++i) residual -= alpha[i] * normals[idx[i]];
    for (int j = 0; j < n; ++j)  // moving along -residual must push into no contact
      if (dot(residual, normals[j]) > kPushes) return;
    const double r2 = norm2(residual);
    if (found && r2 >= best_residual - 1e-24) return;
    found = true;
    best_residual = r2;
    best.active = idx;
    best.active_count = count;
    for (int i = 0; i < 3; ++i) best.alpha[i] = i < count ? std::max(0.0, alpha[i]) : 0.0;
    best.direction = -residual;
  };
  consider({-1, -1, -1}, {}, 0);
  for (int a = 0; a < n; ++a) consider({a, -1, -1}, {normals[a].z, 0, 0}, 1);
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b) {
      const double c = dot(normals[a], normals[b]);
      const double det = 1.0 - c * c;
      if (det < 1e-12) continue;
      const double za = normals[a].z, zb = normals[b].z;
      consider({a, b, -1}, {(za - c * zb) / det, (zb - c * za) / det, 0}, 2);
    }
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b)
      for (int c = b + 1; c < n; ++c) {
        const Vec3 bc = cross(normals[b], normals[c]), ca = cross(normals[c], normals[a]),
                   ab = cross(normals[a], normals[b]);
        const double det = dot(normals[a], bc);
        if (std::abs(det) < 1e-9) continue;
        consider({a, b, c}, {bc.z / det, ca.z / det, ab.z / det}, 3);
      }
  if (!found) best.direction = -kUp;  // cannot happen for unit normals; fall as a fallback
  // Residuals at rounding level are a rest, not a creeping motion.
  if (norm(best.direction) < 1e-13) best.direction = {};
  return best;
}

ArcAngle ArcAngle::of(double c, double s) {
  const double inv = 1.0 / std::sqrt(c * c + s * s);
  ArcAngle t;
  t.c = c * inv;
  t.s = s * inv;
  // The "diamond angle": s / (|c| + |s|) per half-plane, continued to [0, 4).
  const double p = t.s / (std::abs(t.c) + std::abs(t.s));
  t.key = t.c >= 0.0 ? (t.s >= 0.0 ? p : 4.0 + p) : 2.0 - p;
  if (t.key >= 4.0) t.key = 0.0;
  return t;
}

double ArcAngle::angle() const { return wrap_angle(std::atan2(s, c)); }

ArcAngle Arc::lowest() const { return ArcAngle::of(-e1.z, -e2.z); }

void Arc::bounding_box(Vec3& lo, Vec3& hi) const { bounding_box(ArcAngle{}, end, lo, hi); }

void Arc::bounding_box(const ArcAngle& from, const ArcAngle& to, Vec3& lo, Vec3& hi) const {
  const Vec3 a = point(from), b = point(to);
  double l[3] = {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
  double h[3] = {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
  const auto within = [&](const ArcAngle& t) { return !(t < from) && !(to < t); };
  for (int axis = 0; axis < 3; ++axis) {
    const double u = e1[axis], v = e2[axis];
    if (u == 0.0 && v == 0.0) continue;
    const double c = centre[axis], amplitude = radius * std::sqrt(u * u + v * v);
    if (within(ArcAngle::of(u, v))) h[axis] = c + amplitude;    // the maximum lies on the arc
    if (within(ArcAngle::of(-u, -v))) l[axis] = c - amplitude;  // the minimum lies on the arc
  }
  lo = {l[0], l[1], l[2]};
  hi = {h[0], h[1], h[2]};
}

std::optional<ArcAngle> first_entry(double k, double a, double b, const ArcAngle& limit, double skip) {
  // Never deeper than skip (min F = k - amplitude >= -skip): decided without a square root.
  const double amplitude2 = a * a + b * b;
  if (k + skip >= 0.0 && amplitude2 <= (k + skip) * (k + skip)) return std::nullopt;
  // Already inside (within the caller's tolerance) and going deeper: enters at once.
  if (k + a <= 0.0 && b <= 0.0) return ArcAngle{};
  // F = k + A cos(t - psi) with A = |(a, b)| turns negative at t = psi + beta, where
  // cos beta = -k / A and beta in (0, pi): rotate (a, b) / A by beta.
  const double amplitude = std::sqrt(amplitude2);
  const double cos_beta = std::clamp(-k / amplitude, -1.0, 1.0);
  const double sin_beta = std::sqrt(std::max(0.0, 1.0 - cos_beta * cos_beta));
  const ArcAngle enter = ArcAngle::of(a * cos_beta - b * sin_beta, b * cos_beta + a * sin_beta);
  if (limit < enter) return std::nullopt;
  return enter;
}

std::optional<ArcAngle> first_contact(const Arc& arc, const Obstacle& obstacle, double skip) {
  if (obstacle.is_plane) {
    const Vec3& n = obstacle.centre;
    return first_entry(dot(n, arc.centre) - obstacle.reach, arc.radius * dot(n, arc.e1),
                       arc.radius * dot(n, arc.e2), arc.end, skip);
  }
  // |p(t) - c|^2 - S^2 = K + P cos t + Q sin t; divided by 2S it is the gap near contact.
  const Vec3 w = arc.centre - obstacle.centre;
  const double s = obstacle.reach;
  const double scale = 0.5 / s;
  return first_entry((norm2(w) + arc.radius * arc.radius - s * s) * scale, 2.0 * arc.radius * dot(arc.e1, w) * scale,
                     2.0 * arc.radius * dot(arc.e2, w) * scale, arc.end, skip);
}

}  // namespace aggpack
