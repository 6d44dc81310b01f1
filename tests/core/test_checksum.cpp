// The checkpoint's checksum is XXH64 (seed 0): the reference implementation's values, and the
// same value whatever pieces the bytes come in (a section is streamed into its file).
#include <gtest/gtest.h>

#include <string>

#include "core/checksum.hpp"

namespace {

TEST(Checksum, IsXxh64) {
  EXPECT_EQ(aggpack::checksum(""), 0xEF46DB3751D8E999ull);
  EXPECT_EQ(aggpack::checksum("a"), 0xD24EC4F1A98C6E5Bull);
  EXPECT_EQ(aggpack::checksum("abc"), 0x44BC2CF5AD770999ull);
  EXPECT_EQ(aggpack::checksum("Nobody inspects the spammish repetition"), 0xFBCEA83C8A378BF1ull);
}

TEST(Checksum, TakesItsBytesInPiecesOfAnySize) {
  std::string bytes;
  for (int i = 0; i < 1000; ++i) bytes += static_cast<char>(i * 7 + 3);
  const std::uint64_t whole = aggpack::checksum(bytes);
  for (const std::size_t piece : {1u, 3u, 31u, 32u, 33u, 100u, 999u}) {
    aggpack::Checksum sum;
    for (std::size_t at = 0; at < bytes.size(); at += piece) sum.add(std::string_view(bytes).substr(at, piece));
    EXPECT_EQ(sum.value(), whole) << piece;
  }
  std::string changed = bytes;
  changed[500] = static_cast<char>(changed[500] ^ 1);
  EXPECT_NE(aggpack::checksum(changed), whole);
}

}  // namespace
