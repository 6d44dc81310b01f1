#pragma once
// An independent check of a deposited bed, written apart from the deposition code: brute
// force over pairs (sorted by height), and the cone test by solving every triple of contact
// normals directly.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "aggpack/core/container.hpp"
#include "aggpack/core/particle_store.hpp"

namespace aggpack {

struct BedReport {
  double worst_overlap = 0.0;       // largest overlap / smaller diameter
  std::size_t outside_walls = 0;
  std::size_t unsupported = 0;      // neither on the floor nor held by its contact cone
  std::size_t first_unsupported = 0;
  std::size_t on_floor = 0;
};

inline Vec3 min_image(Vec3 d, const Container& c) {
  if (c.periodic) {
    d.x -= c.length_x() * std::nearbyint(d.x / c.length_x());
    d.y -= c.length_y() * std::nearbyint(d.y / c.length_y());
  }
  return d;
}

// Is the upward vertical a non-negative combination of some of these unit normals?
inline bool vertical_in_cone(const std::vector<Vec3>& n) {
  const double eps = 1e-9;
  for (const Vec3& a : n)
    if (a.z > 1 - eps) return true;
  for (std::size_t i = 0; i < n.size(); ++i)
    for (std::size_t j = i + 1; j < n.size(); ++j)
      for (std::size_t k = j + 1; k < n.size(); ++k) {
        // Solve [n_i n_j n_k] alpha = z by Cramer's rule.
        const Vec3 &a = n[i], &b = n[j], &c = n[k];
        const double det = a.x * (b.y * c.z - b.z * c.y) - b.x * (a.y * c.z - a.z * c.y) + c.x * (a.y * b.z - a.z * b.y);
        if (std::abs(det) < 1e-12) continue;
        const double ai = (b.x * c.y - b.y * c.x) / det;
        const double aj = (c.x * a.y - c.y * a.x) / det;
        const double ak = (a.x * b.y - a.y * b.x) / det;
        if (ai >= -eps && aj >= -eps && ak >= -eps) return true;
      }
  return false;
}

// Spheres are checked against those placed before them (index order is drop order).
inline BedReport check_bed(const ParticleStore& bed, const Container& c, double tolerance) {
  BedReport report;
  const std::size_t n = bed.size();
  const Box& b = c.bounds;
  double r_max = 0.0;
  for (double r : bed.radius) r_max = std::max(r_max, r);
  std::vector<std::size_t> by_z(n);
  std::iota(by_z.begin(), by_z.end(), 0);
  std::sort(by_z.begin(), by_z.end(), [&](auto i, auto j) { return bed.position[i].z < bed.position[j].z; });
  std::vector<std::vector<Vec3>> normals(n);
  for (std::size_t a = 0; a < n; ++a) {
    const std::size_t i = by_z[a];
    for (std::size_t q = a + 1; q < n; ++q) {
      const std::size_t j = by_z[q];
      if (bed.position[j].z - bed.position[i].z > bed.radius[i] + r_max) break;
      const Vec3 d = min_image(bed.position[j] - bed.position[i], c);
      const double s = bed.radius[i] + bed.radius[j];
      const double dist = norm(d);
      if (dist >= s * (1 + 4 * tolerance)) continue;
      report.worst_overlap = std::max(report.worst_overlap, (s - dist) / (2 * std::min(bed.radius[i], bed.radius[j])));
      // The later-placed sphere rests on the earlier one.
      if (i > j) normals[i].push_back(d * (-1.0 / dist));
      else normals[j].push_back(d * (1.0 / dist));
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& p = bed.position[i];
    const double r = bed.radius[i], tol = 4 * tolerance * 2 * r;
    if (!c.periodic) {
      if (p.x - r < b.lo.x - tol || p.x + r > b.hi.x + tol || p.y - r < b.lo.y - tol || p.y + r > b.hi.y + tol)
        ++report.outside_walls;
      if (p.x - r <= b.lo.x + tol) normals[i].push_back({1, 0, 0});
      if (p.x + r >= b.hi.x - tol) normals[i].push_back({-1, 0, 0});
      if (p.y - r <= b.lo.y + tol) normals[i].push_back({0, 1, 0});
      if (p.y + r >= b.hi.y - tol) normals[i].push_back({0, -1, 0});
    }
    if (p.z - r < b.lo.z - tol) ++report.outside_walls;
    if (p.z - r <= b.lo.z + tol) {
      ++report.on_floor;
      continue;
    }
    if (!vertical_in_cone(normals[i]) && report.unsupported++ == 0) report.first_unsupported = i;
  }
  return report;
}

}  // namespace aggpack
