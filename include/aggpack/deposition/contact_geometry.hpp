#pragma once
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "aggpack/core/vec3.hpp"

// The closed-form geometry of drop-and-roll (docs/method.md section 3), free of any bed:
// obstacles, the steepest admissible descent, circular paths and their events.
namespace aggpack {

// What a sphere touches or rests on: a particle index, the floor or a wall.
using SupportId = std::uint32_t;
inline constexpr SupportId kNoSupport = 0xFFFFFFFFu;
inline constexpr SupportId kFloor = 0xFFFFFFFEu;
inline constexpr SupportId kWallXLow = 0xFFFFFFF0u;  // then x high, y low, y high
inline constexpr SupportId kWallXHigh = kWallXLow + 1;
inline constexpr SupportId kWallYLow = kWallXLow + 2;
inline constexpr SupportId kWallYHigh = kWallXLow + 3;
[[nodiscard]] inline bool is_wall(SupportId id) { return id >= kWallXLow && id <= kWallYHigh; }
[[nodiscard]] inline bool is_particle(SupportId id) { return id < kWallXLow; }
// "floor", "wall_x_low", ..., or the particle index.
[[nodiscard]] std::string support_name(SupportId id);

struct Supports {
  std::array<SupportId, 3> ids{kNoSupport, kNoSupport, kNoSupport};
};

// Something the dropped sphere (radius r, centre p) must stay out of. A sphere k is the
// ball |p - c| < S with S = r + r_k; a wall or the floor is the half-space n.p < offset.
struct Obstacle {
  SupportId id = kNoSupport;
  bool is_plane = false;
  Vec3 centre;          // sphere: centre (the periodic image nearest p); plane: unit normal n
  double reach = 0.0;   // sphere: contact distance S; plane: offset (n.p >= offset is allowed)

  [[nodiscard]] double gap(const Vec3& p) const {
    return is_plane ? dot(centre, p) - reach : norm(p - centre) - reach;
  }
  // Unit contact normal, pointing from the obstacle towards p.
  [[nodiscard]] Vec3 normal(const Vec3& p) const {
    if (is_plane) return centre;
    const Vec3 d = p - centre;
    return d * (1.0 / norm(d));
  }
};

// Steepest descent that pushes into no contact: the projection of -z onto the cone
// {d : d.n_i >= 0}. By Moreau's decomposition, d = -(z - sum alpha_i n_i) with alpha the
// non-negative least-squares fit of z by the normals; found exactly by trying the subsets
// of at most three normals and keeping the one that satisfies the optimality conditions.
struct Descent {
  std::array<int, 3> active{-1, -1, -1};   // indices into the normals, alpha > 0
  std::array<double, 3> alpha{0.0, 0.0, 0.0};
  int active_count = 0;
  Vec3 direction;  // zero at rest
  [[nodiscard]] bool at_rest(double eps = 1e-12) const { return norm(direction) <= eps; }
};
[[nodiscard]] Descent steepest_descent(std::span<const Vec3> normals);

// A point of a circular path by its direction (cos t, sin t), ordered along the path by a
// pseudo-angle key that grows with t in [0, 2 pi) and needs no inverse trigonometry.
struct ArcAngle {
  double c = 1.0, s = 0.0;  // cos t, sin t
  double key = 0.0;         // in [0, 4), monotone in t
  static ArcAngle of(double c, double s);  // (c, s) need not be normalised
  static ArcAngle at(double t) { return of(std::cos(t), std::sin(t)); }
  [[nodiscard]] double angle() const;  // t in [0, 2 pi)
  [[nodiscard]] bool operator<(const ArcAngle& o) const { return key < o.key; }
};

// A circular path p(t) = m + rho (cos t e1 + sin t e2), from t = 0 to `end`; e1, e2 orthonormal.
struct Arc {
  Vec3 centre;
  double radius = 0.0;
  Vec3 e1, e2;
  ArcAngle end;
  [[nodiscard]] Vec3 point(const ArcAngle& t) const { return centre + radius * (t.c * e1 + t.s * e2); }
  [[nodiscard]] Vec3 point(double t) const { return point(ArcAngle::at(t)); }
  [[nodiscard]] ArcAngle lowest() const;  // where p_z is least
  void bounding_box(Vec3& lo, Vec3& hi) const;  // of the points from 0 to end
  void bounding_box(const ArcAngle& from, const ArcAngle& to, Vec3& lo, Vec3& hi) const;
};

// First t in [0, limit] where F(t) = k + a cos t + b sin t becomes negative, ignoring
// excursions that never go below -skip. Returns t = 0 when F is already negative and falling
// at t = 0 (within the tolerance the caller allowed), nothing when it never enters.
[[nodiscard]] std::optional<ArcAngle> first_entry(double k, double a, double b, const ArcAngle& limit, double skip);

// First point of the arc where the obstacle is entered (its gap becomes negative), as above.
[[nodiscard]] std::optional<ArcAngle> first_contact(const Arc& arc, const Obstacle& obstacle, double skip);

}  // namespace aggpack
