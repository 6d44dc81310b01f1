#include "aggpack/report/render.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace aggpack {

namespace {
constexpr int kMarginPixels = 8;
}

Camera::Camera(const Box& frame, const RenderOptions& options) : width_(options.width) {
  const double az = options.azimuth_deg * std::numbers::pi / 180.0, el = options.elevation_deg * std::numbers::pi / 180.0;
  forward_ = -Vec3{std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
  right_ = normalized(cross(forward_, Vec3{0, 0, 1}));
  up_ = cross(right_, forward_);
  double u_lo = std::numeric_limits<double>::infinity(), u_hi = -u_lo, v_lo = u_lo, v_hi = -u_lo;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 c{corner & 1 ? frame.hi.x : frame.lo.x, corner & 2 ? frame.hi.y : frame.lo.y,
                 corner & 4 ? frame.hi.z : frame.lo.z};
    u_lo = std::min(u_lo, dot(c, right_));
    u_hi = std::max(u_hi, dot(c, right_));
    v_lo = std::min(v_lo, dot(c, up_));
    v_hi = std::max(v_hi, dot(c, up_));
  }
  const int inner = std::max(1, width_ - 2 * kMarginPixels);
  scale_ = inner / std::max(u_hi - u_lo, 1e-300);
  height_ = static_cast<int>(std::ceil((v_hi - v_lo) * scale_)) + 2 * kMarginPixels;
  u0_ = u_lo - kMarginPixels / scale_;
  v0_ = v_hi + kMarginPixels / scale_;
}

Camera::Projection Camera::project(const Vec3& p) const {
  return {(dot(p, right_) - u0_) * scale_, (v0_ - dot(p, up_)) * scale_, dot(p, forward_)};
}

Image render_spheres(const ParticleStore& particles, const Box& frame, const RenderOptions& options) {
  const Camera camera(frame, options);
  Image image(camera.width(), camera.height(), options.background);
  double d_lo = options.d_lo, d_hi = options.d_hi;
  if (d_lo <= 0.0 && d_hi <= 0.0 && particles.size() > 0) {
    const auto [lo, hi] = std::minmax_element(particles.radius.begin(), particles.radius.end());
    d_lo = 2.0 * *lo;
    d_hi = 2.0 * *hi;
  }
  // Light from the upper left, slightly towards the viewer (camera coordinates: right, up, forward).
  const Vec3 light = normalized(Vec3{-0.45, 0.65, -0.6});
  std::vector<double> depth(static_cast<std::size_t>(camera.width()) * static_cast<std::size_t>(camera.height()),
                            std::numeric_limits<double>::infinity());
  const double scale = camera.pixels_per_metre();
  // The section plane: vertical, through the frame's centre, facing the camera.
  const Vec3 centre = 0.5 * (frame.lo + frame.hi);
  const Vec3 towards_camera = normalized(Vec3{-camera.forward().x, -camera.forward().y, 0.0});
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (options.cut_away && dot(particles.position[i] - centre, towards_camera) > 0.0) continue;
    const double r = particles.radius[i];
    const Camera::Projection c = camera.project(particles.position[i]);
    const double t = d_hi > d_lo ? (2.0 * r - d_lo) / (d_hi - d_lo) : 0.5;
    const Rgb base = viridis(t);
    const double r_px = r * scale;
    const int x0 = std::max(0, static_cast<int>(std::floor(c.column - r_px)));
    const int x1 = std::min(camera.width() - 1, static_cast<int>(std::ceil(c.column + r_px)));
    const int y0 = std::max(0, static_cast<int>(std::floor(c.row - r_px)));
    const int y1 = std::min(camera.height() - 1, static_cast<int>(std::ceil(c.row + r_px)));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const double du = (x + 0.5 - c.column) / scale, dv = (c.row - (y + 0.5)) / scale;
        const double q = r * r - du * du - dv * dv;
        if (q < 0.0) continue;
        const double h = std::sqrt(q);
        double& z = depth[static_cast<std::size_t>(y) * static_cast<std::size_t>(camera.width()) +
                          static_cast<std::size_t>(x)];
        if (c.depth - h >= z) continue;
        z = c.depth - h;
        const Vec3 normal{du / r, dv / r, -h / r};
        const double shade = 0.3 + 0.7 * std::max(0.0, dot(normal, light));
        const auto lit = [&](std::uint8_t channel) {
          return static_cast<std::uint8_t>(std::lround(std::min(255.0, channel * shade)));
        };
        image.set(x, y, {lit(base.r), lit(base.g), lit(base.b)});
      }
  }
  return image;
}

}  // namespace aggpack
