#pragma once
#include <string_view>

#include "aggpack/report/image.hpp"

namespace aggpack {

// Text drawn into a raster with a 5 x 7 pixel font, for the labels a picture must carry on
// its own (the colour bar's diameters, the scale bar's length). It has the digits, '.', '-',
// ' ' and the letters a c d e i l m n o r s t u x; any other character is a programming
// error (std::invalid_argument).
struct TextStyle {
  int scale = 2;  // pixels per font pixel
  Rgb colour{0, 0, 0};
};
// Width in pixels of `text` (one font pixel between letters).
[[nodiscard]] int text_width(std::string_view text, const TextStyle& style);
[[nodiscard]] inline int text_height(const TextStyle& style) { return 7 * style.scale; }
// Draws `text` with its top-left corner at (x, y); pixels off the image are skipped.
void draw_text(Image& image, int x, int y, std::string_view text, const TextStyle& style);

}  // namespace aggpack
