// `[materials.NAME] file = "stone.toml"` (and `[material] file = ...`): a material file's values
// written into the scenario's tables before they are read, where the tables do not give them,
// so that the scenario's own readers and checks read them as if written there. What the table
// gives beside `file` (or a calibrated_by or --set assignment) wins over the file.
#include <filesystem>
#include <string>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "scenario_tables.hpp"

namespace aggpack {

namespace {

// Keys of a component's table that give its grading: one present, the component has its own.
constexpr std::array kGradingWays{"name", "file", "sieves", "law"};

struct FileMaterial {
  std::string name;  // the scenario's name of it: "default" for [material]
  std::filesystem::path path;
  MaterialFileRead read;
};

// The material file a table names, read and checked (its errors at the table's `file`).
FileMaterial load_named_file(const TomlSection& table, const std::string& name, const std::filesystem::path& dir) {
  const std::string given = *table.string("file");
  const std::filesystem::path path = input_file_at(table, "file", dir, given, "the material file");
  if (table.has("density"))
    table.fail("density", fmt::format("the density is the material file's ({}: its oven-dry specific gravity x {} "
                                      "kg/m3); remove it here, or give another specific_gravity in the file",
                                      given, kWaterDensityAt23C));
  try {
    return {name, path, read_material_file(path)};
  } catch (const InputError& e) {
    table.fail("file", e.what());
  }
}

// Writes `key` = `value` into `table` unless it has the key; messages about it name `source`.
void write_missing(toml::table& table, const std::string& table_path, std::string_view key, const toml::node& value,
                   const std::string& source, ScenarioOrigin& origin) {
  if (table.contains(key)) return;
  table.insert(key, value);
  origin.overrides[table_path + "." + std::string(key)] = source;
}

// The material's density and contact keys into its scenario table.
void write_material(toml::table& table, const std::string& table_path, const FileMaterial& m, ScenarioOrigin& origin) {
  const std::string source = fmt::format("{} (the material file of {})", m.path.string(), table_path);
  write_missing(table, table_path, "density", toml::value<double>(m.read.material.material.density), source, origin);
  if (const toml::table* contact = m.read.root["contact"].as_table())
    for (const auto& [key, value] : *contact) write_missing(table, table_path, key.str(), value, source, origin);
}

// A graded component that names a file's material and gives no grading takes the file's
// grading (its file's path made absolute: it was relative to the material file) and, when it
// gives no shape, the file's shape.
void write_component(toml::table& component, const std::string& path, const FileMaterial& m, ScenarioOrigin& origin) {
  for (const char* way : kGradingWays)
    if (component.contains(way)) return;
  const std::string source = fmt::format("{} (the material file of material \"{}\")", m.path.string(), m.name);
  if (const toml::table* grading = m.read.root["grading"].as_table())
    for (const auto& [key, value] : *grading) {
      if (key.str() == "file" && value.is_string()) {
        const std::filesystem::path csv = m.path.parent_path() / value.as_string()->get();
        write_missing(component, path, "file", toml::value<std::string>(std::filesystem::absolute(csv).string()),
                      source, origin);
      } else {
        write_missing(component, path, key.str(), value, source, origin);
      }
    }
  if (const toml::node* shape = m.read.root.get("shape")) write_missing(component, path, "shape", *shape, source, origin);
}

}  // namespace

void apply_material_files(toml::table& root, const std::filesystem::path& scenario_file, ScenarioOrigin& origin) {
  const std::filesystem::path dir = scenario_file.parent_path();
  std::vector<FileMaterial> files;
  const TomlSection s(root, "", origin);
  if (toml::table* material = root["material"].as_table(); material && material->contains("file")) {
    files.push_back(load_named_file(*s.table("material"), "default", dir));
    write_material(*material, "material", files.back(), origin);
  }
  if (toml::table* materials = root["materials"].as_table())
    for (auto& [key, node] : *materials) {
      toml::table* table = node.as_table();
      if (!table || !table->contains("file")) continue;
      const std::string name(key.str());
      files.push_back(load_named_file(*s.table("materials")->table(name), name, dir));
      write_material(*table, "materials." + name, files.back(), origin);
    }
  if (files.empty()) return;
  toml::table* particles = root["particles"].as_table();
  if (!particles) return;
  for (const char* part : {"grading", "coarse", "fine"}) {
    toml::table* component = (*particles)[part].as_table();
    const toml::node* named = component ? component->get("material") : nullptr;
    if (!named || !named->is_string()) continue;
    for (const FileMaterial& m : files)
      if (m.name == named->as_string()->get())
        write_component(*component, std::string("particles.") + part, m, origin);
  }
}

}  // namespace aggpack
