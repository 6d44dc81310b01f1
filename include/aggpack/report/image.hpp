#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace aggpack {

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
  friend bool operator==(const Rgb&, const Rgb&) = default;
};

// An 8-bit RGB raster, row 0 at the top.
class Image {
 public:
  Image(int width, int height, Rgb background);
  [[nodiscard]] int width() const { return width_; }
  [[nodiscard]] int height() const { return height_; }
  [[nodiscard]] Rgb at(int x, int y) const;
  void set(int x, int y, Rgb colour);
  [[nodiscard]] const std::vector<std::uint8_t>& bytes() const { return rgb_; }

 private:
  int width_, height_;
  std::vector<std::uint8_t> rgb_;
};

// The image as a PNG file (8-bit RGB, zlib-compressed).
std::string encode_png(const Image& image);

// The viridis colour map at t in [0, 1] (clamped): dark blue to yellow, readable in grey and
// by colour-blind readers.
Rgb viridis(double t);

}  // namespace aggpack
