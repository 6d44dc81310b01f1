#include "aggpack/core/units.hpp"

#include "aggpack/core/text.hpp"

#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>

#include <fmt/format.h>

namespace aggpack {

namespace {
constexpr std::array<LengthUnit, 8> kUnits{{
    {"m", 1.0L},
    {"cm", 1e-2L},
    {"mm", 1e-3L},
    {"um", 1e-6L},
    {"µm", 1e-6L},
    {"in", 0.0254L},
    {"ft", 0.3048L},
    {"yd", 0.9144L},
}};

}  // namespace

std::span<const LengthUnit> length_units() { return kUnits; }

std::optional<long double> metres_per_unit(std::string_view symbol) {
  for (const auto& u : kUnits)
    if (u.symbol == symbol) return u.metres;
  return std::nullopt;
}

std::optional<double> parse_length(std::string_view text, std::string* why, long double bare_unit) {
  const std::string s(trim(text));
  if (s.empty()) {
    if (why) *why = "empty length";
    return std::nullopt;
  }
  errno = 0;
  char* end = nullptr;
  // long double keeps the unit conversion correctly rounded to double ("25.4 mm" == "1 in").
  const long double number = std::strtold(s.c_str(), &end);
  if (end == s.c_str() || errno == ERANGE || !std::isfinite(number)) {
    if (why) *why = "'" + s + "' does not start with a number";
    return std::nullopt;
  }
  const std::string_view symbol = trim(std::string_view(end));
  long double factor = bare_unit;
  if (!symbol.empty()) {
    const auto f = metres_per_unit(symbol);
    if (!f) {
      if (why) {
        *why = "unknown length unit '" + std::string(symbol) + "' (known: ";
        for (std::size_t i = 0; i < kUnits.size(); ++i)
          *why += (i ? ", " : "") + std::string(kUnits[i].symbol);
        *why += ")";
      }
      return std::nullopt;
    }
    factor = *f;
  }
  return static_cast<double>(number * factor);
}

std::string length_text(double metres, const std::string& written_unit) {
  const auto per_unit = written_unit.empty() ? std::nullopt : metres_per_unit(written_unit);
  if (!per_unit) return fmt::format("{:.4g} m", metres);
  return fmt::format("{:.4g} m ({:.4g} {})", metres, metres / static_cast<double>(*per_unit), written_unit);
}

}  // namespace aggpack
