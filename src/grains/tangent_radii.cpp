// tangent_radii over Highway vectors, compiled for every target of Highway's list and
// dispatched at run time. Each lane mirrors the scalar bound of one plane (see the header),
// the planes after the last whole vector are taken one by one the same way, and the module is
// compiled without contracting products into FMAs, so every target gives the same bits.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "tangent_radii.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <algorithm>

#include "tangent_radii.hpp"

HWY_BEFORE_NAMESPACE();
namespace aggpack::grains_internal::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

void TangentRadii(const PlaneColumns& planes, const SurfacePoint* points, std::size_t count, double* radii) {
  const hn::ScalableTag<double> d;
  using V = hn::Vec<decltype(d)>;
  const std::size_t lanes = hn::Lanes(d), size = planes.offset.size();
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0), parallel = hn::Set(d, 1e-12), none = hn::Inf(d);
  for (std::size_t p = 0; p < count; ++p) {
    const Vec3 &x = points[p].position, &n = points[p].normal;
    const V px = hn::Set(d, x.x), py = hn::Set(d, x.y), pz = hn::Set(d, x.z);
    const V qx = hn::Set(d, n.x), qy = hn::Set(d, n.y), qz = hn::Set(d, n.z);
    V bounds = none;
    std::size_t k = 0;
    for (; k + lanes <= size; k += lanes) {
      const V nx = hn::LoadU(d, planes.nx.data() + k), ny = hn::LoadU(d, planes.ny.data() + k),
              nz = hn::LoadU(d, planes.nz.data() + k);
      const V closing = one - (nx * qx + ny * qy + nz * qz);
      const V reach = hn::LoadU(d, planes.offset.data() + k) - (nx * px + ny * py + nz * pz);
      const V room = hn::IfThenElse(hn::Lt(zero, reach), reach, zero);  // std::max(0.0, reach)
      const auto faces = hn::Gt(closing, parallel);  // not its own plane, nor one parallel to it
      const V bound = hn::IfThenElse(faces, room / hn::IfThenElse(faces, closing, one), none);
      bounds = hn::IfThenElse(hn::Lt(bound, bounds), bound, bounds);
    }
    // The lanes' minimum is exact: the bounds are +0, positive or +inf, never NaN.
    double radius = hn::GetLane(hn::MinOfLanes(d, bounds));
    for (; k < size; ++k) {  // the planes after the last whole vector, each as one lane above
      const double closing = 1.0 - (planes.nx[k] * n.x + planes.ny[k] * n.y + planes.nz[k] * n.z);
      const double reach = planes.offset[k] - (planes.nx[k] * x.x + planes.ny[k] * x.y + planes.nz[k] * x.z);
      if (closing > 1e-12) radius = std::min(radius, std::max(0.0, reach) / closing);
    }
    radii[p] = radius;
  }
}

}  // namespace aggpack::grains_internal::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include <stdexcept>

#include "core/highway_target.hpp"

namespace aggpack::grains_internal {

HWY_EXPORT(TangentRadii);

void PlaneColumns::add(const Vec3& normal, double plane_offset) {
  nx.push_back(normal.x), ny.push_back(normal.y), nz.push_back(normal.z), offset.push_back(plane_offset);
}

std::vector<double> tangent_radii(const PlaneColumns& planes, std::span<const SurfacePoint> points) {
  const std::size_t size = planes.offset.size();
  if (planes.nx.size() != size || planes.ny.size() != size || planes.nz.size() != size)
    throw std::invalid_argument("tangent_radii: the planes' columns differ in length");
  std::vector<double> radii(points.size());
  HWY_DYNAMIC_DISPATCH(TangentRadii)(planes, points.data(), points.size(), radii.data());
  return radii;
}

std::vector<std::string> tangent_radii_targets() { return highway::target_names(); }

std::vector<double> tangent_radii_on(const std::string& target, const PlaneColumns& planes,
                                     std::span<const SurfacePoint> points) {
  return highway::on_target(target, "tangent_radii_on", [&] { return tangent_radii(planes, points); });
}

}  // namespace aggpack::grains_internal
#endif  // HWY_ONCE
