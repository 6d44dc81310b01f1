#pragma once
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace aggpack {

// The one trim and the two field splitters every reader of text files uses.

// `text` without leading and trailing whitespace.
[[nodiscard]] std::string_view trim(std::string_view text);

// The comma-separated fields of a CSV line, each trimmed; "a,,b," gives four fields, the
// empty ones included. (No quoting: aggpack's files and the sieve tables it reads have none.)
[[nodiscard]] std::vector<std::string> split_csv_fields(std::string_view line);

// The whitespace-separated words of a line; runs of blanks count as one separator.
[[nodiscard]] std::vector<std::string> split_words(std::string_view line);

// The whole of `text` as a finite number (strtod's syntax), or as an integer; nullopt for
// anything else (empty, trailing characters, out of range, inf or nan).
[[nodiscard]] std::optional<double> parse_finite_number(std::string_view text);
[[nodiscard]] std::optional<std::int64_t> parse_integer(std::string_view text);

// Characters of UTF-8 `text`, as a terminal or a plot shows them ("±" is one, not two bytes).
[[nodiscard]] inline std::size_t display_width(std::string_view text) {
  std::size_t n = 0;
  for (const unsigned char c : text) n += (c & 0xC0) != 0x80;  // continuation bytes take no column
  return n;
}

}  // namespace aggpack
