#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "aggpack/core/box.hpp"
#include "aggpack/core/enum_names.hpp"

namespace aggpack {

// A vertical motion of the whole container, floor and walls together (a tapped, vibrated or
// jigged bed), at rest before `start` and after end(). Two profiles:
// - Sine (a tap): z(t) = A sin(w (t - start)) for `cycles` periods. A tap is half a period:
//   the container rises and comes back, its peak acceleration A w^2 (the tap intensity
//   Gamma = A w^2 / g) downward at the top; it then stops dead, as on an anvil.
// - LiftAndDrop (ASTM C29's jigging, README "Jigging"): raised by A = `amplitude` with a
//   constant acceleration `lift_acceleration` for the first half of the height and the same
//   deceleration for the second (below g, the bed rides with it and arrives at rest), then
//   released: it falls freely, z = A - g (t - t_release)^2 / 2 with g = `fall_acceleration`,
//   and stops dead at its rest height (the firm base), met at sqrt(2 g A).
enum class MotionProfile : unsigned char { Sine, LiftAndDrop };
struct ContainerMotion {
  double start = 0.0;              // s
  double amplitude = 0.0;          // m
  double angular_frequency = 0.0;  // rad/s (Sine)
  double cycles = 0.5;             // (Sine)
  MotionProfile profile = MotionProfile::Sine;
  double lift_acceleration = 0.0;  // m/s^2 (LiftAndDrop), > 0
  double fall_acceleration = 0.0;  // m/s^2 (LiftAndDrop): |g|

  // A lift by `height` at `lift_acceleration` then a free fall under `g`, from `start`.
  static ContainerMotion lift_and_drop(double start, double height, double lift_acceleration, double g) {
    return {start, height, 0.0, 0.0, MotionProfile::LiftAndDrop, lift_acceleration, g};
  }
  [[nodiscard]] bool moving_at(double t) const {
    return amplitude != 0.0 && t > start && t < end();
  }
  // LiftAndDrop: the lift's duration, 2 sqrt(A / a), and the fall's, sqrt(2 A / g).
  [[nodiscard]] double lift_time() const { return 2.0 * std::sqrt(amplitude / lift_acceleration); }
  [[nodiscard]] double fall_time() const { return std::sqrt(2.0 * amplitude / fall_acceleration); }
  [[nodiscard]] double end() const {
    if (amplitude == 0.0) return start;
    if (profile == MotionProfile::LiftAndDrop) return start + lift_time() + fall_time();
    return start + cycles * 2.0 * std::numbers::pi / angular_frequency;
  }
  [[nodiscard]] double offset(double t) const {
    if (!moving_at(t)) return 0.0;
    const double s = t - start;
    if (profile == MotionProfile::Sine) return amplitude * std::sin(angular_frequency * s);
    const double lift = lift_time();
    if (s <= 0.5 * lift) return 0.5 * lift_acceleration * s * s;
    if (s <= lift) return amplitude - 0.5 * lift_acceleration * (lift - s) * (lift - s);
    return std::max(0.0, amplitude - 0.5 * fall_acceleration * (s - lift) * (s - lift));
  }
  [[nodiscard]] double velocity(double t) const {
    if (!moving_at(t)) return 0.0;
    const double s = t - start;
    if (profile == MotionProfile::Sine) return amplitude * angular_frequency * std::cos(angular_frequency * s);
    const double lift = lift_time();
    if (s <= 0.5 * lift) return lift_acceleration * s;
    if (s <= lift) return lift_acceleration * (lift - s);
    return -fall_acceleration * (s - lift);
  }
};

// container.shape: a box (floor and four side walls, or periodic sides) or a vertical
// cylinder (floor and one curved wall: the measures of ASTM C29 and C1252).
enum class ContainerShape { Box, Cylinder };
inline constexpr std::array kContainerShapeNames{EnumName<ContainerShape>{ContainerShape::Box, "box"},
                                                 EnumName<ContainerShape>{ContainerShape::Cylinder, "cylinder"}};

// The container, the one owner of the boundary: a floor at bounds.lo.z and side walls at
// the x and y faces of `bounds`; with periodic sides, x and y wrap instead. A cylinder has
// one side wall, the circle inscribed in the bounds' x-y square (its axis vertical through
// the bounds' centre), and is never periodic. Deposition, the DEM, the grid and the analysis
// ask it for gaps, normals, images and the walls' motion. Scenarios make containers with the
// floor at z = 0; a packing file from another tool gets its own bounding box.
struct Container {
  Box bounds;
  bool periodic = false;
  ContainerShape shape = ContainerShape::Box;
  // A cylinder's rim above the floor, where its content is struck off (the walls above it
  // are a collar); 0 for a box.
  double rim = 0.0;

  static Container square(double side, double height, bool periodic) {
    return {{{0.0, 0.0, 0.0}, {side, side, height}}, periodic};
  }
  static Container cylinder(double diameter, double height) {
    return {{{0.0, 0.0, 0.0}, {diameter, diameter, height}}, false, ContainerShape::Cylinder, height};
  }
  [[nodiscard]] bool is_cylinder() const { return shape == ContainerShape::Cylinder; }
  [[nodiscard]] double radius() const { return 0.5 * length_x(); }
  [[nodiscard]] double axis_x() const { return 0.5 * (bounds.lo.x + bounds.hi.x); }
  [[nodiscard]] double axis_y() const { return 0.5 * (bounds.lo.y + bounds.hi.y); }
  // The floor's area: side x side, or pi R^2.
  [[nodiscard]] double cross_section_area() const {
    return is_cylinder() ? std::numbers::pi * radius() * radius() : length_x() * length_y();
  }
  // The side of the largest square, centred in the footprint, that keeps `margin` from the
  // side walls (the whole width with periodic sides; sqrt 2 (R - margin) in a cylinder).
  [[nodiscard]] double widest_centred_square(double margin) const {
    const double width = std::min(length_x(), length_y());
    if (periodic) return width;
    return is_cylinder() ? std::numbers::sqrt2 * (radius() - margin) : width - 2.0 * margin;
  }
  // Whether a centre p lies within the side walls (always with periodic sides).
  [[nodiscard]] bool holds_horizontally(const Vec3& p) const {
    if (periodic) return true;
    if (is_cylinder()) return std::hypot(p.x - axis_x(), p.y - axis_y()) <= radius();
    return p.x >= bounds.lo.x && p.x <= bounds.hi.x && p.y >= bounds.lo.y && p.y <= bounds.hi.y;
  }
  [[nodiscard]] double length_x() const { return bounds.hi.x - bounds.lo.x; }
  [[nodiscard]] double length_y() const { return bounds.hi.y - bounds.lo.y; }
  [[nodiscard]] double height() const { return bounds.hi.z - bounds.lo.z; }
  // p with x and y brought into [lo, hi) when the sides are periodic; p itself otherwise.
  [[nodiscard]] Vec3 wrapped(Vec3 p) const {
    if (!periodic) return p;
    const auto wrap = [](double v, double lo, double length) {
      const double w = lo + std::fmod(std::fmod(v - lo, length) + length, length);
      return w >= lo + length ? lo : w;
    };
    p.x = wrap(p.x, bounds.lo.x, length_x());
    p.y = wrap(p.y, bounds.lo.y, length_y());
    return p;
  }

  // The displacement d taken to its nearest periodic image (|d.x| <= L_x / 2 and the same in
  // y) when the sides are periodic, for displacements within one and a half periods; d
  // itself otherwise. The branches are symmetric, so minimum_image(-d) is exactly -minimum_image(d).
  [[nodiscard]] Vec3 minimum_image(Vec3 d) const {
    if (!periodic) return d;
    const double lx = length_x(), ly = length_y();
    if (d.x > 0.5 * lx) d.x -= lx;
    else if (d.x < -0.5 * lx) d.x += lx;
    if (d.y > 0.5 * ly) d.y -= ly;
    else if (d.y < -0.5 * ly) d.y += ly;
    return d;
  }

  // Calls visit(centre) for a sphere of radius r at p and, with periodic sides, for each
  // image of it that reaches into the footprint across a side.
  template <class Visit>
  void for_each_image(const Vec3& p, double r, Visit&& visit) const {
    if (!periodic) {
      visit(p);
      return;
    }
    const auto shifts = [&](double v, double lo, double hi, double (&out)[3]) {
      int n = 0;
      out[n++] = 0.0;
      if (v - r < lo) out[n++] = hi - lo;
      if (v + r > hi) out[n++] = lo - hi;
      return n;
    };
    double sx[3], sy[3];
    const int nx = shifts(p.x, bounds.lo.x, bounds.hi.x, sx), ny = shifts(p.y, bounds.lo.y, bounds.hi.y, sy);
    for (int i = 0; i < nx; ++i)
      for (int j = 0; j < ny; ++j) visit(Vec3{p.x + sx[i], p.y + sy[j], p.z});
  }

  // The planes a sphere can touch, by index: the floor, then the four side walls (x low,
  // x high, y low, y high) unless the sides are periodic; a cylinder's floor and its one
  // curved wall (kCylinderWall).
  enum Plane : unsigned { kFloor = 0, kXLow, kXHigh, kYLow, kYHigh };
  static constexpr unsigned kCylinderWall = 1;
  [[nodiscard]] unsigned plane_count() const { return periodic ? 1u : is_cylinder() ? 2u : 5u; }
  // Distance from a centre x to plane w (positive inside the container); `towards` is set
  // to the unit normal from x towards the plane. A cylinder's wall: R minus x's distance
  // from the axis, towards the horizontal direction from the axis through x (+x on the axis).
  [[nodiscard]] double plane_distance(unsigned w, const Vec3& x, Vec3& towards) const {
    if (w != kFloor && is_cylinder()) {
      const double dx = x.x - axis_x(), dy = x.y - axis_y(), rho = std::hypot(dx, dy);
      towards = rho > 0.0 ? Vec3{dx / rho, dy / rho, 0.0} : Vec3{1.0, 0.0, 0.0};
      return radius() - rho;
    }
    switch (w) {
      case kFloor: towards = {0, 0, -1}; return x.z - bounds.lo.z;
      case kXLow: towards = {-1, 0, 0}; return x.x - bounds.lo.x;
      case kXHigh: towards = {1, 0, 0}; return bounds.hi.x - x.x;
      case kYLow: towards = {0, -1, 0}; return x.y - bounds.lo.y;
      default: towards = {0, 1, 0}; return bounds.hi.y - x.y;
    }
  }
  // The effective radius of a sphere of radius r in contact with plane w: r for a plane; for a
  // cylinder's wall, concave, 1 / (1/r - 1/(2R)) (its curvature halved: curved one way, flat
  // the other), as LAMMPS's region walls take it (region cylinder's contact radius -2R).
  [[nodiscard]] double wall_contact_radius(unsigned w, double r) const {
    if (w == kFloor || !is_cylinder()) return r;
    const double twice_radius = 2.0 * radius();
    return r * twice_radius / (twice_radius - r);
  }
  // Plane w as n . x = offset with n its inward unit normal. Drop-and-roll's alone, which
  // the scenario reader allows in boxes only (a cylinder's wall is no plane).
  struct PlaneEquation {
    Vec3 inward;
    double offset;
  };
  [[nodiscard]] PlaneEquation plane(unsigned w) const {
    switch (w) {
      case kFloor: return {{0, 0, 1}, bounds.lo.z};
      case kXLow: return {{1, 0, 0}, bounds.lo.x};
      case kXHigh: return {{-1, 0, 0}, -bounds.hi.x};
      case kYLow: return {{0, 1, 0}, bounds.lo.y};
      default: return {{0, -1, 0}, -bounds.hi.y};
    }
  }
  // The velocity of plane w when the container moves by `motion` (the same for the floor and
  // the walls: it moves as one), at time t (s). The DEM's wall contacts take it into their
  // relative velocity; the DEM also moves `bounds` with the motion's offset.
  [[nodiscard]] static Vec3 plane_velocity(unsigned /*w*/, const ContainerMotion& motion, double t) {
    return {0.0, 0.0, motion.velocity(t)};
  }
};

}  // namespace aggpack
