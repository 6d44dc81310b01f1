#pragma once
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace aggpack {

struct LengthUnit {
  std::string_view symbol;
  long double metres;  // exact by definition (1 in = 0.0254 m)
};

// The length units a scenario or a command line may use.
std::span<const LengthUnit> length_units();

// Parses "25.4 mm", "1in", "0.0254 m" or a bare number, which is in `bare_unit` (metres per
// unit: 1 for metres, 1e-3 when the bare numbers of a file in mm are meant).
// Returns std::nullopt with `why` set when the text is not a length.
std::optional<double> parse_length(std::string_view text, std::string* why = nullptr, long double bare_unit = 1.0L);

// Metres per unit for a symbol such as "mm"; std::nullopt if unknown.
std::optional<long double> metres_per_unit(std::string_view symbol);

// A length in metres, and in the unit the scenario is written in beside it ("0.1016 m (4 in)");
// metres alone when it is written in none.
std::string length_text(double metres, const std::string& written_unit);

}  // namespace aggpack
