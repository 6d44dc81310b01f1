#include "aggpack/report/render.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <vector>

#include <fmt/format.h>

#include "aggpack/report/bitmap_text.hpp"

namespace aggpack {

namespace {
constexpr int kMarginPixels = 8;
}

std::optional<SectionPlane> section_plane(const Box& frame, const Vec3& camera_forward) {
  const Vec3 horizontal{-camera_forward.x, -camera_forward.y, 0.0};
  if (!(dot(horizontal, horizontal) > 1e-24)) return std::nullopt;  // looking straight down: no vertical plane faces it
  return SectionPlane{0.5 * (frame.lo + frame.hi), normalized(horizontal)};
}

Camera::Camera(const Box& frame, const RenderOptions& options) : width_(options.width) {
  const double az = options.azimuth_deg * std::numbers::pi / 180.0, el = options.elevation_deg * std::numbers::pi / 180.0;
  forward_ = -Vec3{std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
  right_ = normalized(cross(forward_, Vec3{0, 0, 1}));
  up_ = cross(right_, forward_);
  // What is framed: the box, or for a section the half of it behind the section plane (its
  // corners there and where its edges cross the plane; the whole box left an empty band
  // below the picture, where the front half was cut away).
  const auto corner_of = [&](int k) {
    return Vec3{k & 1 ? frame.hi.x : frame.lo.x, k & 2 ? frame.hi.y : frame.lo.y, k & 4 ? frame.hi.z : frame.lo.z};
  };
  const std::optional<SectionPlane> section = options.cut_away ? section_plane(frame, forward_) : std::nullopt;
  std::vector<Vec3> framed;
  for (int k = 0; k < 8; ++k)
    if (!section || !section->removes(corner_of(k))) framed.push_back(corner_of(k));
  if (section)
    for (int k = 0; k < 8; ++k)
      for (const int axis : {1, 2, 4})
        if (!(k & axis)) {  // each edge once: from corner k to the corner one step along `axis`
          const Vec3 a = corner_of(k), b = corner_of(k | axis);
          const double da = section->signed_distance(a), db = section->signed_distance(b);
          if ((da > 0.0) != (db > 0.0)) framed.push_back(a + (da / (da - db)) * (b - a));
        }
  double u_lo = std::numeric_limits<double>::infinity(), u_hi = -u_lo, v_lo = u_lo, v_hi = -u_lo;
  for (const Vec3& c : framed) {
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

namespace {
// What colours sphere i and where a section cuts it: a sphere its own diameter and centre; a
// grain's sphere its grain's (the diameter of the grain's volume, its centre of mass), so a
// grain shows in one colour and a section takes it away whole.
double colour_diameter(const ParticleStore& particles, std::size_t i) {
  if (particles.body.empty() || particles.body[i] == kNoBody) return 2.0 * particles.radius[i];
  return std::cbrt(6.0 * particles.bodies.volume[particles.body[i]] / std::numbers::pi);
}
const Vec3& section_point(const ParticleStore& particles, std::size_t i) {
  if (particles.body.empty() || particles.body[i] == kNoBody) return particles.position[i];
  return particles.bodies.position[particles.body[i]];
}

// The picture at options.width (times the supersampling factor), without a legend.
Image ray_cast(const ParticleStore& particles, const Box& frame, const RenderOptions& options, double d_lo,
               double d_hi) {
  const Camera camera(frame, options);
  Image image(camera.width(), camera.height(), options.background);
  // Light from the upper left, slightly towards the viewer (camera coordinates: right, up, forward).
  const Vec3 light = normalized(Vec3{-0.45, 0.65, -0.6});
  std::vector<double> depth(static_cast<std::size_t>(camera.width()) * static_cast<std::size_t>(camera.height()),
                            std::numeric_limits<double>::infinity());
  const double scale = camera.pixels_per_metre();
  const std::optional<SectionPlane> section = options.cut_away ? section_plane(frame, camera.forward()) : std::nullopt;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (section && section->removes(section_point(particles, i))) continue;
    const double r = particles.radius[i];
    const Camera::Projection c = camera.project(particles.position[i]);
    const Rgb base = viridis(colour_position(colour_diameter(particles, i), d_lo, d_hi, options.log_colour));
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


// Each n x n block of `fine` averaged into one pixel.
Image downsampled(const Image& fine, int n) {
  Image coarse(fine.width() / n, fine.height() / n, Rgb{});
  for (int y = 0; y < coarse.height(); ++y)
    for (int x = 0; x < coarse.width(); ++x) {
      int r = 0, g = 0, b = 0;
      for (int dy = 0; dy < n; ++dy)
        for (int dx = 0; dx < n; ++dx) {
          const Rgb c = fine.at(x * n + dx, y * n + dy);
          r += c.r, g += c.g, b += c.b;
        }
      const int count = n * n;
      coarse.set(x, y, {static_cast<std::uint8_t>((r + count / 2) / count), static_cast<std::uint8_t>((g + count / 2) / count),
                        static_cast<std::uint8_t>((b + count / 2) / count)});
    }
  return coarse;
}

std::string millimetres(double metres) {
  const double mm = 1e3 * metres;
  return mm >= 100 ? fmt::format("{:.0f} mm", mm) : fmt::format("{:.3g} mm", mm);
}
}  // namespace

double colour_position(double d, double d_lo, double d_hi, bool log_colour) {
  if (!(d_hi > d_lo)) return 0.5;
  const double t = log_colour && d_lo > 0.0 ? std::log(d / d_lo) / std::log(d_hi / d_lo) : (d - d_lo) / (d_hi - d_lo);
  return std::clamp(t, 0.0, 1.0);
}

Image render_spheres(const ParticleStore& particles, const Box& frame, const RenderOptions& options) {
  double d_lo = options.d_lo, d_hi = options.d_hi;
  if (d_lo <= 0.0 && d_hi <= 0.0 && particles.size() > 0) {
    d_lo = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < particles.size(); ++i) {
      d_lo = std::min(d_lo, colour_diameter(particles, i));
      d_hi = std::max(d_hi, colour_diameter(particles, i));
    }
  }
  const int n = std::max(1, options.supersample);
  RenderOptions fine = options;
  fine.width = options.width * n;
  Image picture = ray_cast(particles, frame, fine, d_lo, d_hi);
  if (n > 1) picture = downsampled(picture, n);
  if (!options.legend) return picture;
  return add_legend(picture, d_lo, d_hi, Camera(frame, fine).pixels_per_metre() / n, options.log_colour);
}

double scale_bar_length(int width, double pixels_per_metre) {
  const double target = 0.2 * width / pixels_per_metre;
  const double decade = std::pow(10.0, std::floor(std::log10(target)));
  double length = decade;
  for (const double m : {2.0, 5.0})
    if (m * decade <= target) length = m * decade;
  return length;
}

Image add_legend(const Image& picture, double d_lo, double d_hi, double pixels_per_metre, bool log_colour) {
  constexpr int kMargin = 8, kBarHeight = 12, kBarWidth = 200;
  Image out(picture.width(), picture.height() + kLegendHeight, Rgb{255, 255, 255});
  for (int y = 0; y < picture.height(); ++y)
    for (int x = 0; x < picture.width(); ++x) out.set(x, y, picture.at(x, y));
  const TextStyle text;
  const int top = picture.height() + 6, label_top = top + kBarHeight + 4;
  // Colour bar: "diameter", then viridis from d_lo to d_hi with both ends labelled.
  draw_text(out, kMargin, top, "diameter", text);
  const int bar_left = kMargin + text_width("diameter", text) + kMargin;
  for (int x = 0; x < kBarWidth; ++x)
    for (int y = 0; y < kBarHeight; ++y) out.set(bar_left + x, top + y, viridis(x / (kBarWidth - 1.0)));
  draw_text(out, bar_left, label_top, millimetres(d_lo), text);
  const std::string hi = millimetres(d_hi);
  draw_text(out, bar_left + kBarWidth - text_width(hi, text), label_top, hi, text);
  if (log_colour) draw_text(out, bar_left + kBarWidth + kMargin, top, "log", text);  // the bar's scale
  // Scale bar at the right: a black bar with end ticks, its length below it.
  const double length = scale_bar_length(picture.width(), pixels_per_metre);
  const int bar_px = static_cast<int>(std::lround(length * pixels_per_metre));
  const int right = picture.width() - kMargin, left = right - bar_px;
  for (int x = left; x < right; ++x)
    for (int y = top + kBarHeight / 2 - 1; y <= top + kBarHeight / 2 + 1; ++y) out.set(x, y, {0, 0, 0});
  for (const int x : {left, right - 1})
    for (int y = top; y < top + kBarHeight; ++y) out.set(x, y, {0, 0, 0});
  const std::string label = fmt::format("{:g} mm", 1e3 * length);
  draw_text(out, right - text_width(label, text), label_top, label, text);
  return out;
}

}  // namespace aggpack
