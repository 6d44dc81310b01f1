#pragma once
#include <optional>

#include "aggpack/core/box.hpp"
#include "aggpack/core/particle_store.hpp"
#include "aggpack/report/image.hpp"

namespace aggpack {

struct RenderOptions {
  int width = 720;               // pixels; the height follows from the view
  double azimuth_deg = -60.0;    // camera direction about the vertical, from +x
  double elevation_deg = 25.0;   // camera above the horizontal
  double d_lo = 0.0, d_hi = 0.0; // diameters mapped to the ends of the colour map (0, 0: the bed's own range)
  Rgb background{255, 255, 255};
  bool cut_away = false;         // leave out spheres centred nearer than the frame's vertical mid-plane: a section
  int supersample = 1;           // n x n rays per pixel, averaged: spheres a few pixels wide stay round
  bool legend = false;           // a strip below the picture: the diameter colour bar and a scale bar
  // Colour by log(d) instead of d: a grading from 1 to 25 mm on a linear scale paints all the
  // sand one colour.
  bool log_colour = false;
};

// Where a diameter d falls on the colour map, 0 at d_lo to 1 at d_hi (0.5 when they are equal).
[[nodiscard]] double colour_position(double d, double d_lo, double d_hi, bool log_colour);

// A section's plane: vertical, through the frame's centre, facing the camera; the spheres
// centred on the camera's side of it are cut away.
struct SectionPlane {
  Vec3 centre, towards_camera;  // a point of the plane; its unit normal, horizontal
  [[nodiscard]] double signed_distance(const Vec3& p) const { return dot(p - centre, towards_camera); }
  [[nodiscard]] bool removes(const Vec3& p) const { return signed_distance(p) > 0.0; }
};
// None when the camera looks straight down (no vertical plane faces it).
[[nodiscard]] std::optional<SectionPlane> section_plane(const Box& frame, const Vec3& camera_forward);

// An orthographic camera framing a box: world point -> pixel column, row and depth.
class Camera {
 public:
  Camera(const Box& frame, const RenderOptions& options);
  struct Projection {
    double column, row, depth;  // pixels from the left and from the top; metres away from the viewer
  };
  [[nodiscard]] Projection project(const Vec3& p) const;
  [[nodiscard]] double pixels_per_metre() const { return scale_; }
  [[nodiscard]] int width() const { return width_; }
  [[nodiscard]] int height() const { return height_; }
  [[nodiscard]] Vec3 right() const { return right_; }
  [[nodiscard]] Vec3 up() const { return up_; }
  [[nodiscard]] Vec3 forward() const { return forward_; }

 private:
  Vec3 right_, up_, forward_;
  double scale_ = 1.0, u0_ = 0.0, v0_ = 0.0;
  int width_ = 1, height_ = 1;
};

// Spheres ray-cast exactly (depth-buffered, Lambert-shaded), coloured by diameter with
// viridis, seen by a camera framing `frame` (usually the container). A grain's spheres take
// its colour (the diameter of its volume) and a section cuts it away whole (by its centre of
// mass). With `legend`, the image is taller by kLegendHeight: see add_legend.
Image render_spheres(const ParticleStore& particles, const Box& frame, const RenderOptions& options);

// The strip add_legend puts below a picture, in pixels.
inline constexpr int kLegendHeight = 44;
// A copy of `picture` with a white strip below it holding the colour bar (viridis from d_lo
// to d_hi, labelled in mm) on the left and, on the right, a bar of a round length (1, 2 or
// 5 x 10^k mm, about a fifth of the width) at `pixels_per_metre`: the camera is
// orthographic, so the bar holds for any length in the picture plane.
Image add_legend(const Image& picture, double d_lo, double d_hi, double pixels_per_metre, bool log_colour = false);
// The scale bar's length for a picture `width` pixels wide, m.
[[nodiscard]] double scale_bar_length(int width, double pixels_per_metre);

}  // namespace aggpack
