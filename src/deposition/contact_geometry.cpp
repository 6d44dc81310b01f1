#include "aggpack/deposition/contact_geometry.hpp"

#include <algorithm>
#include <numbers>

namespace aggpack {

namespace {
constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr Vec3 kUp{0.0, 0.0, 1.0};

double wrap_angle(double t) {
  t = std::fmod(t, kTwoPi);
  return t < 0.0 ? t + kTwoPi : t;
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

double Arc::lowest_t() const { return wrap_angle(std::atan2(-e2.z, -e1.z)); }

void Arc::bounding_box(Vec3& lo, Vec3& hi) const {
  const Vec3 a = point(0.0), b = point(t_end);
  double l[3] = {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
  double h[3] = {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
  for (int axis = 0; axis < 3; ++axis) {
    const double t_max = wrap_angle(std::atan2(e2[axis], e1[axis]));
    const double t_min = wrap_angle(t_max + std::numbers::pi);
    const double c = centre[axis], amplitude = radius * std::hypot(e1[axis], e2[axis]);
    if (t_max <= t_end) h[axis] = c + amplitude;
    if (t_min <= t_end) l[axis] = c - amplitude;
  }
  lo = {l[0], l[1], l[2]};
  hi = {h[0], h[1], h[2]};
}

std::optional<double> first_entry(double k, double a, double b, double limit, double skip) {
  const double amplitude = std::hypot(a, b);
  if (k - amplitude >= -skip) return std::nullopt;  // never deeper than skip
  if (amplitude == 0.0) return 0.0;
  // F < 0 exactly for t - psi in (beta, 2 pi - beta).
  const double psi = std::atan2(b, a);
  const double beta = std::acos(std::clamp(-k / amplitude, -1.0, 1.0));
  const double enter = wrap_angle(psi + beta);
  const double overlap = kTwoPi - 2.0 * beta;
  const double past_entry = wrap_angle(-enter);  // how far t = 0 lies past the entry
  if (past_entry <= 0.5 * overlap) return 0.0;  // already inside (within tolerance), going deeper
  if (enter <= limit) return enter;
  return std::nullopt;
}

std::optional<double> first_contact(const Arc& arc, const Obstacle& obstacle, double skip) {
  if (obstacle.is_plane) {
    const Vec3& n = obstacle.centre;
    return first_entry(dot(n, arc.centre) - obstacle.reach, arc.radius * dot(n, arc.e1),
                       arc.radius * dot(n, arc.e2), arc.t_end, skip);
  }
  // |p(t) - c|^2 - S^2 = K + P cos t + Q sin t; divided by 2S it is the gap near contact.
  const Vec3 w = arc.centre - obstacle.centre;
  const double s = obstacle.reach;
  const double scale = 0.5 / s;
  return first_entry((norm2(w) + arc.radius * arc.radius - s * s) * scale, 2.0 * arc.radius * dot(arc.e1, w) * scale,
                     2.0 * arc.radius * dot(arc.e2, w) * scale, arc.t_end, skip);
}

}  // namespace aggpack
