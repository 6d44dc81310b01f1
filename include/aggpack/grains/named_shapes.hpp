#pragma once
// Named default grain shapes for the aggregates a lab most often has at hand, each a
// GrainShapeSpec (a family, its proportions and its template's sphere count): what a material
// file's or a component's `shape = { default = "gravel" }` gives. The sources of each are in
// named_shapes.cpp and README.md ("Materials: one file per aggregate").
#include <optional>
#include <string_view>
#include <vector>

#include "aggpack/grains/grain_library.hpp"

namespace aggpack {

// crushed_stone, gravel, natural_sand, manufactured_sand; none for another name.
[[nodiscard]] std::optional<GrainShapeSpec> named_grain_shape(std::string_view name);
[[nodiscard]] std::vector<std::string_view> named_grain_shape_names();

}  // namespace aggpack
