// tangent_radii over Highway vectors, compiled for every target of Highway's list and
// dispatched at run time. Each lane mirrors the scalar bound of one plane (see the header),
// and the module is compiled without contracting products into FMAs, so every target gives
// the same bits.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "tangent_radii.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <algorithm>

#include "tangent_radii.hpp"

HWY_BEFORE_NAMESPACE();
namespace aggpack::grains_internal::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
static_assert(HWY_MAX_BYTES / sizeof(double) <= PlaneColumns::kPadding, "a vector must fit in the planes' padding");

void TangentRadii(const PlaneColumns& planes, const SurfacePoint* points, std::size_t count, double* radii) {
  const hn::ScalableTag<double> d;
  using V = hn::Vec<decltype(d)>;
  const std::size_t lanes = hn::Lanes(d), size = planes.offset.size();
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0), parallel = hn::Set(d, 1e-12), none = hn::Inf(d);
  for (std::size_t p = 0; p < count; ++p) {
    const Vec3 &x = points[p].position, &n = points[p].normal;
    const V px = hn::Set(d, x.x), py = hn::Set(d, x.y), pz = hn::Set(d, x.z);
    const V qx = hn::Set(d, n.x), qy = hn::Set(d, n.y), qz = hn::Set(d, n.z);
    V radius = none;
    for (std::size_t k = 0; k < size; k += lanes) {
      const V nx = hn::LoadU(d, planes.nx.data() + k), ny = hn::LoadU(d, planes.ny.data() + k),
              nz = hn::LoadU(d, planes.nz.data() + k);
      const V closing = one - (nx * qx + ny * qy + nz * qz);
      const V reach = hn::LoadU(d, planes.offset.data() + k) - (nx * px + ny * py + nz * pz);
      const V room = hn::IfThenElse(hn::Lt(zero, reach), reach, zero);  // std::max(0.0, reach)
      const auto bounds = hn::Gt(closing, parallel);  // not its own plane, nor one parallel to it
      const V bound = hn::IfThenElse(bounds, room / hn::IfThenElse(bounds, closing, one), none);
      radius = hn::IfThenElse(hn::Lt(bound, radius), bound, radius);
    }
    double lane[HWY_MAX_BYTES / sizeof(double)];
    hn::StoreU(radius, d, lane);
    radii[p] = *std::min_element(lane, lane + lanes);
  }
}

}  // namespace aggpack::grains_internal::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include <limits>
#include <stdexcept>

namespace aggpack::grains_internal {

HWY_EXPORT(TangentRadii);

void PlaneColumns::add(const Vec3& normal, double plane_offset) {
  nx.push_back(normal.x), ny.push_back(normal.y), nz.push_back(normal.z), offset.push_back(plane_offset);
}

void PlaneColumns::pad() {
  while (offset.size() % kPadding != 0) add(Vec3{}, std::numeric_limits<double>::infinity());
}

std::vector<double> tangent_radii(const PlaneColumns& planes, std::span<const SurfacePoint> points) {
  std::vector<double> radii(points.size());
  HWY_DYNAMIC_DISPATCH(TangentRadii)(planes, points.data(), points.size(), radii.data());
  return radii;
}

std::vector<std::string> tangent_radii_targets() {
  std::vector<std::string> names;
  for (const std::int64_t target : hwy::SupportedAndGeneratedTargets()) names.emplace_back(hwy::TargetName(target));
  return names;
}

std::vector<double> tangent_radii_on(const std::string& target, const PlaneColumns& planes,
                                     std::span<const SurfacePoint> points) {
  for (const std::int64_t t : hwy::SupportedAndGeneratedTargets()) {
    if (target != hwy::TargetName(t)) continue;
    hwy::SetSupportedTargetsForTest(t);
    std::vector<double> radii = tangent_radii(planes, points);
    hwy::SetSupportedTargetsForTest(0);
    return radii;
  }
  throw std::invalid_argument("tangent_radii_on: " + target + " is not a target of this machine");
}

}  // namespace aggpack::grains_internal
#endif  // HWY_ONCE
