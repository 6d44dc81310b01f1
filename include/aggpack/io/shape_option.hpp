#pragma once
// A grain shape given on the command line (`aggpack grading --shape`), read by the scenario's
// own reader of a component's `shape` table, so that its keys, ranges and messages are the same.
#include <string_view>

#include "aggpack/grains/grain_library.hpp"

namespace aggpack {

// `text` is the table's inside, with or without its braces: family = "angular", flakiness_index = 18.
// InputError naming `option` and the key when it is not a valid shape table.
[[nodiscard]] GrainShapeSpec read_shape_option(std::string_view text, std::string_view option);

}  // namespace aggpack
