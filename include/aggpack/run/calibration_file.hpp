#pragma once

#include <filesystem>
#include <string_view>

#include "aggpack/run/predictions.hpp"

namespace aggpack {

// A calibration file (`calibrate --out`) as the models' parameters, naming the file;
// parse_calibration() reads its text (InputError naming `file` and the key when it is not one).
ModelParameters read_calibration(const std::filesystem::path& file);
ModelParameters parse_calibration(std::string_view text, const std::filesystem::path& file);
}  // namespace aggpack
