#include "aggpack/deposition/drop_and_roll.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace aggpack {

namespace {
// Consecutive events that move the sphere by less than this (relative to r) mean it is
// caught between contacts the tolerance cannot separate: redrop it.
constexpr double kNoProgress = 1e-12;
constexpr int kMaxEventsWithoutProgress = 20;
// A support whose coefficient is this close to zero is being left: roll on the others.
constexpr double kLeaving = 1e-9;
// Angle (radians) of the pieces an arc is searched in (0.2 to 0.7 measured; 0.7 fastest).
constexpr double kArcPiece = 0.7;

std::vector<double> all_radii(const ParticleStore& bed, std::span<const double> to_come) {
  std::vector<double> radii(bed.radius.begin(), bed.radius.end());
  radii.insert(radii.end(), to_come.begin(), to_come.end());
  return radii;
}

// Volume the bed will fill: its solid volume at a loose packing fraction, within the container.
double expected_bed_volume(const ParticleStore& bed, std::span<const double> to_come, const Container& c) {
  double solid = 0.0;
  for (double r : bed.radius) solid += r * r * r;
  for (double r : to_come) solid += r * r * r;
  solid *= 4.0 / 3.0 * std::numbers::pi;
  const double bed_volume = solid / 0.5;
  return std::isfinite(c.bounds.volume()) ? std::min(bed_volume, c.bounds.volume()) : bed_volume;
}


// z at which a support's coefficient, linear in the height of the dropped sphere on a
// two-support circle, becomes zero. Support i has n_i.z = s_i z + q_i.
struct LinearInZ {
  double slope = 0.0, intercept = 0.0;
};
LinearInZ vertical_normal_component(const Obstacle& o, const Vec3& p) {
  if (o.is_plane) return {0.0, o.centre.z};
  const double s = norm(p - o.centre);
  return {1.0 / s, -o.centre.z / s};
}

// A sphere with the upward vertical in the cone of its contact normals is held when one of
// them is the floor or there are three; it then rests on them (the floor alone when it is one).
// False on one sphere or a ridge: an unstable equilibrium.
bool held_at_rest(const Descent& descent, const std::vector<Obstacle>& contacts, Supports& supports) {
  bool on_floor = false;
  for (int i = 0; i < descent.active_count; ++i) on_floor = on_floor || contacts[descent.active[i]].id == kFloor;
  if (!on_floor && descent.active_count < 3) return false;
  for (int i = 0; i < descent.active_count; ++i) supports.ids[i] = contacts[descent.active[i]].id;
  if (on_floor) supports.ids = {kFloor, kNoSupport, kNoSupport};
  return true;
}

// The supports the sphere rolls on: positive coefficients (all of them on a tie), spheres
// first; none when only walls are left (they never hold: the sphere slides down them).
struct RollingSupports {
  std::array<const Obstacle*, 2> on{};
  int count = 0;
};
RollingSupports rolling_supports(const Descent& descent, const std::vector<Obstacle>& contacts, bool tie) {
  RollingSupports rolling;
  for (int i = 0; i < descent.active_count && rolling.count < 2; ++i)
    if (descent.alpha[i] > kLeaving || tie) rolling.on[rolling.count++] = &contacts[descent.active[i]];
  if (rolling.count == 2 && rolling.on[0]->is_plane) std::swap(rolling.on[0], rolling.on[1]);
  if (rolling.count >= 1 && rolling.on[0]->is_plane) rolling.count = 0;  // walls alone never hold: slide down them
  return rolling;
}

// The circle the sphere at p rolls on, over one support (a great circle about it) or two (the
// circle about their axis), downhill or, on a tie, in a random direction drawn from `rng`; it
// ends at its lowest point or where a support is left, whichever comes first (obstacles met
// on the way are not looked for here).
Arc rolling_arc(const RollingSupports& rolling, const Vec3& p, const Descent& descent, bool tie, Rng& rng) {
  const int count = rolling.count;
  const Obstacle& a = *rolling.on[0];
  Arc arc;
  std::array<LinearInZ, 2> lift{};  // n.z of each rolling support as a function of height
  if (count == 1) {
    arc.centre = a.centre;
    arc.e1 = normalized(p - a.centre);
    if (tie) {
      const double phi = 2.0 * std::numbers::pi * rng.uniform();
      const Vec3 u{std::cos(phi), std::sin(phi), 0.0};
      arc.e2 = normalized(u - dot(u, arc.e1) * arc.e1);
    } else {
      arc.e2 = normalized(descent.direction - dot(descent.direction, arc.e1) * arc.e1);
    }
  } else {
    const Obstacle& b = *rolling.on[1];
    const Vec3 axis = b.is_plane ? b.centre : normalized(b.centre - a.centre);
    arc.centre = a.centre + dot(p - a.centre, axis) * axis;
    arc.e1 = normalized(p - arc.centre);
    const Vec3 tangent = normalized(cross(axis, arc.e1));
    const double along = tie ? (rng.uniform() < 0.5 ? -1.0 : 1.0) : dot(tangent, descent.direction);
    arc.e2 = along < 0.0 ? -tangent : tangent;
    lift[1] = vertical_normal_component(b, p);
  }
  lift[0] = vertical_normal_component(a, p);
  arc.radius = norm(p - arc.centre);
  // A horizontal circle (two supports one above the other) has no lowest point: allow
  // half a turn; the events on it end the step.
  const bool level = std::abs(arc.e1.z) + std::abs(arc.e2.z) < 1e-12;
  arc.end = level ? ArcAngle::at(std::numbers::pi) : arc.lowest();
  // Leave a support where its coefficient reaches zero; alpha is linear in the height.
  const double c = count == 2 ? dot(a.normal(p), rolling.on[1]->normal(p)) : 0.0;
  for (int i = 0; i < count; ++i) {
    const LinearInZ& own = lift[i];
    const LinearInZ& other = lift[1 - i];
    const double slope = own.slope - (count == 2 ? c * other.slope : 0.0);
    const double intercept = own.intercept - (count == 2 ? c * other.intercept : 0.0);
    if (slope == 0.0) continue;
    const double z_leave = -intercept / slope;
    if (z_leave >= p.z) continue;  // the coefficient grows on the way down
    if (const auto t = first_entry(arc.centre.z - z_leave, arc.radius * arc.e1.z, arc.radius * arc.e2.z,
                                   arc.end, 0.0))
      arc.end = std::min(arc.end, *t);
  }
  return arc;
}
}  // namespace

std::string_view to_string(DepositionEnd end) { return name_of(kDepositionEndNames, end); }

Rng deposition_stream(std::uint64_t seed, std::uint32_t layer) {
  return Rng(seed, static_cast<std::uint64_t>(RngPurpose::Deposition) + (std::uint64_t{layer} << 32));
}

DropAndRoll::DropAndRoll(ParticleStore& bed, const Container& container, std::span<const double> radii_to_come,
                         const DepositionSettings& settings, Rng rng)
    : bed_(bed),
      container_(container),
      settings_(settings),
      rng_(rng),
      grid_(container, all_radii(bed, radii_to_come), expected_bed_volume(bed, radii_to_come, container)),
      supports_(bed.size()) {
  // Its contacts take the walls as planes; the scenario reader refuses a cylinder before this.
  if (container.is_cylinder())
    throw std::invalid_argument("DropAndRoll: a cylindrical container has a curved wall; drop-and-roll needs a box");
  grid_.reserve(bed.size() + radii_to_come.size());
  supports_.reserve(bed.size() + radii_to_come.size());
  for (std::size_t i = 0; i < bed.size(); ++i)
    grid_.insert(static_cast<std::uint32_t>(i), bed.position[i], bed.radius[i]);
}

std::size_t DropAndRoll::deposit(std::span<const double> radii, const SphereMaterials& materials, std::uint32_t layer,
                                 const DepositionObserver& observer) {
  const Box& b = container_.bounds;
  std::size_t placed = 0;
  for (std::size_t k = 0; k < radii.size(); ++k) {
    const double r = radii[k];
    ++stats_.requested;
    bool rested = false;
    for (std::size_t attempt = 0; attempt <= settings_.max_redrops && !rested; ++attempt) {
      const double x = container_.periodic ? rng_.uniform(b.lo.x, b.hi.x) : rng_.uniform(b.lo.x + r, b.hi.x - r);
      const double y = container_.periodic ? rng_.uniform(b.lo.y, b.hi.y) : rng_.uniform(b.lo.y + r, b.hi.y - r);
      const DropResult result = drop(x, y, r);
      stats_.ties_on_top += result.ties_on_top;
      stats_.ties_on_ridge += result.ties_on_ridge;
      if (!result.rested) {
        ++stats_.redrops;
        continue;
      }
      rested = true;
      if (result.position.z + r > b.lo.z + settings_.fill_height + settings_.tolerance * 2.0 * r) {
        stats_.end = DepositionEnd::FillHeight;
        return placed;
      }
      const Vec3 p = container_.wrapped(result.position);
      const std::size_t id = bed_.add(p, r, materials.density_of(k), layer, materials.material(k));
      grid_.insert(static_cast<std::uint32_t>(id), p, r);
      supports_.push_back(result.supports);
      ++placed;
      ++stats_.placed;
      if (observer.on_placed && observer.every > 0 && placed % observer.every == 0) observer.on_placed(placed);
      stats_.events += result.events;
      stats_.max_events_one_sphere = std::max(stats_.max_events_one_sphere, result.events);
      const auto& ids = result.supports.ids;
      if (ids[0] == kFloor) ++stats_.resting_on_floor;
      else if (ids[2] != kNoSupport) ++stats_.resting_on_three;
      if (std::any_of(ids.begin(), ids.end(), is_wall)) ++stats_.touching_a_wall;
    }
    if (!rested) {
      stats_.end = DepositionEnd::Unplaceable;
      return placed;
    }
  }
  return placed;
}

Obstacle DropAndRoll::sphere_obstacle(std::uint32_t k, const Vec3& p, double r) const {
  return {k, false, p + grid_.separation(p, bed_.position[k]), r + bed_.radius[k]};
}

// Every path step records the spheres near it (near_); whatever touches its end point is
// among them, so the contacts after a step need no second grid query.
void DropAndRoll::collect_contacts(const Vec3& p, double r, double tol) {
  contacts_.clear();
  for_each_wall_and_floor(r, [&](const Obstacle& o) {
    if (o.gap(p) <= tol) contacts_.push_back(o);
  });
  for (const Obstacle& o : near_)
    if (o.gap(p) <= tol) contacts_.push_back(o);
}

bool DropAndRoll::fall(Vec3& p, double r, double skip) {
  const double tol = 2.0 * skip;
  double best = container_.bounds.lo.z + r;  // the floor
  near_.clear();
  grid_.for_each_below(
      p, r,
      [&](std::uint32_t k) {
        const Vec3& c = bed_.position[k];
        const Vec3 d = grid_.separation(p, c);
        const double s = r + bed_.radius[k];
        const double h2 = d.x * d.x + d.y * d.y;
        if (h2 < (s + tol) * (s + tol)) near_.push_back({k, false, {p.x + d.x, p.y + d.y, c.z}, s});
        if (h2 >= (s - skip) * (s - skip)) return;  // passes by, or only grazes within tolerance
        const double hit = c.z + std::sqrt(s * s - h2);
        if (hit > best && hit <= p.z + tol) best = hit;
      },
      [&] { return best - tol; });
  const bool moved = best < p.z;
  p.z = std::min(p.z, best);
  return moved;
}

ArcAngle DropAndRoll::first_event_on_arc(const Arc& arc, double r, double skip) {
  const double tol = 2.0 * skip;
  ArcAngle t = arc.end;
  for_each_wall_and_floor(r, [&](const Obstacle& o) {
    if (const auto hit = first_contact(arc, o, skip)) t = std::min(t, *hit);
  });
  // Most rolls end early: search the arc piece by piece, each with its own small
  // neighbourhood, and stop at the first piece that holds an event. An obstacle met in a
  // later piece lies near that piece, so it cannot be entered earlier on the arc.
  const Vec3 pad{r + tol, r + tol, r + tol};
  const Vec3 start = arc.point(ArcAngle{});
  ArcAngle from;
  for (double step = kArcPiece;; step += kArcPiece) {
    const ArcAngle to = std::min(t, ArcAngle::at(step));
    Vec3 lo, hi;
    arc.bounding_box(from, to, lo, hi);
    near_.clear();
    grid_.for_each_in_box(lo - pad, hi + pad, [&](std::uint32_t k) {
      const Obstacle o = sphere_obstacle(k, start, r);
      // Spheres out of reach of the piece's bounding box cannot be touched on it.
      const double dx = std::max({lo.x - o.centre.x, 0.0, o.centre.x - hi.x});
      const double dy = std::max({lo.y - o.centre.y, 0.0, o.centre.y - hi.y});
      const double dz = std::max({lo.z - o.centre.z, 0.0, o.centre.z - hi.z});
      if (dx * dx + dy * dy + dz * dz >= (o.reach + tol) * (o.reach + tol)) return;
      near_.push_back(o);
      if (const auto hit = first_contact(arc, o, skip)) t = std::min(t, *hit);
    });
    if (!(to < t) || step >= 2.0 * std::numbers::pi) return t;  // the event is in this piece
    from = to;
  }
}

DropResult DropAndRoll::drop(double x, double y, double r) {
  const double tol = settings_.tolerance * 2.0 * r;
  const double skip = 0.5 * tol;
  DropResult out;
  Vec3 p{x, y, std::numeric_limits<double>::infinity()};
  fall(p, r, skip);
  int without_progress = 0;
  for (out.events = 1; out.events <= settings_.max_events; ++out.events) {
    if (settings_.record_paths) out.path.push_back(p);
    collect_contacts(p, r, tol);
    normals_.clear();
    for (const Obstacle& o : contacts_) normals_.push_back(o.normal(p));
    const Descent descent = steepest_descent(normals_);

    bool tie = false;
    if (descent.at_rest()) {
      if (held_at_rest(descent, contacts_, out.supports)) {
        out.rested = true;
        out.position = p;
        return out;
      }
      tie = true;  // balanced on one sphere or on a ridge: an unstable equilibrium
      (descent.active_count == 1 ? out.ties_on_top : out.ties_on_ridge) += 1;
    }

    const RollingSupports rolling = rolling_supports(descent, contacts_, tie);
    const Vec3 before = p;
    if (rolling.count == 0) {
      fall(p, r, skip);
    } else {
      const Arc arc = rolling_arc(rolling, p, descent, tie, rng_);
      p = arc.point(first_event_on_arc(arc, r, skip));
    }
    without_progress = norm(p - before) < kNoProgress * r ? without_progress + 1 : 0;
    if (without_progress > kMaxEventsWithoutProgress) break;
  }
  out.rested = false;
  out.position = p;
  return out;
}

}  // namespace aggpack
