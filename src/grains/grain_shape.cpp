#include "aggpack/grains/grain_shape.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "aggpack/core/rng.hpp"
#include "tangent_radii.hpp"

namespace aggpack {
namespace {

// The icosahedron on the unit sphere, its triangles anticlockwise seen from outside.
ConvexHull unit_icosahedron() {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  ConvexHull h;
  for (const Vec3& v :
       {Vec3{-1, t, 0}, Vec3{1, t, 0}, Vec3{-1, -t, 0}, Vec3{1, -t, 0}, Vec3{0, -1, t}, Vec3{0, 1, t}, Vec3{0, -1, -t},
        Vec3{0, 1, -t}, Vec3{t, 0, -1}, Vec3{t, 0, 1}, Vec3{-t, 0, -1}, Vec3{-t, 0, 1}})
    h.vertices.push_back(normalized(v));
  h.triangles = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                 {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                 {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  return h;
}

// Each triangle split in four, the new vertices (the edges' midpoints) pushed out onto the
// unit sphere; an edge's midpoint is made once and shared by its two triangles.
void subdivide(ConvexHull& h) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> midpoint;
  const auto middle = [&](std::uint32_t a, std::uint32_t b) {
    const auto key = std::minmax(a, b);
    const auto [it, fresh] =
        midpoint.try_emplace({key.first, key.second}, static_cast<std::uint32_t>(h.vertices.size()));
    if (fresh) h.vertices.push_back(normalized(h.vertices[a] + h.vertices[b]));
    return it->second;
  };
  std::vector<std::array<std::uint32_t, 3>> split;
  split.reserve(4 * h.triangles.size());
  for (const auto& [a, b, c] : h.triangles) {
    const std::uint32_t ab = middle(a, b), bc = middle(b, c), ca = middle(c, a);
    split.push_back({a, ab, ca});
    split.push_back({b, bc, ab});
    split.push_back({c, ca, bc});
    split.push_back({ab, bc, ca});
  }
  h.triangles = std::move(split);
}

// The surface's distinct tangent planes (n.x <= offset inside): the points of a polyhedron's
// face share one (its normal, to the bit), so a face of many points is one plane; of an
// ellipsoid's points, each is its own. A face's offset is its points' largest n.x (they
// differ by rounding only).
grains_internal::PlaneColumns tangent_planes(const ConvexSurface& surface) {
  grains_internal::PlaneColumns planes;
  const Vec3* last_normal = nullptr;
  for (const SurfacePoint& p : surface) {
    const double offset = dot(p.normal, p.position);
    if (last_normal != nullptr && *last_normal == p.normal) {
      planes.offset.back() = std::max(planes.offset.back(), offset);
      continue;
    }
    planes.add(p.normal, offset);
    last_normal = &p.normal;
  }
  return planes;
}

}  // namespace

ConvexHull ellipsoid_hull(const Vec3& semi_axes, int subdivisions) {
  for (int axis = 0; axis < 3; ++axis)
    if (!(semi_axes[axis] > 0.0) || !std::isfinite(semi_axes[axis]))
      throw std::invalid_argument("ellipsoid_hull: the semi-axes must be positive and finite");
  if (subdivisions < 0 || subdivisions > 6)
    throw std::invalid_argument("ellipsoid_hull: subdivisions must lie in [0, 6] (20 x 4^6 = 81920 triangles)");
  ConvexHull h = unit_icosahedron();
  for (int s = 0; s < subdivisions; ++s) subdivide(h);
  for (Vec3& v : h.vertices) v = {v.x * semi_axes.x, v.y * semi_axes.y, v.z * semi_axes.z};
  return h;
}

ConvexSurface ellipsoid_surface(const Vec3& semi_axes, int subdivisions) {
  const ConvexHull hull = ellipsoid_hull(semi_axes, subdivisions);
  ConvexSurface surface;
  surface.reserve(hull.vertices.size());
  for (const Vec3& v : hull.vertices)  // the gradient of x²/a² + y²/b² + z²/c²
    surface.push_back({v, normalized(Vec3{v.x / (semi_axes.x * semi_axes.x), v.y / (semi_axes.y * semi_axes.y),
                                          v.z / (semi_axes.z * semi_axes.z)})});
  return surface;
}

ConvexSurface hull_surface(const ConvexHull& hull, double spacing) {
  if (!(spacing > 0.0)) throw std::invalid_argument("hull_surface: the spacing must be positive");
  ConvexSurface surface;
  for (const auto& [ia, ib, ic] : hull.triangles) {
    const Vec3 &a = hull.vertices[ia], &b = hull.vertices[ib], &c = hull.vertices[ic];
    const Vec3 normal = normalized(cross(b - a, c - a));
    const double side = std::max({norm(b - a), norm(c - b), norm(a - c)});
    const int n = std::max(1, static_cast<int>(std::min(1e3, std::ceil(side / spacing))));
    for (int i = 0; i < n; ++i)
      for (int j = 0; i + j < n; ++j)  // the centroid of each upright sub-triangle
        surface.push_back({a + (b - a) * ((i + 1.0 / 3.0) / n) + (c - a) * ((j + 1.0 / 3.0) / n), normal});
  }
  return surface;
}

std::vector<MemberSphere> fill_convex(const ConvexSurface& surface, std::size_t count) {
  if (surface.empty() || count == 0)
    throw std::invalid_argument("fill_convex: needs surface points and at least one sphere");
  for (const SurfacePoint& p : surface)
    if (!std::isfinite(norm2(p.position)) || !(std::abs(norm(p.normal) - 1.0) < 1e-6))
      throw std::invalid_argument("fill_convex: a surface point is not finite or its normal is not of unit length");
  // Each point's sphere: the largest behind every tangent plane that touches the point's own
  // plane there (its centre p - r n stays r behind plane k: r (1 - n_k.n) <= offset_k - n_k.p).
  const std::vector<double> radius = grains_internal::tangent_radii(tangent_planes(surface), surface);
  std::vector<MemberSphere> candidate(surface.size());
  for (std::size_t k = 0; k < surface.size(); ++k) {
    if (!std::isfinite(radius[k]))
      throw std::invalid_argument("fill_convex: the surface bounds no body (no tangent plane faces a point's plane)");
    candidate[k] = {surface[k].position - surface[k].normal * radius[k], radius[k]};
  }
  // How far each point lies outside the spheres chosen so far (at first: unbounded).
  std::vector<double> outside(surface.size(), std::numeric_limits<double>::infinity());
  double largest = 0.0;
  for (const MemberSphere& c : candidate) largest = std::max(largest, c.radius);
  const double covered = 1e-9 * largest;  // a point on a chosen sphere, to rounding
  std::vector<MemberSphere> spheres;
  while (spheres.size() < count) {
    // What a point's sphere would add: its size, unless the point is nearly covered already.
    std::size_t pick = surface.size();
    double best = covered;
    for (std::size_t k = 0; k < surface.size(); ++k)
      if (const double gain = std::min(candidate[k].radius, outside[k]); gain > best) best = gain, pick = k;
    if (pick == surface.size()) break;  // every point is on a sphere already
    const MemberSphere& s = candidate[pick];
    spheres.push_back(s);
    for (std::size_t k = 0; k < surface.size(); ++k)
      outside[k] = std::min(outside[k], norm(surface[k].position - s.centre) - s.radius);
  }
  return spheres;
}

SymmetricEigen symmetric_eigen(const InertiaTensor& t) {
  double a[3][3] = {{t[0], t[3], t[4]}, {t[3], t[1], t[5]}, {t[4], t[5], t[2]}};
  double v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const double size =
      std::abs(t[0]) + std::abs(t[1]) + std::abs(t[2]) + std::abs(t[3]) + std::abs(t[4]) + std::abs(t[5]);
  for (int sweep = 0; sweep < 50; ++sweep) {
    const double off = std::abs(a[0][1]) + std::abs(a[0][2]) + std::abs(a[1][2]);
    if (off <= 1e-15 * size) break;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q) {
        if (a[p][q] == 0.0) continue;
        // The rotation in the (p, q) plane that zeroes a[p][q] (Numerical Recipes' jacobi).
        const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
        const double tan = (theta >= 0.0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
        const double c = 1.0 / std::sqrt(tan * tan + 1.0), s = tan * c;
        for (int k = 0; k < 3; ++k) {  // columns p and q: A R
          const double akp = a[k][p], akq = a[k][q];
          a[k][p] = c * akp - s * akq;
          a[k][q] = s * akp + c * akq;
        }
        for (int k = 0; k < 3; ++k) {  // rows p and q: R^T (A R)
          const double apk = a[p][k], aqk = a[q][k];
          a[p][k] = c * apk - s * aqk;
          a[q][k] = s * apk + c * aqk;
        }
        for (int k = 0; k < 3; ++k) {
          const double vkp = v[k][p], vkq = v[k][q];
          v[k][p] = c * vkp - s * vkq;
          v[k][q] = s * vkp + c * vkq;
        }
      }
  }
  std::array<int, 3> order{0, 1, 2};
  std::sort(order.begin(), order.end(), [&](int i, int j) { return a[i][i] < a[j][j]; });
  SymmetricEigen e;
  for (int k = 0; k < 3; ++k) {
    const int i = order[static_cast<std::size_t>(k)];
    e.values[static_cast<std::size_t>(k)] = a[i][i];
    e.vectors[static_cast<std::size_t>(k)] = {v[0][i], v[1][i], v[2][i]};
  }
  return e;
}

GrainDimensions grain_dimensions(std::span<const MemberSphere> spheres, const MassProperties& mass) {
  if (spheres.empty()) throw std::invalid_argument("grain_dimensions: no spheres");
  const SymmetricEigen e = symmetric_eigen(mass.inertia);
  std::array<std::pair<double, Vec3>, 3> extent;
  for (std::size_t k = 0; k < 3; ++k) {
    const Vec3& u = e.vectors[k];
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const MemberSphere& s : spheres) {
      lo = std::min(lo, dot(u, s.centre) - s.radius);
      hi = std::max(hi, dot(u, s.centre) + s.radius);
    }
    extent[k] = {hi - lo, u};
  }
  std::sort(extent.begin(), extent.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
  GrainDimensions d;
  d.length = extent[0].first, d.width = extent[1].first, d.thickness = extent[2].first;
  d.axes = {extent[0].second, extent[1].second, cross(extent[0].second, extent[1].second)};
  return d;
}

namespace {

// The spheres moved to their centre of mass and turned onto their dimensions' axes (length
// along x), scaled to a length of 1; the mass properties carried along (volume s³, inertia
// s⁵ Rᵀ I R), not computed again.
GrainTemplate in_body_frame(const std::vector<MemberSphere>& spheres) {
  const MassProperties mass = union_mass_properties(spheres, 1e-9);
  const GrainDimensions d = grain_dimensions(spheres, mass);
  const double scale = 1.0 / d.length;
  GrainTemplate t;
  for (const MemberSphere& s : spheres) {
    const Vec3 r = s.centre - mass.centre_of_mass;
    t.spheres.push_back({Vec3{dot(r, d.axes[0]), dot(r, d.axes[1]), dot(r, d.axes[2])} * scale, s.radius * scale});
  }
  const InertiaTensor& i = mass.inertia;
  const auto apply = [&](const Vec3& v) {
    return Vec3{i[0] * v.x + i[3] * v.y + i[4] * v.z, i[3] * v.x + i[1] * v.y + i[5] * v.z,
                i[4] * v.x + i[5] * v.y + i[2] * v.z};
  };
  const auto element = [&](int a, int b) { return std::pow(scale, 5) * dot(d.axes[a], apply(d.axes[b])); };
  t.mass.volume = mass.volume * scale * scale * scale;
  t.mass.inertia = {element(0, 0), element(1, 1), element(2, 2), element(0, 1), element(0, 2), element(1, 2)};
  t.dimensions = grain_dimensions(t.spheres, t.mass);
  return t;
}

// The spheres' mass properties as if none overlapped (each ball's own, by parallel axes):
// cheap, and close enough for a grain's principal axes.
MassProperties summed_mass(const std::vector<MemberSphere>& spheres) {
  const auto ball = [](double r) { return 4.0 / 3.0 * std::numbers::pi * r * r * r; };
  MassProperties m;
  for (const MemberSphere& s : spheres) {
    m.volume += ball(s.radius);
    m.centre_of_mass += s.centre * ball(s.radius);
  }
  m.centre_of_mass *= 1.0 / m.volume;
  for (const MemberSphere& s : spheres) {
    const double v = ball(s.radius), own = 0.4 * v * s.radius * s.radius;
    const Vec3 d = s.centre - m.centre_of_mass;
    const InertiaTensor add{own + v * (d.y * d.y + d.z * d.z),
                            own + v * (d.x * d.x + d.z * d.z),
                            own + v * (d.x * d.x + d.y * d.y),
                            -v * d.x * d.y,
                            -v * d.x * d.z,
                            -v * d.y * d.z};
    for (std::size_t k = 0; k < 6; ++k) m.inertia[k] += add[k];
  }
  return m;
}

// The spheres that `fill(axes)` makes, the axes corrected (at most 30 times) until the
// spheres' extents along their principal axes (of their summed inertia: overlaps counted
// twice, good enough for the axes) give I/L and S/I within `tolerance`; the best try.
template <class Fill>
std::vector<MemberSphere> fit_proportions(double elongation, double flatness, double tolerance, Fill fill) {
  Vec3 axes{1.0, elongation, elongation * flatness};
  std::vector<MemberSphere> best;
  double best_miss = std::numeric_limits<double>::infinity();
  for (int attempt = 0; attempt < 30; ++attempt) {
    std::vector<MemberSphere> spheres = fill(axes);
    const MassProperties summed = summed_mass(spheres);
    const GrainDimensions d = grain_dimensions(spheres, summed);
    const double got_elongation = d.width / d.length, got_flatness = d.thickness / d.width;
    const double miss = std::max(std::abs(got_elongation - elongation), std::abs(got_flatness - flatness));
    // A grain of one sphere is a sphere whatever the axes it fills: no correction changes it
    // (and squeezing the axes on would make an angular hull's surface points without bound).
    const bool one_sphere = spheres.size() == 1;
    if (miss < best_miss) best_miss = miss, best = std::move(spheres);
    if (miss <= tolerance || one_sphere) break;
    // Each axis corrected by the ratio it missed (the width against the length, the thickness
    // against the width), at most by a factor of 2 at a time.
    axes.y *= std::clamp(elongation / got_elongation, 0.5, 2.0);
    axes.z *= std::clamp(elongation * flatness / (got_elongation * got_flatness), 0.5, 2.0);
    axes.y = std::min(axes.y, axes.x), axes.z = std::min(axes.z, axes.y);
  }
  return best;
}

void check_proportions(double elongation, double flatness, std::size_t count) {
  if (!(elongation > 0.0 && elongation <= 1.0) || !(flatness > 0.0 && flatness <= 1.0))
    throw std::invalid_argument("a grain's elongation I/L and flatness S/I must lie in (0, 1]");
  if (count == 0) throw std::invalid_argument("a grain needs at least one sphere");
}

}  // namespace

GrainTemplate rounded_grain(double elongation, double flatness, std::size_t count, double tolerance) {
  check_proportions(elongation, flatness, count);
  return in_body_frame(fit_proportions(elongation, flatness, tolerance, [&](const Vec3& axes) {
    return fill_convex(ellipsoid_surface(axes, 4), count);
  }));
}

GrainTemplate angular_grain(double elongation, double flatness, std::size_t corners, std::size_t count,
                            std::uint64_t seed, double tolerance) {
  check_proportions(elongation, flatness, count);
  if (corners < 4) throw std::invalid_argument("an angular grain needs at least 4 corners");
  Rng rng = make_rng(seed, RngPurpose::Shapes);
  std::vector<Vec3> directions;
  for (std::size_t k = 0; k < corners; ++k) {
    const double z = rng.uniform(-1.0, 1.0), phi = rng.uniform(0.0, 2.0 * std::numbers::pi);
    const double ring = std::sqrt(std::max(0.0, 1.0 - z * z));
    directions.push_back({ring * std::cos(phi), ring * std::sin(phi), z});
  }
  const ConvexHull unit = convex_hull_of(directions);
  return in_body_frame(fit_proportions(elongation, flatness, tolerance, [&](const Vec3& axes) {
    ConvexHull scaled = unit;
    for (Vec3& v : scaled.vertices) v = {v.x * axes.x, v.y * axes.y, v.z * axes.z};
    // About a thousand surface points whatever the hull (sub-triangles of area about A / 2000,
    // half of them sampled), and at most 200 along any edge (a hull squeezed flat has little
    // area for its edges' length).
    double area = 0.0, longest_edge = 0.0;
    for (const auto& [a, b, c] : scaled.triangles) {
      const Vec3 &p = scaled.vertices[a], &q = scaled.vertices[b], &r = scaled.vertices[c];
      area += 0.5 * norm(cross(q - p, r - p));
      longest_edge = std::max({longest_edge, norm(q - p), norm(r - q), norm(p - r)});
    }
    return fill_convex(hull_surface(scaled, std::max(std::sqrt(2.0 * area / 2000.0), longest_edge / 200.0)), count);
  }));
}

}  // namespace aggpack
