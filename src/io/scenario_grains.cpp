// A component's `shape` table: its particles as rigid grains of several spheres (issue 38).
#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/grains/named_shapes.hpp"
#include "aggpack/io/shape_option.hpp"
#include "scenario_tables.hpp"

namespace aggpack {

namespace {
constexpr NumberRange kRatio{ProportionDistribution::kLeastRatio, 1.0, false, false};
constexpr NumberRange kSpread{0.0, 0.5, false, false};
constexpr NumberRange kPercent{0.0, 100.0, false, false};

// At most one lab measure the proportions are fitted to.
void read_shape_target(const TomlSection& s, GrainShapeSpec& spec) {
  const std::optional<double> flakiness = s.number("flakiness_index", kPercent),
                              shape_index = s.number("shape_index", kPercent),
                              flat_elongated = s.number("flat_elongated", kPercent);
  if (int(flakiness.has_value()) + int(shape_index.has_value()) + int(flat_elongated.has_value()) > 1)
    s.fail(flakiness ? "flakiness_index" : "shape_index",
           "give at most one lab measure to fit the proportions to: flakiness_index (EN 933-3), shape_index "
           "(EN 933-4) or flat_elongated (ASTM D4791)");
  if (s.has("flat_elongated_ratio") && !flat_elongated)
    s.fail("flat_elongated_ratio", "applies only with flat_elongated");
  if (flakiness) spec.target = ShapeTarget{ShapeMeasure::FlakinessIndex, *flakiness, 0.0};
  if (shape_index) spec.target = ShapeTarget{ShapeMeasure::ShapeIndex, *shape_index, 0.0};
  if (flat_elongated) {
    const double ratio = s.number("flat_elongated_ratio", {1.0, 10.0, true, false}).value_or(3.0);
    spec.target = ShapeTarget{ShapeMeasure::FlatAndElongated, *flat_elongated, ratio};
  }
}
}  // namespace

ShapeTable read_shape_table(const TomlSection& s) {
  s.allow_only({"default", "family", "spheres", "corners", "templates", "elongation", "flatness", "spread",
                "elongation_spread", "flatness_spread", "flakiness_index", "shape_index", "flat_elongated",
                "flat_elongated_ratio"});
  ShapeTable shape;
  GrainShapeSpec& spec = shape.spec;
  // A named default gives the family, the proportions and the spheres; the keys beside it refine them.
  const bool named = s.has("default");
  if (named) {
    shape.name = *s.choice("default", named_grain_shape_names());
    spec = *named_grain_shape(shape.name);
    if (s.has("family"))
      s.fail("family", fmt::format("the named shape \"{}\" gives the family; give 'default' or 'family', not both",
                                   shape.name));
  } else {
    const std::string family = s.required(s.choice("family", {"rounded", "angular"}), "family",
                                          "\"rounded\" (gravel) or \"angular\" (crushed stone), or a named shape "
                                          "'default' (crushed_stone, gravel, natural_sand, manufactured_sand)");
    spec.family = family == "rounded" ? GrainFamily::Rounded : GrainFamily::Angular;
    spec.proportions = {0.7, 0.1, 0.7, 0.1};
  }
  if (const auto n = s.integer("spheres", 1, 64)) spec.spheres = static_cast<std::size_t>(*n);
  if (const auto n = s.integer("corners", 4, 200)) {
    if (spec.family != GrainFamily::Angular) s.fail("corners", "applies only to angular grains (a hull's corners)");
    spec.corners = static_cast<std::size_t>(*n);
  }
  if (const auto n = s.integer("templates", 1, 1000)) spec.templates = static_cast<std::size_t>(*n);
  ProportionDistribution& p = spec.proportions;
  p.elongation_mean = s.number("elongation", kRatio).value_or(p.elongation_mean);
  p.flatness_mean = s.number("flatness", kRatio).value_or(p.flatness_mean);
  if (const auto spread = s.number("spread", kSpread)) p.elongation_spread = p.flatness_spread = *spread;
  p.elongation_spread = s.number("elongation_spread", kSpread).value_or(p.elongation_spread);
  p.flatness_spread = s.number("flatness_spread", kSpread).value_or(p.flatness_spread);
  read_shape_target(s, spec);
  return shape;
}

std::optional<GrainShapeSpec> read_grain_shape(const TomlSection& component) {
  const std::optional<TomlSection> table = component.table("shape");
  if (!table) return std::nullopt;
  return read_shape_table(*table).spec;
}

GrainShapeSpec read_shape_option(std::string_view text, std::string_view option) {
  std::string inside(text);
  const auto first = inside.find_first_not_of(" \t");
  if (first == std::string::npos || inside[first] != '{') inside = "{" + inside + "}";
  const std::string quoted = fmt::format("{} '{}'", option, text);
  toml::table root;
  try {
    root = toml::parse("shape = " + inside);
  } catch (const toml::parse_error& e) {
    throw InputError(fmt::format("{}: not a TOML inline table ({}); expected, for example, "
                                 "'family = \"angular\", flakiness_index = 18'",
                                 quoted, e.description()));
  }
  if (!root["shape"].is_table())
    throw InputError(fmt::format("{}: expected a table of the shape's keys, for example 'family = \"rounded\"'", quoted));
  const ScenarioOrigin origin{std::string(option), {{"shape", quoted}}};
  return *read_grain_shape(TomlSection(root, "", origin));
}

}  // namespace aggpack
