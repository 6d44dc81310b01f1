// The convex hull of points in 3-D, by Qhull (libqhull_r, the reentrant library; Barber,
// Dobkin and Huhdanpaa 1996), triangulated, each triangle anticlockwise seen from outside.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "aggpack/grains/grain_shape.hpp"

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

namespace aggpack {

ConvexHull convex_hull_of(const std::vector<Vec3>& points) {
  if (points.size() < 4) throw std::invalid_argument("convex_hull_of: a hull in 3-D needs at least 4 points");
  for (const Vec3& p : points)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw std::invalid_argument("convex_hull_of: a point is not finite");
  double extent = 0.0;  // the points' size, for what counts as a triangle of no area
  for (const Vec3& p : points) extent = std::max(extent, norm(p - points.front()));
  std::vector<coordT> coordinates;
  coordinates.reserve(3 * points.size());
  for (const Vec3& p : points) coordinates.insert(coordinates.end(), {p.x, p.y, p.z});
  qhT state;
  qhT* qh = &state;
  // Qhull's own messages go nowhere: a failure is reported by its code, as an exception here.
  FILE* null_device = std::fopen("/dev/null", "w");
  FILE* quiet = null_device ? null_device : stderr;
  qh_zero(qh, quiet);
  char command[] = "qhull Qt";  // triangulated output
  const int code =
      qh_new_qhull(qh, 3, static_cast<int>(points.size()), coordinates.data(), False, command, nullptr, quiet);
  ConvexHull hull;
  if (code == 0) {
    std::vector<int> slot(points.size(), -1);  // input point -> hull vertex
    facetT* facet;
    FORALLfacets {
      std::array<std::uint32_t, 3> triangle{};
      int corner = 0;
      vertexT *vertex, **vertexp;
      FOREACHvertex_(facet->vertices) {
        const int id = qh_pointid(qh, vertex->point);
        if (id < 0 || static_cast<std::size_t>(id) >= points.size()) continue;  // not an input point: none in "Qt"
        if (slot[static_cast<std::size_t>(id)] < 0) {
          slot[static_cast<std::size_t>(id)] = static_cast<int>(hull.vertices.size());
          hull.vertices.push_back(points[static_cast<std::size_t>(id)]);
        }
        if (corner < 3)
          triangle[static_cast<std::size_t>(corner)] = static_cast<std::uint32_t>(slot[static_cast<std::size_t>(id)]);
        ++corner;
      }
      if (corner != 3) continue;  // "Qt" gives triangles only
      const Vec3 outward{facet->normal[0], facet->normal[1], facet->normal[2]};
      const Vec3 &a = hull.vertices[triangle[0]], &b = hull.vertices[triangle[1]], &c = hull.vertices[triangle[2]];
      // "Qt" may split a face into triangles of no area, whose normal would be noise.
      if (norm(cross(b - a, c - a)) <= 1e-12 * extent * extent) continue;
      if (dot(cross(b - a, c - a), outward) < 0.0) std::swap(triangle[1], triangle[2]);
      hull.triangles.push_back(triangle);
    }
  }
  qh_freeqhull(qh, !qh_ALL);
  int still_long = 0, total_long = 0;
  qh_memfreeshort(qh, &still_long, &total_long);
  if (null_device) std::fclose(null_device);
  if (code != 0)
    throw std::invalid_argument("convex_hull_of: Qhull found no hull (the points are flat or coincident), code " +
                                std::to_string(code));
  return hull;
}

}  // namespace aggpack
