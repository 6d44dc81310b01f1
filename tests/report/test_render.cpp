#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "aggpack/report/render.hpp"

namespace aggpack {
namespace {

TEST(Render, OneSphereCoversExactlyItsDisc) {
  const Box frame{{0, 0, 0}, {1, 1, 1}};
  ParticleStore particles;
  const Vec3 centre{0.5, 0.5, 0.5};
  const double r = 0.2;
  particles.add(centre, r, 1000.0);
  RenderOptions options;
  options.width = 400;
  const Image image = render_spheres(particles, frame, options);
  const Camera camera(frame, options);
  const auto c = camera.project(centre);
  const double r_px = r * camera.pixels_per_metre();
  const auto pixel = [&](double dx, double dy) {
    return image.at(static_cast<int>(std::floor(c.column + dx)), static_cast<int>(std::floor(c.row + dy)));
  };
  const Rgb white{255, 255, 255};
  EXPECT_NE(pixel(0, 0), white);
  for (const double angle : {0.0, 1.0, 2.0, 3.0, 4.0, 5.0}) {
    const double dx = std::cos(angle), dy = std::sin(angle);
    EXPECT_NE(pixel(0.93 * r_px * dx, 0.93 * r_px * dy), white) << angle;
    EXPECT_EQ(pixel(1.07 * r_px * dx, 1.07 * r_px * dy), white) << angle;
  }
  // One size: the middle of the colour map, brightest towards the light (upper left).
  const Rgb upper_left = pixel(-0.5 * r_px, -0.6 * r_px), lower_right = pixel(0.5 * r_px, 0.6 * r_px);
  EXPECT_GT(upper_left.g, lower_right.g);
  EXPECT_EQ(image.at(1, 1), white);
}

TEST(Render, NearerSphereHidesFartherOne) {
  const Box frame{{0, 0, 0}, {1, 1, 1}};
  RenderOptions options;
  options.width = 300;
  const Camera camera(frame, options);
  ParticleStore particles;
  const Vec3 middle{0.5, 0.5, 0.5};
  particles.add(middle + 0.3 * camera.forward(), 0.1, 1000.0);   // far, large: yellow end
  particles.add(middle - 0.3 * camera.forward(), 0.05, 1000.0);  // near, small: blue end
  const Image image = render_spheres(particles, frame, options);
  const auto c = camera.project(middle);
  const Rgb seen = image.at(static_cast<int>(c.column), static_cast<int>(c.row));
  EXPECT_LT(seen.r, seen.b);  // the blue (small, near) sphere is in front
  const double r_px = 0.1 * camera.pixels_per_metre();
  const Rgb rim = image.at(static_cast<int>(c.column + 0.8 * r_px), static_cast<int>(c.row));
  EXPECT_GT(rim.r, rim.b);  // outside the small disc the large yellow sphere shows
}

TEST(Render, CutAwayShowsTheSectionBehindTheFrontHalf) {
  const Box frame{{0, 0, 0}, {1, 1, 1}};
  RenderOptions options;
  options.width = 300;
  options.elevation_deg = 0.0;
  options.azimuth_deg = -90.0;  // camera on the -y side, looking along +y
  ParticleStore particles;
  particles.add({0.5, 0.3, 0.5}, 0.05, 1000.0);   // front half: small, blue end of the map
  particles.add({0.5, 0.7, 0.5}, 0.1, 1000.0);    // back half: large, yellow end
  const Camera camera(frame, options);
  const auto c = camera.project({0.5, 0.5, 0.5});
  const auto seen = [&](bool cut) {
    options.cut_away = cut;
    return render_spheres(particles, frame, options).at(static_cast<int>(c.column), static_cast<int>(c.row));
  };
  EXPECT_LT(seen(false).r, seen(false).b);  // the front sphere hides the back one
  EXPECT_GT(seen(true).r, seen(true).b);    // cut away: the back sphere shows
}

// A grain shows in its grain's colour (the diameter of its volume), not its spheres' own, and
// a section takes it whole: its centre of mass behind the plane keeps its sphere in front of
// the plane, which hides a small sphere behind it.
TEST(Render, AGrainIsOneColourAndASectionCutsItWhole) {
  const Box frame{{0, 0, 0}, {1, 1, 1}};
  RenderOptions options;
  options.width = 300;
  options.elevation_deg = 0.0;
  options.azimuth_deg = -90.0;  // camera on the -y side, looking along +y; the section plane y = 0.5
  const std::vector<Vec3> centres{{-0.15, 0.0, 0.0}, {0.15, 0.0, 0.0}};
  const std::vector<double> radii{0.05, 0.1};
  // Its volume: that of a sphere of diameter 0.15, halfway along the colour map's 0.1 to 0.2.
  const double d = 0.15, volume = std::numbers::pi / 6.0 * d * d * d;
  const RigidBodyShape shape{centres, radii, volume, {1e-3, 2e-3, 2e-3}, 1.0, 0};
  ParticleStore particles;
  particles.add({0.1, 0.5, 0.9}, 0.05, 1000.0);  // d 0.1: the blue end
  particles.add({0.9, 0.5, 0.9}, 0.1, 1000.0);   // d 0.2: the yellow end
  // Turned 45 degrees about z: its large sphere at (0.606, 0.414), in front of the plane; its
  // centre of mass at y = 0.52, behind it.
  particles.add_body({0.5, 0.52, 0.5}, axis_angle({0, 0, 1}, -std::numbers::pi / 4.0), shape, 1000.0);
  const Vec3 front = particles.position[3];
  particles.add({front.x, 0.85, 0.5}, 0.05, 1000.0);  // blue, behind the grain's front sphere
  const Camera camera(frame, options);
  const auto seen = [&](bool cut) {
    options.cut_away = cut;
    const auto c = camera.project(front);
    return render_spheres(particles, frame, options).at(static_cast<int>(c.column), static_cast<int>(c.row));
  };
  const Rgb grain = seen(false);
  const Rgb middle = viridis(0.5);  // shading scales the three channels alike
  EXPECT_NEAR(static_cast<double>(grain.g) / grain.b, static_cast<double>(middle.g) / middle.b, 0.05);
  EXPECT_EQ(seen(true), grain);  // not the blue sphere behind it
}

// A section frames the half of the box that is left: the whole box left an empty band below
// the Table 2 picture, where the front half had been cut away.
TEST(Render, ASectionFillsItsPictureToTheBottom) {
  const Box frame{{0, 0, 0}, {1, 1, 1}};
  ParticleStore bed;  // a simple cubic lattice filling the box
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j)
      for (int k = 0; k < 10; ++k) bed.add({0.05 + 0.1 * i, 0.05 + 0.1 * j, 0.05 + 0.1 * k}, 0.05, 1000.0);
  RenderOptions options;  // the report's view: azimuth -60, elevation 25
  options.width = 400;
  options.cut_away = true;
  const Image picture = render_spheres(bed, frame, options);
  const auto row_is_empty = [&](int y) {
    for (int x = 0; x < picture.width(); ++x)
      if (picture.at(x, y).r != 255 || picture.at(x, y).g != 255 || picture.at(x, y).b != 255) return false;
    return true;
  };
  int lowest = picture.height() - 1;
  while (lowest > 0 && row_is_empty(lowest)) --lowest;
  int highest = 0;
  while (highest < picture.height() - 1 && row_is_empty(highest)) ++highest;
  // The bed reaches the margins (8 px) at the top and the bottom alike, but for the rim of a
  // sphere (14 px here); the whole box's framing left some 80 px empty below.
  EXPECT_GE(lowest, picture.height() - 1 - 8 - 20) << picture.height();
  EXPECT_LE(highest, 8 + 20) << picture.height();
}

// Table 2's picture painted all the sand one colour on a linear scale of 1 to 25 mm: on a log
// scale the middle of the map is the geometric mean, and the legend says "log".
TEST(Render, ALogColourScaleSeparatesTheSmallSizes) {
  EXPECT_DOUBLE_EQ(colour_position(5e-3, 1e-3, 25e-3, true), 0.5);
  EXPECT_NEAR(colour_position(2e-3, 1e-3, 25e-3, false), 1.0 / 24.0, 1e-12);
  EXPECT_GT(colour_position(2e-3, 1e-3, 25e-3, true), 0.2);
  EXPECT_EQ(colour_position(1e-3, 1e-3, 1e-3, true), 0.5);
  ParticleStore bed;
  bed.add({0.5, 0.5, 0.5}, 0.001, 1000.0);
  bed.add({0.2, 0.5, 0.5}, 0.0125, 1000.0);
  RenderOptions options;
  options.legend = true;
  options.log_colour = true;
  const Image picture = render_spheres(bed, Box{{0, 0, 0}, {1, 1, 1}}, options);  // every label has its glyphs
  EXPECT_GT(picture.height(), kLegendHeight);
}

TEST(Render, FramesTheBoxWithItsAspect) {
  RenderOptions options;
  options.width = 500;
  options.elevation_deg = 0.0;
  options.azimuth_deg = -90.0;  // looking along +y: x to the right, z up
  const Camera camera(Box{{0, 0, 0}, {2, 1, 1}}, options);
  EXPECT_NEAR(camera.pixels_per_metre(), (500 - 16) / 2.0, 1e-9);
  EXPECT_NEAR(camera.height(), 500 / 2 + 8, 2);
  const auto lo = camera.project({0, 0, 0}), hi = camera.project({2, 0, 1});
  EXPECT_NEAR(lo.column, 8.0, 1e-9);
  EXPECT_NEAR(hi.column, 492.0, 1e-9);
  EXPECT_LT(hi.row, lo.row);  // up is up
}

// The report's pictures had no colour bar and no scale: the legend strip carries both.
TEST(Render, LegendHasTheColourBarAndAScaleBarOfTheRightLength) {
  const Box frame{{0, 0, 0}, {0.1, 0.1, 0.1}};
  ParticleStore particles;
  particles.add({0.05, 0.05, 0.05}, 0.01, 1000.0);
  particles.add({0.02, 0.05, 0.02}, 0.002, 1000.0);
  RenderOptions options;
  options.width = 400;
  options.legend = true;
  const Image with = render_spheres(particles, frame, options);
  options.legend = false;
  const Image without = render_spheres(particles, frame, options);
  ASSERT_EQ(with.height(), without.height() + kLegendHeight);
  ASSERT_EQ(with.width(), without.width());
  for (int y = 0; y < without.height(); y += 7)
    for (int x = 0; x < without.width(); x += 7) ASSERT_EQ(with.at(x, y), without.at(x, y));
  // The colour bar runs from viridis(0) at d_min to viridis(1) at d_max, one row of it:
  const int row = without.height() + 6 + 6;
  std::vector<int> bar;
  for (int x = 0; x < with.width(); ++x)
    if (with.at(x, row) == viridis(0.0) || with.at(x, row) == viridis(1.0)) bar.push_back(x);
  ASSERT_GE(bar.size(), 2u);
  EXPECT_EQ(with.at(bar.front(), row), viridis(0.0));
  EXPECT_EQ(with.at(bar.back(), row), viridis(1.0));
  EXPECT_EQ(bar.back() - bar.front(), 199);
  // The scale bar: black from its left tick to its right one, as long as its length in pixels.
  const Camera camera(frame, options);
  const double length = scale_bar_length(with.width(), camera.pixels_per_metre());
  EXPECT_DOUBLE_EQ(length, 0.02);  // a fifth of 0.14 m of view, rounded down to 1, 2 or 5 x 10^k
  int left = -1, right = -1;
  for (int x = with.width() / 2; x < with.width(); ++x)
    if (with.at(x, row) == Rgb{0, 0, 0}) {
      if (left < 0) left = x;
      right = x;
    }
  EXPECT_NEAR(right + 1 - left, length * camera.pixels_per_metre(), 1.0);
}

// A sphere a few pixels wide came out as aliased noise: with 3 x 3 rays per pixel its edge
// pixels are blends of it and the background, which one ray per pixel never gives.
TEST(Render, SupersamplingBlendsTheEdges) {
  const Box frame{{0, 0, 0}, {1, 1, 1}};
  ParticleStore particles;
  particles.add({0.5, 0.5, 0.5}, 0.01, 1000.0);  // about 2.5 px in radius at 200 px
  RenderOptions options;
  options.width = 200;
  // The sphere's own red channel is at most viridis(0.5).r = 33; a blend with white is brighter.
  const auto blends = [&](const Image& image) {
    std::size_t n = 0, touched = 0;
    for (int y = 0; y < image.height(); ++y)
      for (int x = 0; x < image.width(); ++x) {
        const Rgb c = image.at(x, y);
        touched += c != Rgb{255, 255, 255};
        n += c.r > 40 && c.r < 250;
      }
    return std::pair{n, touched};
  };
  const auto [single_blends, single_touched] = blends(render_spheres(particles, frame, options));
  options.supersample = 3;
  const auto [fine_blends, fine_touched] = blends(render_spheres(particles, frame, options));
  EXPECT_EQ(single_blends, 0u);
  EXPECT_GE(fine_blends, 8u);
  EXPECT_GE(fine_touched, single_touched);
  const double r_px = 0.01 * Camera(frame, options).pixels_per_metre();
  EXPECT_NEAR(static_cast<double>(single_touched), M_PI * r_px * r_px, 2.0 * 2.0 * M_PI * r_px);
}

}  // namespace
}  // namespace aggpack
