#pragma once
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace aggpack {

// A DEM calibration (`aggpack calibrate --dem --out FILE`): scenario keys whose values were
// fitted to a measured density, and what they were fitted to. A scenario takes it with
// `calibrated_by = "FILE"` (`run --calibration FILE`): its assignments replace the scenario's
// own values of those keys.
struct DemCalibrationFile {
  std::filesystem::path file;
  // "materials.sand.rolling_friction=0.231": only a material's rolling_friction or
  // friction_particle, of [material] or of a [materials.NAME].
  std::vector<std::string> assignments;
  std::string fitted_to;  // one line: the measurement, the scenario and protocol, the seeds, the band
};

inline constexpr std::string_view kDemCalibrationKind = "aggpack DEM calibration";

// Whether `text` is a DEM calibration (its "kind"), as opposed to CPM's (`calibrate` without --dem).
[[nodiscard]] bool is_dem_calibration_text(std::string_view text);
// Reads and checks the file: InputError naming the file and the key when it is not one.
DemCalibrationFile read_dem_calibration(const std::filesystem::path& file);
DemCalibrationFile parse_dem_calibration(std::string_view text, const std::filesystem::path& file);
}  // namespace aggpack
