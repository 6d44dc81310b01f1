#pragma once
#include <array>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace aggpack {

// One table per enum gives each value the name that scenario files, summary.json and the
// notes all use, so that a key and its echo never drift apart (the scenario's "as_listed"
// was "listed" in the notes).
template <class E>
struct EnumName {
  E value;
  std::string_view name;
};

template <class E, std::size_t N>
[[nodiscard]] constexpr std::string_view name_of(const std::array<EnumName<E>, N>& table, E value) {
  for (const auto& entry : table)
    if (entry.value == value) return entry.name;
  throw std::logic_error("name_of: a value missing from its table");
}

template <class E, std::size_t N>
[[nodiscard]] constexpr std::optional<E> value_of(const std::array<EnumName<E>, N>& table, std::string_view name) {
  for (const auto& entry : table)
    if (entry.name == name) return entry.value;
  return std::nullopt;
}

template <class E, std::size_t N>
[[nodiscard]] std::vector<std::string_view> names_of(const std::array<EnumName<E>, N>& table) {
  std::vector<std::string_view> names;
  for (const auto& entry : table) names.push_back(entry.name);
  return names;
}

}  // namespace aggpack
