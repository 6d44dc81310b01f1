#include "aggpack/io/toml_reader.hpp"

#include <algorithm>
#include <span>
#include <cmath>
#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/core/text.hpp"
#include "aggpack/core/units.hpp"

namespace aggpack {

bool NumberRange::contains(double v) const {
  if (!std::isfinite(v)) return false;
  const bool above = min_open ? v > min : v >= min;
  const bool below = max_open ? v < max : v <= max;
  return above && below;
}

std::string NumberRange::describe() const {
  const bool has_min = min > -1e307, has_max = max < 1e307;
  if (has_min && has_max)
    return fmt::format("a number in {}{:g}, {:g}{}", min_open ? "(" : "[", min, max, max_open ? ")" : "]");
  if (has_min) {
    if (min == 0.0) return min_open ? "a positive number" : "a number >= 0";
    return fmt::format("a number {} {:g}", min_open ? ">" : ">=", min);
  }
  if (has_max) return fmt::format("a number {} {:g}", max_open ? "<" : "<=", max);
  return "a number";
}

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

std::string describe_type(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a float";
    case toml::node_type::boolean: return "a boolean";
    case toml::node_type::table: return "a table";
    case toml::node_type::array: return "an array";
    default: return "a date or time";
  }
}

namespace {
std::string render(const toml::node& n) {
  if (const auto* s = n.as_string()) return fmt::format("\"{}\"", s->get());
  if (const auto* i = n.as_integer()) return std::to_string(i->get());
  if (const auto* f = n.as_floating_point()) return fmt::format("{:g}", f->get());
  if (const auto* b = n.as_boolean()) return b->get() ? "true" : "false";
  return describe_type(n);
}
}  // namespace

TomlSection::TomlSection(const toml::table& table, std::string path, const ScenarioOrigin& origin)
    : table_(&table), path_(std::move(path)), origin_(&origin) {}

std::string TomlSection::key_path(std::string_view key) const {
  return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
}

const toml::node* TomlSection::node(std::string_view key) const { return table_->get(key); }

bool TomlSection::has(std::string_view key) const { return node(key) != nullptr; }

std::string TomlSection::node_location(const toml::node& n, const std::string& full_key) const {
  // --set values carry no source position: name the option instead.
  for (const auto& [key, text] : origin_->overrides)
    if (full_key == key || full_key.rfind(key + ".", 0) == 0 || full_key.rfind(key + "[", 0) == 0) return text;
  const auto& src = n.source();
  if (src.begin.line > 0) return fmt::format("{}:{}:{}", origin_->file, src.begin.line, src.begin.column);
  return origin_->file;
}

std::string TomlSection::location(std::string_view key) const {
  if (const toml::node* n = node(key)) return node_location(*n, key_path(key));
  return node_location(*table_, path_);
}

void TomlSection::fail(std::string_view key, std::string_view what) const {
  throw InputError(fmt::format("{}: {}: {}", location(key), key_path(key), what));
}

void TomlSection::missing(std::string_view key, std::string_view expected) const {
  const std::string where = path_.empty() ? origin_->root_name : "[" + path_ + "]";
  throw InputError(fmt::format("{}: {}: missing required key '{}' in {} (expected {})",
                               node_location(*table_, path_), key_path(key), key, where, expected));
}

void TomlSection::allow_only(std::initializer_list<std::string_view> allowed) const {
  allow_only(std::span<const std::string_view>(allowed.begin(), allowed.size()));
}

void TomlSection::allow_only(std::span<const std::string_view> allowed) const {
  for (const auto& [k, v] : *table_) {
    const std::string_view key = k.str();
    if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
    std::string_view best;
    std::size_t best_distance = 1000;
    for (std::string_view candidate : allowed) {
      const std::size_t d = edit_distance(key, candidate);
      if (d < best_distance) best_distance = d, best = candidate;
    }
    std::string message = fmt::format("unknown key '{}'", key);
    if (!best.empty() && best_distance <= std::max<std::size_t>(2, key.size() / 3))
      message += fmt::format("; did you mean '{}'?", best);
    std::string list;
    for (std::string_view candidate : allowed) list += (list.empty() ? "" : ", ") + std::string(candidate);
    message += fmt::format(" (valid keys here: {})", list);
    throw InputError(fmt::format("{}: {}: {}", node_location(v, key_path(key)), key_path(key), message));
  }
}

std::optional<double> TomlSection::number(std::string_view key, NumberRange range) const {
  const toml::node* n = node(key);
  if (!n) return std::nullopt;
  double v = 0.0;
  if (const auto* i = n->as_integer()) v = static_cast<double>(i->get());
  else if (const auto* f = n->as_floating_point()) v = f->get();
  else fail(key, fmt::format("expected {}, got {} {}", range.describe(), describe_type(*n), render(*n)));
  if (!range.contains(v)) fail(key, fmt::format("expected {}, got {}", range.describe(), render(*n)));
  return v;
}

std::optional<std::int64_t> TomlSection::integer(std::string_view key, std::int64_t min, std::int64_t max) const {
  const toml::node* n = node(key);
  if (!n) return std::nullopt;
  const auto* i = n->as_integer();
  const std::string expected = fmt::format("an integer in [{}, {}]", min, max);
  if (!i) fail(key, fmt::format("expected {}, got {} {}", expected, describe_type(*n), render(*n)));
  if (i->get() < min || i->get() > max) fail(key, fmt::format("expected {}, got {}", expected, i->get()));
  return i->get();
}

std::optional<std::string> TomlSection::string(std::string_view key) const {
  const toml::node* n = node(key);
  if (!n) return std::nullopt;
  const auto* s = n->as_string();
  if (!s) fail(key, fmt::format("expected a string, got {} {}", describe_type(*n), render(*n)));
  return s->get();
}

std::optional<bool> TomlSection::boolean(std::string_view key) const {
  const toml::node* n = node(key);
  if (!n) return std::nullopt;
  const auto* b = n->as_boolean();
  if (!b) fail(key, fmt::format("expected true or false, got {} {}", describe_type(*n), render(*n)));
  return b->get();
}

std::optional<std::string> TomlSection::choice(std::string_view key,
                                               std::initializer_list<std::string_view> choices) const {
  return choice(key, std::vector<std::string_view>(choices));
}

std::optional<std::string> TomlSection::choice(std::string_view key,
                                               const std::vector<std::string_view>& choices) const {
  auto s = string(key);
  if (!s) return s;
  if (std::find(choices.begin(), choices.end(), *s) != choices.end()) return s;
  std::string list;
  for (auto c : choices) list += (list.empty() ? "\"" : ", \"") + std::string(c) + "\"";
  fail(key, fmt::format("expected one of {}, got \"{}\"", list, *s));
}

double TomlSection::length_value(const toml::node& n, const std::string& full_key, NumberRange range,
                                 double largest_bare) const {
  const auto bad = [&](const std::string& what) -> double {
    throw InputError(fmt::format("{}: {}: {}", node_location(n, full_key), full_key, what));
  };
  const std::string expected =
      "a length such as \"1 in\", \"25.4 mm\" or \"0.0254 m\" (a bare number is metres)";
  double v = 0.0;
  if (const auto* s = n.as_string()) {
    std::string why;
    const auto parsed = parse_length(s->get(), &why);
    if (!parsed) return bad(fmt::format("{}; expected {}", why, expected));
    v = *parsed;
  } else if (const auto* i = n.as_integer()) {
    v = static_cast<double>(i->get());
  } else if (const auto* f = n.as_floating_point()) {
    v = f->get();
  } else {
    return bad(fmt::format("expected {}, got {} {}", expected, describe_type(n), render(n)));
  }
  if (!range.contains(v))
    return bad(fmt::format("expected {} (in metres), got {}", range.describe(), render(n)));
  if (!n.is_string() && v > largest_bare)
    return bad(fmt::format("{} is a bare number, read as {:g} m, more than {:g} m: if it is in inches or millimetres, "
                           "write its unit (\"{} in\", \"{} mm\"); a length this large is taken with its unit written "
                           "(\"{} m\")",
                           render(n), v, largest_bare, render(n), render(n), render(n)));
  return v;
}

std::optional<double> TomlSection::length(std::string_view key, NumberRange range, double largest_bare) const {
  const toml::node* n = node(key);
  if (!n) return std::nullopt;
  return length_value(*n, key_path(key), range, largest_bare);
}

std::optional<std::string> TomlSection::written_unit(std::string_view key) const {
  const toml::node* n = node(key);
  const auto* text = n ? n->as_string() : nullptr;
  if (!text) return std::nullopt;
  const std::string value = text->get();
  const std::size_t unit = value.find_first_not_of("0123456789+-.eE \t");
  if (unit == std::string::npos) return std::nullopt;
  return std::string(trim(std::string_view(value).substr(unit)));
}

std::optional<std::vector<double>> TomlSection::length_list(std::string_view key) const {
  const toml::node* n = node(key);
  if (!n) return std::nullopt;
  const auto* arr = n->as_array();
  if (!arr) fail(key, fmt::format("expected an array of lengths such as [\"6 in\", \"8 in\"], got {}", describe_type(*n)));
  std::vector<double> out;
  for (std::size_t i = 0; i < arr->size(); ++i)
    out.push_back(length_value(*arr->get(i), fmt::format("{}[{}]", key_path(key), i), kPositive));
  return out;
}

std::optional<std::vector<std::string>> TomlSection::string_list(std::string_view key) const {
  const toml::node* n = node(key);
  if (!n) return std::nullopt;
  const auto* arr = n->as_array();
  if (!arr) fail(key, fmt::format("expected an array of strings, got {}", describe_type(*n)));
  std::vector<std::string> out;
  for (std::size_t i = 0; i < arr->size(); ++i) {
    const auto* s = arr->get(i)->as_string();
    if (!s)
      throw InputError(fmt::format("{}: {}[{}]: expected a string, got {}", node_location(*arr->get(i), key_path(key)),
                                   key_path(key), i, describe_type(*arr->get(i))));
    out.push_back(s->get());
  }
  return out;
}

std::vector<std::string> TomlSection::keys() const {
  std::vector<std::string> names;
  for (const auto& [key, value] : *table_) names.emplace_back(key.str());
  return names;
}

std::optional<TomlSection> TomlSection::table(std::string_view key) const {
  const toml::node* n = node(key);
  if (!n) return std::nullopt;
  const auto* t = n->as_table();
  if (!t) fail(key, fmt::format("expected a table ([{}]), got {}", key_path(key), describe_type(*n)));
  return TomlSection(*t, key_path(key), *origin_);
}

std::optional<std::vector<TomlSection>> TomlSection::table_array(std::string_view key) const {
  const toml::node* n = node(key);
  if (!n) return std::nullopt;
  const auto* arr = n->as_array();
  if (!arr) fail(key, fmt::format("expected an array of tables, got {}", describe_type(*n)));
  std::vector<TomlSection> out;
  for (std::size_t i = 0; i < arr->size(); ++i) {
    const auto* t = arr->get(i)->as_table();
    if (!t)
      throw InputError(fmt::format("{}: {}[{}]: expected a table such as {{ diameter = \"1 in\", count = 10 }}, got {}",
                                   node_location(*arr->get(i), key_path(key)), key_path(key), i,
                                   describe_type(*arr->get(i))));
    out.emplace_back(*t, fmt::format("{}[{}]", key_path(key), i), *origin_);
  }
  return out;
}

}  // namespace aggpack
