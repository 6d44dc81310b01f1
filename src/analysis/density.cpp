#include "aggpack/analysis/density.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <fmt/format.h>

#include "aggpack/analysis/sphere_box_volume.hpp"
#include "aggpack/analysis/sphere_cylinder_volume.hpp"
#include "aggpack/core/error.hpp"
#include "aggpack/core/quaternion.hpp"
#include "aggpack/grains/union_mass_properties.hpp"

namespace aggpack {

namespace {
double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const auto mid = v.begin() + static_cast<long>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// The solid of a packing in pieces whose volume in a box is exact: each sphere of no rigid
// body, and each rigid body (the union of its member spheres, each point once).
struct Piece {
  Vec3 centre;  // a sphere's centre, a body's centre of mass
  double reach;  // the radius of the sphere about the centre that holds the piece
  std::size_t index;  // in the store's spheres or its bodies
  bool body;
};

double body_reach(const ParticleStore& p, std::size_t b) {
  double reach = 0.0;
  for (std::uint32_t i = p.bodies.first_member[b]; i < p.bodies.first_member[b] + p.bodies.member_count[b]; ++i)
    reach = std::max(reach, norm(p.body_offset[i]) + p.radius[i]);
  return reach;
}

// The spheres first, in the store's order (a packing of spheres sums as it always has), then the bodies.
template <class Visit>
void for_each_piece(const ParticleStore& p, Visit&& visit) {
  const bool bodies = !p.bodies.empty();
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!bodies || p.body[i] == kNoBody) visit(Piece{p.position[i], p.radius[i], i, false});
  for (std::size_t b = 0; b < p.bodies.size(); ++b) visit(Piece{p.bodies.position[b], body_reach(p, b), b, true});
}

// Its whole volume.
double piece_volume(const ParticleStore& p, const Piece& piece) {
  const double r = piece.reach;
  return piece.body ? p.bodies.volume[piece.index] : 4.0 / 3.0 * std::numbers::pi * r * r * r;
}

// Its volume inside `box`, the piece moved to `centre` (one of its periodic images): a
// body's by the slicing of its union cut by the box (to 1e-6 of its spheres' summed volume),
// unless its bounding sphere lies wholly inside the box or a box plane separates them.
double piece_volume_in_box(const ParticleStore& p, const Piece& piece, const Vec3& centre, const Box& box) {
  if (!piece.body) return sphere_box_volume(centre, piece.reach, box);
  const double r = piece.reach;
  if (centre.x + r <= box.lo.x || centre.x - r >= box.hi.x || centre.y + r <= box.lo.y || centre.y - r >= box.hi.y ||
      centre.z + r <= box.lo.z || centre.z - r >= box.hi.z)
    return 0.0;
  if (centre.x - r >= box.lo.x && centre.x + r <= box.hi.x && centre.y - r >= box.lo.y && centre.y + r <= box.hi.y &&
      centre.z - r >= box.lo.z && centre.z + r <= box.hi.z)
    return piece_volume(p, piece);
  const std::size_t b = piece.index;
  const Quaternion& q = p.bodies.orientation[b];
  std::vector<MemberSphere> members;
  for (std::uint32_t i = p.bodies.first_member[b]; i < p.bodies.first_member[b] + p.bodies.member_count[b]; ++i)
    members.push_back({centre + rotate(q, p.body_offset[i]), p.radius[i]});
  return union_volume_in_box(members, box, 1e-6);
}
}  // namespace

Container bounding_container(const ParticleStore& particles) {
  if (particles.empty()) return {};
  Box b{particles.position[0], particles.position[0]};
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const Vec3& c = particles.position[i];
    const double r = particles.radius[i];
    b.lo = {std::min(b.lo.x, c.x - r), std::min(b.lo.y, c.y - r), std::min(b.lo.z, c.z - r)};
    b.hi = {std::max(b.hi.x, c.x + r), std::max(b.hi.y, c.y + r), std::max(b.hi.z, c.z + r)};
  }
  return {b, false};
}

double solid_volume_in_box(const ParticleStore& particles, const Container& container, const Box& box) {
  double volume = 0.0;
  for_each_piece(particles, [&](const Piece& piece) {
    container.for_each_image(piece.centre, piece.reach,
                             [&](const Vec3& c) { volume += piece_volume_in_box(particles, piece, c, box); });
  });
  return volume;
}

namespace {
// A body's volume in `box` by its spheres' shares: its union's volume times the fraction of its
// spheres' summed volume that lies in the box (exact sphere-box volumes). Not its exact volume
// in the box, but smooth in its pose and some hundred times cheaper: what the surface estimate
// of measure_bed takes (sampled at every step of the quiet criterion). A sphere's is exact.
double piece_share_in_box(const ParticleStore& p, const Piece& piece, const Vec3& centre, const Box& box) {
  if (!piece.body) return sphere_box_volume(centre, piece.reach, box);
  const std::size_t b = piece.index;
  const Quaternion& q = p.bodies.orientation[b];
  double inside = 0.0, all = 0.0;
  for (std::uint32_t i = p.bodies.first_member[b]; i < p.bodies.first_member[b] + p.bodies.member_count[b]; ++i) {
    const double r = p.radius[i];
    inside += sphere_box_volume(centre + rotate(q, p.body_offset[i]), r, box);
    all += 4.0 / 3.0 * std::numbers::pi * r * r * r;
  }
  return p.bodies.volume[b] * inside / all;
}

using PieceInBox = double (*)(const ParticleStore&, const Piece&, const Vec3&, const Box&);

Profile vertical_profile_by(const ParticleStore& particles, const Container& container, double thickness,
                            PieceInBox volume_in_box) {
  const Box& footprint = container.bounds;
  const double z0 = footprint.lo.z;
  double top = z0;
  for (std::size_t i = 0; i < particles.size(); ++i)
    top = std::max(top, particles.position[i].z + particles.radius[i]);
  const auto bins = static_cast<long>(std::max(1.0, std::ceil((top - z0) / thickness)));
  // Each sphere (or grain) adds its exact volume to the slices it reaches.
  std::vector<double> volume(static_cast<std::size_t>(bins), 0.0);
  for_each_piece(particles, [&](const Piece& piece) {
    const double r = piece.reach;
    container.for_each_image(piece.centre, r, [&](const Vec3& c) {
      const long first = std::max(0L, static_cast<long>(std::floor((c.z - r - z0) / thickness)));
      const long last = std::min(bins - 1, static_cast<long>(std::floor((c.z + r - z0) / thickness)));
      for (long k = first; k <= last; ++k) {
        Box slab = footprint;
        slab.lo.z = z0 + thickness * static_cast<double>(k);
        slab.hi.z = slab.lo.z + thickness;
        volume[static_cast<std::size_t>(k)] += volume_in_box(particles, piece, c, slab);
      }
    });
  });
  Profile profile;
  // A cylinder's spheres all lie inside its wall: their volume in the bounds' slab is theirs in its circle's.
  const double slab_volume = container.cross_section_area() * thickness;
  for (long k = 0; k < bins; ++k) {
    profile.position.push_back(z0 + thickness * (static_cast<double>(k) + 0.5));
    profile.solid_fraction.push_back(volume[static_cast<std::size_t>(k)] / slab_volume);
  }
  return profile;
}
}  // namespace

Profile vertical_profile(const ParticleStore& particles, const Container& container, double thickness) {
  return vertical_profile_by(particles, container, thickness, piece_volume_in_box);
}

namespace {
// A piece's volume inside a vertical cylinder: a sphere's exact (lens areas over z); a grain's
// by its spheres' shares of its union's volume, as piece_share_in_box does for boxes.
double piece_share_in_cylinder(const ParticleStore& p, const Piece& piece, const VerticalCylinder& cylinder) {
  if (!piece.body) return sphere_cylinder_volume(piece.centre, piece.reach, cylinder, 1e-9);
  const std::size_t b = piece.index;
  const Quaternion& q = p.bodies.orientation[b];
  double inside = 0.0, all = 0.0;
  for (std::uint32_t i = p.bodies.first_member[b]; i < p.bodies.first_member[b] + p.bodies.member_count[b]; ++i) {
    const double r = p.radius[i];
    inside += sphere_cylinder_volume(piece.centre + rotate(q, p.body_offset[i]), r, cylinder, 1e-9);
    all += 4.0 / 3.0 * std::numbers::pi * r * r * r;
  }
  return p.bodies.volume[b] * inside / all;
}

// A cylinder's shells: ring k holds the points whose distance from the wall is in
// [k t, (k + 1) t), the volume inside the cylinder of radius R - k t less that inside R - (k + 1) t.
Profile radial_wall_profile(const ParticleStore& particles, const Container& container, double thickness,
                            double z_lo, double z_hi) {
  Profile profile;
  const double radius = container.radius();
  const auto bins = static_cast<std::size_t>(std::floor(radius / thickness));
  const auto inset = [&](double depth) {
    return VerticalCylinder{container.axis_x(), container.axis_y(), z_lo, z_hi, std::max(radius - depth, 0.0)};
  };
  std::vector<double> volume(bins, 0.0);
  for_each_piece(particles, [&](const Piece& piece) {
    const Vec3& c = piece.centre;
    const double r = piece.reach;
    if (c.z + r <= z_lo || c.z - r >= z_hi) return;
    Vec3 outward;
    const double near = container.plane_distance(Container::kCylinderWall, c, outward);
    const long first = std::max(static_cast<long>(std::floor((near - r) / thickness)), 0L);
    const long last = std::min(static_cast<long>(std::floor((near + r) / thickness)), static_cast<long>(bins) - 1);
    if (first > last) return;
    double outer = piece_share_in_cylinder(particles, piece, inset(thickness * static_cast<double>(first)));
    for (long k = first; k <= last; ++k) {
      const double inner = piece_share_in_cylinder(particles, piece, inset(thickness * static_cast<double>(k + 1)));
      volume[static_cast<std::size_t>(k)] += outer - inner;
      outer = inner;
    }
  });
  for (std::size_t k = 0; k < bins; ++k) {
    const double a = radius - thickness * static_cast<double>(k), b = a - thickness;
    profile.position.push_back(thickness * (static_cast<double>(k) + 0.5));
    profile.solid_fraction.push_back(volume[k] / (std::numbers::pi * (a * a - b * b) * (z_hi - z_lo)));
  }
  return profile;
}
}  // namespace

Profile wall_distance_profile(const ParticleStore& particles, const Container& container,
                              double thickness, double z_lo, double z_hi) {
  Profile profile;
  if (container.periodic || z_hi <= z_lo) return profile;
  if (container.is_cylinder()) return radial_wall_profile(particles, container, thickness, z_lo, z_hi);
  const Box& f = container.bounds;
  const double half_width = 0.5 * std::min(container.length_x(), container.length_y());
  const auto bins = static_cast<std::size_t>(std::floor(half_width / thickness));
  const auto inset_box = [&](double inset) {
    return Box{{f.lo.x + inset, f.lo.y + inset, z_lo}, {f.hi.x - inset, f.hi.y - inset, z_hi}};
  };
  // Shell k: distance to the nearest side wall in [k t, (k + 1) t). That distance changes
  // at most as fast as the position, so a sphere spans near - r .. near + r.
  const auto range = [&](const Vec3& c, double r) {
    const double near = std::min({c.x - f.lo.x, c.y - f.lo.y, f.hi.x - c.x, f.hi.y - c.y});
    return std::pair<long, long>{static_cast<long>(std::floor((near - r) / thickness)),
                                 static_cast<long>(std::floor((near + r) / thickness))};
  };
  std::vector<double> volume(bins, 0.0);
  for_each_piece(particles, [&](const Piece& piece) {
    const Vec3& c = piece.centre;
    const double r = piece.reach;
    if (c.z + r <= z_lo || c.z - r >= z_hi) return;
    auto [first, last] = range(c, r);
    first = std::max(first, 0L);
    last = std::min(last, static_cast<long>(bins) - 1);
    if (first > last) return;
    // Volume inside each inset square, differenced into shells.
    double outer = piece_volume_in_box(particles, piece, c, inset_box(thickness * static_cast<double>(first)));
    for (long k = first; k <= last; ++k) {
      const double inner = piece_volume_in_box(particles, piece, c, inset_box(thickness * static_cast<double>(k + 1)));
      volume[k] += outer - inner;
      outer = inner;
    }
  });
  for (std::size_t k = 0; k < bins; ++k) {
    const double a = thickness * static_cast<double>(k), b = a + thickness;
    const double lx = container.length_x(), ly = container.length_y();
    const double shell_area = (lx - 2 * a) * (ly - 2 * a) - (lx - 2 * b) * (ly - 2 * b);
    profile.position.push_back(0.5 * (a + b));
    profile.solid_fraction.push_back(volume[k] / (shell_area * (z_hi - z_lo)));
  }
  return profile;
}

BedGeometry measure_bed(const ParticleStore& particles, const Container& container) {
  BedGeometry bed;
  bed.floor = container.bounds.lo.z;
  if (particles.empty()) return bed;
  // d_max: the largest sphere's or grain's (the diameter of the sphere that holds it).
  double reach_min = std::numeric_limits<double>::infinity(), reach_max = 0.0, solid = 0.0;
  for_each_piece(particles, [&](const Piece& piece) {
    reach_min = std::min(reach_min, piece.reach);
    reach_max = std::max(reach_max, piece.reach);
    solid += piece_volume(particles, piece);
  });
  bed.d_min = 2.0 * reach_min;
  bed.d_max = 2.0 * reach_max;
  for (std::size_t i = 0; i < particles.size(); ++i)
    bed.top = std::max(bed.top, particles.position[i].z + particles.radius[i]);
  // Equivalent height: a bed of the median slice fraction holding the same solid volume (a
  // grain split among the slices by its spheres' shares: an estimate, as this height is).
  const Profile slices = vertical_profile_by(particles, container, bed.d_max, piece_share_in_box);
  const double bulk_fraction = median(slices.solid_fraction);
  const double footprint = container.cross_section_area();
  bed.surface = bulk_fraction > 0.0 ? std::min(bed.floor + solid / (footprint * bulk_fraction), bed.top) : bed.top;
  return bed;
}

Box place_virtual_cube(double side, const Container& container, const BedGeometry& bed) {
  const double half = 0.5 * side;
  const double cx = 0.5 * (container.bounds.lo.x + container.bounds.hi.x);
  const double cy = 0.5 * (container.bounds.lo.y + container.bounds.hi.y);
  const double cz = 0.5 * (bed.floor + bed.surface);
  const Box box{{cx - half, cy - half, cz - half}, {cx + half, cy + half, cz + half}};
  const double slack = 1e-9 * std::max(bed.d_max, side);
  const auto fail = [&](const char* what, double largest) {
    throw InputError(fmt::format(
        "a virtual cube of side {:.6g} m comes closer than d_max = {:.6g} m to {} "
        "(floor {:.6g} m, free surface {:.6g} m, container {}{:.6g} x {:.6g} m); the largest admissible side is "
        "{:.6g} m",
        side, bed.d_max, what, bed.floor, bed.surface, container.is_cylinder() ? "a cylinder in " : "",
        container.length_x(), container.length_y(),
        std::max(largest, 0.0)));
  };
  const double vertical_limit = bed.surface - bed.floor - 2.0 * bed.d_max;
  const double horizontal_limit = container.widest_centred_square(bed.d_max);
  if (side > vertical_limit + slack)
    fail("the floor or the free surface", std::min(vertical_limit, horizontal_limit));
  if (side > horizontal_limit + slack) fail("a side wall", std::min(vertical_limit, horizontal_limit));
  return box;
}

DensityResult measure_density(const ParticleStore& particles, const Container& container,
                              std::span<const Box> boxes) {
  DensityResult result;
  for (const Box& box : boxes) {
    const double d = solid_volume_in_box(particles, container, box) / box.volume();
    result.boxes.push_back({box.size().x, box, d});
    result.mean += d;
  }
  if (boxes.empty()) return result;
  const auto n = static_cast<double>(boxes.size());
  result.mean /= n;
  if (boxes.size() > 1) {
    double ss = 0.0;
    for (const auto& b : result.boxes) ss += (b.density - result.mean) * (b.density - result.mean);
    result.sd = std::sqrt(ss / (n - 1.0));
  }
  return result;
}

}  // namespace aggpack
