#include <gtest/gtest.h>
#include <zlib.h>

#include "aggpack/report/image.hpp"

namespace aggpack {
namespace {

std::uint32_t read_u32(const std::string& s, std::size_t at) {
  std::uint32_t v = 0;
  for (int k = 0; k < 4; ++k) v = (v << 8) | static_cast<unsigned char>(s[at + static_cast<std::size_t>(k)]);
  return v;
}

TEST(Png, HeaderChunksAndPixelsRoundTrip) {
  Image image(3, 2, {255, 255, 255});
  image.set(0, 0, {10, 20, 30});
  image.set(2, 1, {200, 100, 50});
  const std::string png = encode_png(image);
  ASSERT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_EQ(png.substr(12, 4), "IHDR");
  EXPECT_EQ(read_u32(png, 16), 3u);
  EXPECT_EQ(read_u32(png, 20), 2u);
  EXPECT_EQ(png[24], 8);  // bit depth
  EXPECT_EQ(png[25], 2);  // RGB
  // IHDR's CRC covers type and data.
  EXPECT_EQ(read_u32(png, 29), crc32(0L, reinterpret_cast<const Bytef*>(png.data() + 12), 17));
  const std::size_t idat_length = read_u32(png, 33);
  ASSERT_EQ(png.substr(37, 4), "IDAT");
  std::string raw(2 * (1 + 3 * 3), '\0');
  uLongf raw_size = raw.size();
  ASSERT_EQ(uncompress(reinterpret_cast<Bytef*>(raw.data()), &raw_size,
                       reinterpret_cast<const Bytef*>(png.data() + 41), idat_length),
            Z_OK);
  ASSERT_EQ(raw_size, raw.size());
  EXPECT_EQ(raw[0], 0);  // filter "none"
  EXPECT_EQ(static_cast<unsigned char>(raw[1]), 10);
  EXPECT_EQ(static_cast<unsigned char>(raw[3]), 30);
  EXPECT_EQ(static_cast<unsigned char>(raw[4]), 255);
  EXPECT_EQ(static_cast<unsigned char>(raw[10 + 1 + 6]), 200);
  EXPECT_EQ(static_cast<unsigned char>(raw[10 + 1 + 8]), 50);
  EXPECT_EQ(png.substr(png.size() - 8, 4), "IEND");
}

TEST(Viridis, EndsAndClamping) {
  EXPECT_EQ(viridis(0.0), (Rgb{68, 1, 84}));
  EXPECT_EQ(viridis(1.0), (Rgb{253, 231, 37}));
  EXPECT_EQ(viridis(-3.0), viridis(0.0));
  EXPECT_EQ(viridis(7.0), viridis(1.0));
  EXPECT_EQ(viridis(0.5), (Rgb{33, 144, 141}));  // the middle sample
}

}  // namespace
}  // namespace aggpack
