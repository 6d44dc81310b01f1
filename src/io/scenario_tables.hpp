#pragma once
// The scenario reader's pieces, one reader per TOML table, shared by its files (private to
// src/io): scenario.cpp reads the file and calls them in order, scenario_particles.cpp reads
// [particles], scenario_dynamics.cpp the stages' tables ([material], [dynamics], [deposition],
// [pour], [tapping]), scenario_settings.cpp the plain settings ([container], [analysis],
// [limits], [output], [models]), scenario_protocol.cpp [[protocol]]; scenario_json.cpp echoes it.
#include <array>
#include <filesystem>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "aggpack/core/enum_names.hpp"
#include "aggpack/io/material_file.hpp"
#include "aggpack/io/scenario.hpp"
#include "aggpack/io/toml_reader.hpp"

namespace aggpack {

inline constexpr NumberRange kFraction{0.0, 1.0, true, false};
inline constexpr NumberRange kPoissonRatio{-1.0, 0.5, true, true};

// container.sides: the Container keeps it as its `periodic` flag.
enum class ContainerSides { Walls, Periodic };
inline constexpr std::array kContainerSidesNames{EnumName<ContainerSides>{ContainerSides::Walls, "walls"},
                                                 EnumName<ContainerSides>{ContainerSides::Periodic, "periodic"}};

// output.formats: the files of the bed besides summary.json (OutputSettings' csv and vtp flags).
enum class OutputFormat { Csv, Vtp };
inline constexpr std::array kOutputFormatNames{EnumName<OutputFormat>{OutputFormat::Csv, "csv"},
                                               EnumName<OutputFormat>{OutputFormat::Vtp, "vtp"}};
// The flag of OutputSettings (or a const one) that says whether `format` is written. A switch
// without a default: a new format without its flag is a compile error (-Wswitch), not silently
// another format's flag.
template <class Settings>
auto& format_flag(Settings& o, OutputFormat format) {
  switch (format) {
    case OutputFormat::Csv: return o.csv;
    case OutputFormat::Vtp: return o.vtp;
  }
  throw std::logic_error("an output format without its flag");  // unreachable for a valid enumerator
}

// The input file that `key` names, from the scenario's folder: one that is not there is
// refused at the key, with the path it was looked for at (absolute) and the path as given.
std::filesystem::path input_file_at(const TomlSection& s, std::string_view key,
                                    const std::filesystem::path& scenario_dir, const std::string& given,
                                    std::string_view what);

// scenario_particles.cpp; `material_names` are the run's materials, in index order;
// `imports_beds`: the protocol has an import_lammps step (a file of the bed taken back, which
// the file tolerances then apply to with generated sizes too).
// A grading's keys (name, file, sieves or law; d_min, d_max, band), files from `dir`; the caller
// checks which keys its table allows (a scenario's component has material and shape besides).
GradingSource read_grading_source(const TomlSection& s, const std::filesystem::path& dir);
ParticleSource read_particles(const TomlSection& s, const std::filesystem::path& scenario_dir,
                              const Container& container, std::span<const std::string> material_names,
                              bool imports_beds);

// scenario_materials.cpp: [materials] (each NAME's keys over `base`, [material]), a component's
// `key` naming one of `names` (as its index), [[material_pairs]].
std::vector<NamedMaterial> read_named_materials(const TomlSection& table, const Material& base);
// The spring-dashpot rolling model needs a rolling_friction > 0 somewhere (InputError at [material]).
void check_rolling_resistance(const TomlSection& root, const Scenario& sc);
std::uint8_t material_index(const TomlSection& s, std::string_view key, std::span<const std::string> names);
// A component's `shape` table (scenario_grains.cpp); none: the component is of spheres.
std::optional<GrainShapeSpec> read_grain_shape(const TomlSection& component);
// A shape table itself (a component's `shape`, a material file's [shape]): its spec, and the
// named default it started from ("" when given by family).
struct ShapeTable {
  GrainShapeSpec spec;
  std::string name;
};
ShapeTable read_shape_table(const TomlSection& shape);
std::vector<MaterialPairCoefficients> read_material_pairs(const std::vector<TomlSection>& entries,
                                                          std::span<const std::string> names, RollingModel rolling);

// scenario_dynamics.cpp: [material] (or a [materials.NAME] table), its keys over `base` (its
// `file`, a material file, was applied before: apply_material_files).
Material read_material(const TomlSection& s, Material base = {});
// The particles' contact keys of [material] (not the density, the walls' or the rolling model's,
// which are the run's): youngs_modulus, poisson_ratio, friction_particle, friction_wall,
// restitution, rolling_friction, those given, over `c`. A material file's [contact] is these.
void read_contact_keys(const TomlSection& s, ContactParameters& c);
inline constexpr std::array<std::string_view, 6> kContactKeys{
    "youngs_modulus", "poisson_ratio", "friction_particle", "friction_wall", "restitution", "rolling_friction"};
// [dynamics]; its friction_model chooses the contact law of `material`.
DynamicsStage read_dynamics(const TomlSection& s, Material& material);
DepositionSettings read_deposition(const TomlSection& s, const Container& container);
PourSettings read_pour(const TomlSection& s);
TappingSettings read_tapping(const TomlSection& s);
RoddingSettings read_rodding(const TomlSection& s);
JiggingSettings read_jigging(const TomlSection& s);

// scenario_settings.cpp
Container read_container(const TomlSection& s);
AnalysisSettings read_analysis(const TomlSection& s);
RunLimits read_limits(const TomlSection& s);
OutputSettings read_output(const TomlSection& s, const std::filesystem::path& scenario_file);
// [models]: the calibration file's path (from the scenario's folder), when it gives one.
std::optional<std::filesystem::path> read_models(const TomlSection& s, const std::filesystem::path& scenario_file);

// scenario_json.cpp: pieces of the echo that a material file's JSON shares.
nlohmann::json material_json(const Material& m);
nlohmann::json grading_source_json(const GradingSource& gs);
// scenario.cpp: a TOML file's text parsed (InputError file:line:column for a syntax error).
toml::table parse_toml(std::string_view text, const std::filesystem::path& file);
// A TOML value as JSON's (a date or time as its TOML text).
nlohmann::json json_of(const toml::node& node);
// A material file named by [material] or a [materials.NAME] table (`file`): its contact keys and
// oven-dry particle density written into the table where the table does not give them, and its
// grading and shape into each graded component that names the material and gives no grading.
// Refused at the key when the file cannot be read or `density` is given beside it.
void apply_material_files(toml::table& root, const std::filesystem::path& scenario_file, ScenarioOrigin& origin);
// material_file.cpp: a material file read and checked, with its TOML (what apply_material_files copies).
struct MaterialFileRead {
  AggregateMaterial material;
  toml::table root;
};
MaterialFileRead read_material_file(const std::filesystem::path& file);

// scenario_protocol.cpp: [[protocol]], the steps in order, checked against the tables of `sc`.
Protocol read_protocol(const TomlSection& root, const std::vector<TomlSection>& entries, const Scenario& sc);

}  // namespace aggpack
