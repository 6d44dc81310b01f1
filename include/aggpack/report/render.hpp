#pragma once
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
};

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
// viridis, seen by a camera framing `frame` (usually the container).
Image render_spheres(const ParticleStore& particles, const Box& frame, const RenderOptions& options);

}  // namespace aggpack
