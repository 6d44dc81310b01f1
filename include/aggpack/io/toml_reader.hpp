#pragma once
#include "aggpack/core/enum_names.hpp"
#include <cstdint>
#include <initializer_list>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

namespace aggpack {

// Where a scenario's values came from: the file, and the keys that --set replaced.
struct ScenarioOrigin {
  std::string file;
  std::map<std::string, std::string> overrides;  // dotted key -> "--set key=value"
  std::string root_name = "the scenario";         // the root table, in messages ("the material file")
};

// Closed or open numeric bounds, with the wording used in error messages.
struct NumberRange {
  double min = -1e308, max = 1e308;
  bool min_open = false, max_open = false;
  [[nodiscard]] bool contains(double v) const;
  [[nodiscard]] std::string describe() const;
};
inline constexpr NumberRange kPositive{0.0, 1e308, true, false};
inline constexpr NumberRange kNonNegative{0.0, 1e308, false, false};

// The largest a bare number (read as metres) may be for a length key: beyond it the number was
// most likely meant in inches or millimetres ("side = 12"). A length this large is accepted
// when its unit is written ("12 m").
inline constexpr double kLargestBareLength = 2.0;  // m: a container side or height, a fill height
inline constexpr double kLargestBareGrain = 0.2;   // m: a grain's diameter, a sieve opening

// Reads one TOML table of a scenario. Every error names the file, line and dotted key,
// says what is wrong and what is expected, and is thrown as InputError.
class TomlSection {
 public:
  TomlSection(const toml::table& table, std::string path, const ScenarioOrigin& origin);

  // Rejects keys not in `allowed`, suggesting the nearest valid key for a typo.
  void allow_only(std::initializer_list<std::string_view> allowed) const;
  void allow_only(std::span<const std::string_view> allowed) const;

  [[nodiscard]] bool has(std::string_view key) const;
  // The table's keys, in alphabetical order.
  [[nodiscard]] std::vector<std::string> keys() const;
  [[nodiscard]] std::string key_path(std::string_view key) const;
  [[nodiscard]] std::string location(std::string_view key) const;
  [[noreturn]] void fail(std::string_view key, std::string_view what) const;

  std::optional<double> number(std::string_view key, NumberRange range) const;
  std::optional<std::int64_t> integer(std::string_view key, std::int64_t min, std::int64_t max) const;
  std::optional<std::string> string(std::string_view key) const;
  std::optional<bool> boolean(std::string_view key) const;
  // One of `choices`; the message lists them.
  std::optional<std::string> choice(std::string_view key, std::initializer_list<std::string_view> choices) const;
  std::optional<std::string> choice(std::string_view key, const std::vector<std::string_view>& choices) const;
  // One of an enum's names (its EnumName table), as the value.
  template <class E, std::size_t N>
  std::optional<E> choice(std::string_view key, const std::array<EnumName<E>, N>& table) const {
    const auto name = choice(key, names_of(table));
    return name ? value_of(table, *name) : std::nullopt;
  }
  // A string with a unit ("1 in") or a bare number (metres), at most `largest_bare` when bare.
  std::optional<double> length(std::string_view key, NumberRange range = kPositive,
                               double largest_bare = kLargestBareLength) const;
  std::optional<std::vector<double>> length_list(std::string_view key) const;
  // The unit symbol a length key is written with ("in" for "4 in"); none for a bare number.
  [[nodiscard]] std::optional<std::string> written_unit(std::string_view key) const;
  std::optional<std::vector<std::string>> string_list(std::string_view key) const;
  std::optional<TomlSection> table(std::string_view key) const;
  // Elements of an array of tables, each as a section named key[i].
  std::optional<std::vector<TomlSection>> table_array(std::string_view key) const;

  template <class T>
  T required(std::optional<T> value, std::string_view key, std::string_view expected) const {
    if (!value) missing(key, expected);
    return *value;
  }
  [[noreturn]] void missing(std::string_view key, std::string_view expected) const;

  [[nodiscard]] const std::string& path() const { return path_; }

 private:
  [[nodiscard]] const toml::node* node(std::string_view key) const;
  [[nodiscard]] std::string node_location(const toml::node& n, const std::string& key_path) const;
  [[nodiscard]] double length_value(const toml::node& n, const std::string& key_path, NumberRange range,
                                    double largest_bare = kLargestBareLength) const;

  const toml::table* table_;
  std::string path_;  // dotted path of this table, "" for the root
  const ScenarioOrigin* origin_;
};

// Levenshtein distance, for "did you mean" suggestions.
std::size_t edit_distance(std::string_view a, std::string_view b);

// toml value type names for messages: "a string", "an integer", ...
std::string describe_type(const toml::node& n);

}  // namespace aggpack
