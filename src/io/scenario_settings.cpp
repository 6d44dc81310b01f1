// The plain settings' tables: [container], [analysis], [limits], [output] and [models].
#include <cstdint>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "scenario_tables.hpp"

namespace aggpack {

namespace {
// The names as a message lists them: "csv" and/or "vtp".
std::string quoted_names(const std::vector<std::string_view>& names, std::string_view separator) {
  std::string list;
  for (const std::string_view name : names) list += fmt::format("{}\"{}\"", list.empty() ? "" : separator, name);
  return list;
}
}  // namespace

Container read_container(const TomlSection& s) {
  s.allow_only({"shape", "side", "diameter", "height", "rim", "sides"});
  const ContainerShape shape = s.choice("shape", kContainerShapeNames).value_or(ContainerShape::Box);
  const auto height = [&] { return s.required(s.length("height"), "height", "a length such as \"24 in\""); };
  if (shape == ContainerShape::Box) {
    for (const std::string_view key : {"diameter", "rim"})
      if (s.has(key))
        s.fail(key, "only a cylinder (shape = \"cylinder\") has a diameter and a rim; expected side for a box");
    const double side = s.required(s.length("side"), "side", "a length such as \"12 in\"");
    const double box_height = height();
    const ContainerSides sides = s.choice("sides", kContainerSidesNames).value_or(ContainerSides::Walls);
    return Container::square(side, box_height, sides == ContainerSides::Periodic);
  }
  if (s.has("side"))
    s.fail("side", "a cylinder (shape = \"cylinder\") has no side; expected diameter (and height, rim)");
  if (s.choice("sides", kContainerSidesNames).value_or(ContainerSides::Walls) == ContainerSides::Periodic)
    s.fail("sides", "a cylinder has a wall all round and cannot be periodic; expected sides = \"walls\" or no key");
  const double diameter = s.required(s.length("diameter"), "diameter", "a length such as \"155 mm\"");
  Container c = Container::cylinder(diameter, height());
  c.rim = s.length("rim").value_or(c.height());
  if (c.rim > c.height())
    s.fail("rim", fmt::format("{:.6g} m is above the container's height ({:.6g} m); expected at most the height (the "
                              "walls above the rim are a collar)",
                              c.rim, c.height()));
  return c;
}

AnalysisSettings read_analysis(const TomlSection& s) {
  s.allow_only({"box_sides", "placement", "contact_tolerance", "slice_thickness", "shell_thickness"});
  AnalysisSettings a;
  a.box_sides = s.length_list("box_sides").value_or(std::vector<double>{});
  s.choice("placement", {"centered"});
  a.contact_tolerance = s.number("contact_tolerance", {0.0, 1.0, false, false}).value_or(a.contact_tolerance);
  a.slice_thickness = s.length("slice_thickness");
  a.shell_thickness = s.length("shell_thickness");
  return a;
}

RunLimits read_limits(const TomlSection& s) {
  s.allow_only({"max_particles", "max_memory_gib", "max_grid_cells", "max_input_file_gib", "max_profile_bins",
                "max_template_minutes"});
  RunLimits l;
  l.max_particles = static_cast<double>(s.integer("max_particles", 1, 4'000'000'000).value_or(
      static_cast<std::int64_t>(l.max_particles)));
  l.max_memory_gib = s.number("max_memory_gib", {0.0, 1e6, true, false});
  l.max_grid_cells = static_cast<double>(s.integer("max_grid_cells", 1, std::int64_t{1} << 31).value_or(
      static_cast<std::int64_t>(l.max_grid_cells)));
  l.max_input_file_gib = s.number("max_input_file_gib", {0.0, 1e6, true, false}).value_or(l.max_input_file_gib);
  l.max_profile_bins = static_cast<double>(s.integer("max_profile_bins", 1, 1'000'000'000).value_or(
      static_cast<std::int64_t>(l.max_profile_bins)));
  l.max_template_minutes =
      s.number("max_template_minutes", {0.0, 1e6, true, false}).value_or(l.max_template_minutes);
  return l;
}

OutputSettings read_output(const TomlSection& s, const std::filesystem::path& scenario_file) {
  s.allow_only({"directory", "formats", "vtp_encoding", "checkpoint", "checkpoint_every", "frame_interval"});
  OutputSettings o;
  o.directory = s.string("directory").value_or("out/" + scenario_file.stem().string());
  o.checkpoint = s.boolean("checkpoint").value_or(o.checkpoint);
  o.checkpoint_every = s.number("checkpoint_every", {0.0, 1e9, false, false}).value_or(o.checkpoint_every);
  o.frame_interval = s.number("frame_interval", {0.0, 1e9, true, false});
  if (const auto encoding = s.choice("vtp_encoding", {"binary", "ascii"}))
    o.vtp_encoding = *encoding == "ascii" ? VtpEncoding::Ascii : VtpEncoding::ZlibAppended;
  if (const auto formats = s.string_list("formats")) {
    o.csv = o.vtp = false;
    for (const auto& name : *formats) {
      const auto format = value_of(kOutputFormatNames, name);
      if (!format)
        s.fail("formats", fmt::format("unknown format \"{}\"; expected {} (summary.json is always written)", name,
                                      quoted_names(names_of(kOutputFormatNames), " and/or ")));
      format_flag(o, *format) = true;
    }
  }
  return o;
}

std::optional<std::filesystem::path> read_models(const TomlSection& s, const std::filesystem::path& scenario_file) {
  s.allow_only({"calibration"});
  const auto given = s.string("calibration");
  if (!given) return std::nullopt;
  std::filesystem::path path = *given;
  if (path.is_relative()) path = scenario_file.parent_path() / path;
  if (!std::filesystem::is_regular_file(path))
    s.fail("calibration", fmt::format("{} is not a file (a calibration written by aggpack calibrate; relative "
                                      "paths are from the scenario's folder)",
                                      path.string()));
  return path;
}

}  // namespace aggpack
