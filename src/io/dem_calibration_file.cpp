// A DEM calibration file read back: its assignments checked one by one (a file is user input:
// it may have been edited), and the line that says what they were fitted to.
#include "aggpack/io/dem_calibration_file.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <regex>

#include "aggpack/core/error.hpp"
#include "aggpack/core/input_file.hpp"

namespace aggpack {

namespace {
std::string described(const nlohmann::json& v) {
  if (v.is_null()) return "null";
  const std::string type = v.type_name();
  return fmt::format("{} {}", type == "object" || type == "array" ? "an" : "a", type);
}

nlohmann::json parsed(std::string_view text) {
  return nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
}

bool has_dem_kind(const nlohmann::json& j) {
  const auto kind = j.is_object() ? j.find("kind") : j.end();
  return kind != j.end() && kind->is_string() && kind->get_ref<const std::string&>() == kDemCalibrationKind;
}
}  // namespace

bool is_dem_calibration_text(std::string_view text) { return has_dem_kind(parsed(text)); }

DemCalibrationFile parse_dem_calibration(std::string_view text, const std::filesystem::path& file) {
  const nlohmann::json j = parsed(text);
  if (j.is_discarded())
    throw InputError(fmt::format("{}: not JSON (expected a file aggpack calibrate --dem wrote)", file.string()));
  if (!has_dem_kind(j))
    throw InputError(
        fmt::format("{}: not a DEM calibration written by aggpack calibrate --dem (expected \"kind\": \"{}\")",
                    file.string(), kDemCalibrationKind));
  const auto fail = [&](std::string_view key, const std::string& what) {
    return InputError(fmt::format("{}: {}: {}", file.string(), key, what));
  };
  const auto member = [&](const nlohmann::json& object, const std::string& path, const char* key, auto is_type,
                          const char* expected) -> const nlohmann::json& {
    const std::string name = path.empty() ? std::string(key) : path + "." + key;
    const auto v = object.find(key);
    if (v == object.end()) throw fail(name, fmt::format("missing; expected {}", expected));
    if (!is_type(*v)) throw fail(name, fmt::format("{}; expected {}", described(*v), expected));
    return *v;
  };
  const auto is_object = [](const nlohmann::json& v) { return v.is_object(); };
  const auto is_number = [](const nlohmann::json& v) { return v.is_number() && std::isfinite(v.get<double>()); };
  const auto is_string = [](const nlohmann::json& v) { return v.is_string(); };
  const auto is_array = [](const nlohmann::json& v) { return v.is_array() && !v.empty(); };
  const auto is_band = [](const nlohmann::json& v) {
    return v.is_array() && v.size() == 2 && v[0].is_number() && v[1].is_number();
  };

  DemCalibrationFile c;
  c.file = file;
  // Only the two levers calibrate fits, of [material] or a named material: a calibration file
  // sets nothing else in a scenario.
  static const std::regex kAssignment(
      R"(^(material|materials\.[A-Za-z0-9_]+)\.(rolling_friction|friction_particle)=(.+)$)");
  const nlohmann::json& assignments = member(j, "", "assignments", is_array, "a list of \"key=value\" strings");
  for (std::size_t i = 0; i < assignments.size(); ++i) {
    const std::string key = fmt::format("assignments[{}]", i);
    if (!assignments[i].is_string())
      throw fail(key, fmt::format("{}; expected a \"key=value\" string", described(assignments[i])));
    const std::string& a = assignments[i].get_ref<const std::string&>();
    std::smatch m;
    double value = NAN;
    if (std::regex_match(a, m, kAssignment)) {
      try {
        std::size_t used = 0;
        value = std::stod(m[3].str(), &used);
        if (used != m[3].str().size()) value = NAN;
      } catch (const std::exception&) {
        value = NAN;
      }
    }
    if (!(value >= 0.0 && std::isfinite(value)))
      throw fail(key,
                 fmt::format("\"{}\"; expected material.KEY=VALUE or materials.NAME.KEY=VALUE, KEY rolling_friction "
                             "or friction_particle, VALUE a number >= 0",
                             a));
    c.assignments.push_back(a);
  }
  const nlohmann::json& measured = member(j, "", "measured", is_object, "an object");
  const double density = member(measured, "measured", "density", is_number, "a number").get<double>();
  const std::string& of = member(measured, "measured", "of", is_string, "a string").get_ref<const std::string&>();
  const nlohmann::json& fit = member(j, "", "fit", is_object, "an object");
  const std::string& parameter = member(fit, "fit", "parameter", is_string, "a string").get_ref<const std::string&>();
  const double value = member(fit, "fit", "value", is_number, "a number").get<double>();
  const nlohmann::json& band = member(fit, "fit", "band", is_band, "[low, high]");
  const std::string& scenario = member(j, "", "scenario_file", is_string, "a string").get_ref<const std::string&>();
  const std::string& protocol = member(j, "", "protocol", is_string, "a string").get_ref<const std::string&>();
  const auto seeds =
      member(
          j, "", "seeds", [](const nlohmann::json& v) { return v.is_number_unsigned(); }, "a count of seeds")
          .get<std::uint64_t>();
  c.fitted_to = fmt::format(
      "{} = {:.4g} (band {:.4g} to {:.4g}) fitted by aggpack calibrate --dem to the measured "
      "density {:.4g} of {} ({}; {}; {} seed{}) [{}]",
      parameter, value, band[0].get<double>(), band[1].get<double>(), density, of, scenario, protocol, seeds,
      seeds == 1 ? "" : "s", file.string());
  return c;
}

DemCalibrationFile read_dem_calibration(const std::filesystem::path& file) {
  return parse_dem_calibration(read_input_text(file, "the calibration"), file);
}

}  // namespace aggpack
