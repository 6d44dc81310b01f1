#include "arguments.hpp"

#include <charconv>
#include <cmath>
#include <limits>
#include <string_view>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "aggpack/core/error.hpp"
#include "aggpack/core/input_file.hpp"
#include "aggpack/core/text.hpp"
#include "aggpack/core/units.hpp"
#include "aggpack/io/dem_calibration_file.hpp"

double length_argument(const std::string& text, const std::string& option, long double bare_unit) {
  std::string why;
  const auto v = aggpack::parse_length(text, &why, bare_unit);
  if (!v) throw aggpack::InputError(fmt::format("{} {}: expected a positive length ({})", option, text, why));
  if (!(*v > 0.0)) throw aggpack::InputError(fmt::format("{} {}: expected a positive length, not {} m", option, text, *v));
  return *v;
}

std::uint64_t seed_argument(const std::string& text) {
  std::int64_t value = -1;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || value < 0)
    throw aggpack::InputError(fmt::format("--seed {}: expected an integer from 0 to {} (as the scenario's seed)", text,
                                          std::numeric_limits<std::int64_t>::max()));
  return static_cast<std::uint64_t>(value);
}

// Not CLI11's PositiveNumber, which would say "not in range 0.000000 to 1797...", its bound
// DBL_MAX in 309 digits.
double positive_argument(const std::string& text, const std::string& option) {
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || !(value > 0.0) || !std::isfinite(value))
    throw aggpack::InputError(fmt::format("{} {}: expected a number above 0", option, text));
  return value;
}

std::vector<double> numbers_argument(const std::string& text, const std::string& option) {
  std::vector<double> values;
  for (const std::string& part : list_parts(text)) {
    double value = 0.0;
    const auto [end, error] = std::from_chars(part.data(), part.data() + part.size(), value);
    if (part.empty() || error != std::errc() || end != part.data() + part.size() || !std::isfinite(value))
      throw aggpack::InputError(fmt::format("{} {}: \"{}\" is not a number; expected numbers separated by commas", option,
                                            text, part));
    values.push_back(value);
  }
  return values;
}

int count_argument(const std::string& text, const std::string& option) {
  int value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || value < 1)
    throw aggpack::InputError(fmt::format("{} {}: expected a whole number, 1 or more", option, text));
  return value;
}

std::string seconds_argument(const std::string& text) {
  double value = -1.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || !(value >= 0.0) || !(value <= 1e9))
    throw aggpack::InputError(
        fmt::format("--checkpoint-every {}: expected seconds of wall clock from 0 (every safe point) to 1e9", text));
  return fmt::format("{}", value);  // the shortest text that reads back as the same double
}

std::vector<std::string> list_parts(const std::string& text) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (true) {
    const auto comma = text.find(',', start);
    const std::size_t length = comma == std::string::npos ? std::string::npos : comma - start;
    parts.emplace_back(aggpack::trim(std::string_view(text).substr(start, length)));
    if (comma == std::string::npos) return parts;
    start = comma + 1;
  }
}

std::vector<double> lengths_argument(const std::string& text, const std::string& option, long double bare_unit) {
  std::vector<double> v;
  for (const std::string& part : list_parts(text)) {
    std::string why;
    const auto value = aggpack::parse_length(part, &why, bare_unit);
    if (!value) throw aggpack::InputError(fmt::format("{} {}: \"{}\": {}", option, text, part, why));
    v.push_back(*value);
  }
  return v;
}

aggpack::Box box_argument(const std::string& text, long double bare_unit) {
  const std::vector<double> v = lengths_argument(text, "--box", bare_unit);
  if (v.size() != 6 || !(v[3] > v[0] && v[4] > v[1] && v[5] > v[2]))
    throw aggpack::InputError(fmt::format("--box {}: expected xmin,ymin,zmin,xmax,ymax,zmax with max > min", text));
  return {{v[0], v[1], v[2]}, {v[3], v[4], v[5]}};
}

std::string toml_path(const std::filesystem::path& file) {
  std::string quoted = "\"";  // a TOML basic string
  for (const char ch : std::filesystem::absolute(file).string()) {
    if (ch == '"' || ch == '\\') quoted += '\\';
    quoted += ch;
  }
  return quoted + '"';
}

CalibrationArguments calibration_arguments(const std::vector<std::string>& files) {
  CalibrationArguments c;
  std::vector<std::string> dem, typed;
  for (const std::string& file : files) {
    // Routed by its kind; a file that cannot be read is refused here, naming it.
    if (aggpack::is_dem_calibration_text(aggpack::read_input_text(file, "the calibration"))) {
      dem.push_back(toml_path(file));
      typed.push_back("--calibration " + file);
    } else if (c.cpm) {
      throw aggpack::InputError(fmt::format("--calibration {} and --calibration {}: two of CPM's calibrations give K "
                                            "and beta twice; give one (DEM calibrations, from calibrate --dem, may be "
                                            "several)",
                                            c.cpm->string(), file));
    } else {
      c.cpm = file;  // read (and refused when it is not one) by the models' own reader
    }
  }
  if (!dem.empty()) {
    c.calibrated_by = fmt::format("calibrated_by=[{}]", fmt::join(dem, ", "));
    c.typed = fmt::format("{}", fmt::join(typed, " "));
  }
  return c;
}

void add_run_calibrations(const std::vector<std::string>& files, aggpack::ScenarioOverrides& overrides) {
  const CalibrationArguments c = calibration_arguments(files);
  if (c.calibrated_by) {
    overrides.set.push_back(*c.calibrated_by);
    overrides.typed_as[*c.calibrated_by] = c.typed;
  }
  if (c.cpm) {
    const std::string models = "models.calibration=" + toml_path(*c.cpm);
    overrides.set.push_back(models);
    overrides.typed_as[models] = "--calibration " + c.cpm->string();
  }
}
