#include "aggpack/core/text.hpp"

#include <gtest/gtest.h>

namespace aggpack {
namespace {

TEST(Text, TrimAndSplit) {
  EXPECT_EQ(trim(" \t a b \r\n"), "a b");
  EXPECT_EQ(trim("   "), "");
  EXPECT_EQ(split_csv_fields(" x , y,,z ,"), (std::vector<std::string>{"x", "y", "", "z", ""}));
  EXPECT_EQ(split_csv_fields(""), (std::vector<std::string>{""}));
  EXPECT_EQ(split_words("  1\t2   3 \r"), (std::vector<std::string>{"1", "2", "3"}));
  EXPECT_TRUE(split_words(" \t").empty());
}

}  // namespace
}  // namespace aggpack
