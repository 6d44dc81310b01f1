#include "aggpack/specimen/specimen.hpp"

#include <algorithm>
#include <initializer_list>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <numbers>

#include <fmt/format.h>

#include "aggpack/analysis/sphere_box_volume.hpp"
#include "aggpack/core/error.hpp"
#include "aggpack/core/overloaded.hpp"

namespace aggpack {

namespace {
constexpr double kPi = std::numbers::pi;

double ball_volume(double r) { return 4.0 / 3.0 * kPi * r * r * r; }

double sphere_region_volume(const MemberSphere& s, const SpecimenRegion& region) {
  return std::visit(Overloaded{[&](const Box& box) { return sphere_box_volume(s.centre, s.radius, box); },
                               [&](const VerticalCylinder& c) { return sphere_cylinder_volume(s.centre, s.radius, c); }},
                    region);
}

// A particle's volume inside the region: a sphere's exactly; a grain's union exactly in a box,
// by its spheres' shares in a cylinder.
double particle_region_volume(std::span<const MemberSphere> members, const SpecimenRegion& region) {
  if (members.size() == 1) return sphere_region_volume(members.front(), region);
  if (const Box* box = std::get_if<Box>(&region)) return union_volume_in_box(members, *box, 1e-9);
  double inside = 0.0, summed = 0.0;
  for (const MemberSphere& s : members) {
    inside += sphere_region_volume(s, region);
    summed += ball_volume(s.radius);
  }
  return summed > 0.0 ? union_mass_properties(members, 1e-9).volume * inside / summed : 0.0;
}

// Whether a ball, grown by `reach`, meets the region: its centre closer than r + reach to it.
bool reaches(const MemberSphere& s, double reach, const SpecimenRegion& region) {
  const Vec3& c = s.centre;
  const double r = s.radius + reach;
  if (const auto* cyl = std::get_if<VerticalCylinder>(&region)) {
    const double radial = std::max(std::hypot(c.x - cyl->x, c.y - cyl->y) - cyl->radius, 0.0);
    const double axial = std::max({cyl->z_lo - c.z, 0.0, c.z - cyl->z_hi});
    return radial * radial + axial * axial < r * r;
  }
  const Box& b = std::get<Box>(region);
  const double dx = std::max({b.lo.x - c.x, 0.0, c.x - b.hi.x}), dy = std::max({b.lo.y - c.y, 0.0, c.y - b.hi.y}),
               dz = std::max({b.lo.z - c.z, 0.0, c.z - b.hi.z});
  return dx * dx + dy * dy + dz * dz < r * r;
}

void check_region(const SpecimenRegion& region) {
  const Box b = region_bounds(region);
  const Vec3 size = b.size();
  const bool finite = std::isfinite(b.lo.x) && std::isfinite(b.lo.y) && std::isfinite(b.lo.z) &&
                      std::isfinite(b.hi.x) && std::isfinite(b.hi.y) && std::isfinite(b.hi.z);
  if (!finite || !(size.x > 0.0 && size.y > 0.0 && size.z > 0.0))
    throw InputError(fmt::format("the specimen {}: expected a region of positive, finite size", region_text(region)));
}
}  // namespace

Box region_bounds(const SpecimenRegion& region) {
  return std::visit(Overloaded{[](const Box& b) { return b; }, [](const VerticalCylinder& c) { return c.bounds(); }},
                    region);
}

double region_volume(const SpecimenRegion& region) {
  return std::visit(Overloaded{[](const Box& b) { return b.volume(); },
                               [](const VerticalCylinder& c) { return c.volume(); }},
                    region);
}

bool region_contains(const SpecimenRegion& region, const Vec3& p) {
  return std::visit(Overloaded{[&](const Box& b) { return b.contains(p); },
                               [&](const VerticalCylinder& c) { return c.contains(p); }},
                    region);
}

std::string region_text(const SpecimenRegion& region) {
  return std::visit(Overloaded{[](const Box& b) { return "box " + box_text(b); },
                               [](const VerticalCylinder& c) {
                                 return fmt::format("cylinder of radius {:.6g} m about ({:.6g}, {:.6g}), z from "
                                                    "{:.6g} to {:.6g} m",
                                                    c.radius, c.x, c.y, c.z_lo, c.z_hi);
                               }},
                    region);
}

Specimen cut_specimen(const PackedParticles& bed, const SpecimenOptions& options) {
  check_region(options.region);
  Specimen out;
  out.region = options.region;
  out.min_size = options.min_size;
  out.itz_thickness = options.itz_thickness;
  out.gap = options.gap;
  out.volume_method = std::holds_alternative<Box>(options.region)
                          ? "exact (each sphere's cut by the box's planes; each grain's union to 1e-9)"
                          : "exact for spheres (lens areas integrated over z); a grain by its spheres' shares";
  // Each particle's spheres, in the bed's order.
  std::map<std::size_t, std::vector<MemberSphere>> members;
  for (std::size_t i = 0; i < bed.spheres.size(); ++i) members[bed.particle_of_sphere[i]].push_back(bed.spheres[i]);
  for (auto& [particle, spheres] : members) {
    const bool kept = bed.particle_size[particle] >= options.min_size;
    // A kept particle reaches the region with its ITZ; a dropped one only with itself.
    const double reach = kept ? options.itz_thickness : 0.0;
    const bool touches = std::any_of(spheres.begin(), spheres.end(), [&](const MemberSphere& s) {
      return reaches(s, reach, options.region);
    });
    if (!touches) continue;
    if (!kept) {
      ++out.dropped_particles;
      out.dropped_volume += particle_region_volume(spheres, options.region);
      continue;
    }
    for (MemberSphere& sphere : spheres) {
      sphere.radius -= 0.5 * options.gap;
      if (!(sphere.radius > 0.0))
        throw InputError(fmt::format("gap {:.6g} m: as wide as a kept sphere in the specimen (radius {:.6g} m); "
                                     "expected a gap below the smallest kept sphere's diameter",
                                     options.gap, sphere.radius + 0.5 * options.gap));
    }
    // Shrunk by the gap, a particle that reached in by less than gap / 2 (with its ITZ) no
    // longer does: it is in no export, and so not counted as kept.
    const std::size_t before = out.spheres.size();
    for (const MemberSphere& s : spheres)
      if (reaches(s, options.itz_thickness, options.region)) {
        out.spheres.push_back(s);
        out.particle_of_sphere.push_back(out.kept_particles);
      }
    if (out.spheres.size() == before) {
      ++out.left_out_by_gap;
      continue;
    }
    ++out.kept_particles;
    out.aggregate_volume += particle_region_volume(spheres, options.region);
  }
  if (out.kept_particles == 0)
    throw InputError(fmt::format("the specimen {} holds no particle of the bed{}: expected a region inside the bed",
                                 region_text(options.region),
                                 out.dropped_particles ? fmt::format(" at or above the minimum size {:.6g} m "
                                                                     "({} smaller ones reach into it)",
                                                                     options.min_size, out.dropped_particles)
                                                       : std::string()));
  return out;
}

}  // namespace aggpack
