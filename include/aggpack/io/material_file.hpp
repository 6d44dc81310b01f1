#pragma once
// A material file: one aggregate as a lab describes it, kept and reused across scenarios. Its
// specific gravity (and basis), its sieve analysis, its grains' shape, its contact parameters
// for the DEM, and the lab's own packing tests on it: the bulk density of ASTM C29 (AASHTO
// T 19) and the uncompacted voids of ASTM C1252 (AASHTO T 304). README.md, "Materials: one
// file per aggregate", lists its keys.
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>
#include <toml++/toml.h>

#include "aggpack/core/enum_names.hpp"
#include "aggpack/grains/grain_library.hpp"
#include "aggpack/io/scenario.hpp"

namespace aggpack {

// ASTM C29's three ways of filling the measure.
enum class C29Method { Shovelling, Rodding, Jigging };
inline constexpr std::array kC29MethodNames{EnumName<C29Method>{C29Method::Shovelling, "shovelling"},
                                            EnumName<C29Method>{C29Method::Rodding, "rodding"},
                                            EnumName<C29Method>{C29Method::Jigging, "jigging"}};
// ASTM C1252's methods: A, the standard grading; B, three single-size fractions; C, as received.
enum class C1252Method { A, B, C };
inline constexpr std::array kC1252MethodNames{EnumName<C1252Method>{C1252Method::A, "A"},
                                              EnumName<C1252Method>{C1252Method::B, "B"},
                                              EnumName<C1252Method>{C1252Method::C, "C"}};
// The basis of a bulk specific gravity (ASTM C127 / C128): oven-dry, or saturated surface-dry.
enum class SpecificGravityBasis { OvenDry, SaturatedSurfaceDry };
inline constexpr std::array kSpecificGravityBasisNames{
    EnumName<SpecificGravityBasis>{SpecificGravityBasis::OvenDry, "oven_dry"},
    EnumName<SpecificGravityBasis>{SpecificGravityBasis::SaturatedSurfaceDry, "ssd"}};

// ASTM C29 / AASHTO T 19: the bulk density of the aggregate in the measure, oven-dry.
struct LabBulkDensity {
  double kg_per_m3 = 0;
  C29Method method = C29Method::Rodding;
};
// ASTM C1252 / AASHTO T 304: the uncompacted void content of a fine aggregate.
struct LabUncompactedVoids {
  double percent = 0;
  C1252Method method = C1252Method::A;
};

struct AggregateMaterial {
  std::filesystem::path file;
  std::string name;
  std::string notes;
  double specific_gravity = 0;  // bulk specific gravity (relative density), as given, on `basis`
  SpecificGravityBasis basis = SpecificGravityBasis::OvenDry;
  std::optional<double> absorption_percent;  // turns an SSD value into oven-dry
  GradingSource grading;                     // the material's sieve analysis, cut-offs optional
  std::optional<GrainShapeSpec> shape;       // none: spheres
  std::string shape_name;  // the named default used; "" when given by family; "spheres" with no [shape]
  Material material;       // density: the oven-dry particle density (kg/m3); the contact parameters
  std::optional<LabBulkDensity> c29;
  std::optional<LabUncompactedVoids> c1252;
  nlohmann::json calibration;  // [calibration] as read (aggpack calibrate writes it), or null
};

// The density of water of ASTM C29/C29M's void content, Voids % = 100 [(S W) - B] / (S W), with
// W = 998 kg/m3 [62.3 lb/ft3] (section "Calculation", Void Content).
inline constexpr double kWaterDensity = 998.0;  // kg/m3
// The density of water ASTM C127 and C128 turn a relative density into a density with
// (water at 23 °C): density (OD) = 997.5 kg/m3 x relative density (OD).
inline constexpr double kWaterDensityAt23C = 997.5;  // kg/m3
// 1 lb/ft3 in kg/m3 (0.45359237 kg / 0.3048^3 m3), exact by the definitions of the pound and foot.
inline constexpr double kKgPerM3PerLbPerFt3 = 0.45359237 / (0.3048 * 0.3048 * 0.3048);

// Whether a file is a material file rather than a scenario: TOML with a top-level
// specific_gravity (which a scenario never has). False for a file that is not TOML.
[[nodiscard]] bool looks_like_material_file(const std::filesystem::path& file);

// Reads and checks a material file. InputError naming file:line:key, what is wrong and what is
// expected. Relative paths in it (a grading's file) are taken from its folder.
AggregateMaterial load_material_file(const std::filesystem::path& file);
AggregateMaterial parse_material_file(std::string_view text, const std::filesystem::path& file);
// The file's tables as a run takes them: its [calibration.contact] values (aggpack calibrate
// --test) in place of [contact]'s. Checked as load_material_file checks them.
toml::table material_file_tables(const std::filesystem::path& file);

// The bulk specific gravity on the oven-dry basis: as given, or SSD / (1 + absorption).
[[nodiscard]] double oven_dry_specific_gravity(const AggregateMaterial& m);
// The oven-dry particle density, kg/m3: oven_dry_specific_gravity x kWaterDensityAt23C (C127).
[[nodiscard]] double oven_dry_particle_density(const AggregateMaterial& m);
// ASTM C29's void content of a bed of this bulk density (kg/m3), percent:
// 100 (1 - BD / (SG_od x kWaterDensity)). The packing fraction is 1 - voids / 100.
[[nodiscard]] double voids_percent(const AggregateMaterial& m, double bulk_density_kg_m3);

// Everything `aggpack material --json` prints: the values as read, the oven-dry particle
// density, the grading's summary (nominal maximum size, fineness modulus, the sieves), the
// shape, the contact parameters, the lab results with their voids and packing fractions.
nlohmann::json to_json(const AggregateMaterial& m);
// The same for a reader: the lines `aggpack material` prints.
std::string describe(const AggregateMaterial& m);

}  // namespace aggpack
