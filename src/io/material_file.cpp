// A material file (include/aggpack/io/material_file.hpp): its keys read by the scenario's own
// readers of a grading, a shape table and [material]'s contact keys, and the checks of a lab's
// numbers against what an aggregate can be.
#include "aggpack/io/material_file.hpp"

#include <charconv>
#include <cmath>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/core/input_file.hpp"
#include "aggpack/core/text.hpp"
#include "scenario_tables.hpp"

namespace aggpack {

namespace {

// Bulk specific gravities of aggregates: from lightweight ones (expanded shale, clay, slate;
// some 1.0 to 1.8) to heavyweight ones (barite, magnetite, hematite; up to some 4.6).
constexpr double kLeastSpecificGravity = 1.0, kMostSpecificGravity = 5.0;
constexpr NumberRange kAbsorption{0.0, 30.0, false, false};
// A bulk density below this fraction of the solid's is no aggregate in a measure (voids > 80 %).
constexpr double kLeastBulkFraction = 0.2;
// Uncompacted voids of fine aggregates by C1252 lie within some 38 to 52 %; a value outside
// 25 to 65 % is a slip (a fraction for a percent, a packing fraction for the voids).
constexpr double kLeastPlausibleVoids = 25.0, kMostPlausibleVoids = 65.0;

struct DensityUnit {
  std::string_view symbol;
  double kg_per_m3;
};
constexpr std::array kDensityUnits{DensityUnit{"kg/m3", 1.0},     DensityUnit{"kg/m^3", 1.0},
                                   DensityUnit{"lb/ft3", kKgPerM3PerLbPerFt3},
                                   DensityUnit{"lb/ft^3", kKgPerM3PerLbPerFt3},
                                   DensityUnit{"pcf", kKgPerM3PerLbPerFt3}, DensityUnit{"g/cm3", 1000.0},
                                   DensityUnit{"t/m3", 1000.0}};

// "1580 kg/m3", "98.6 lb/ft3", or a bare number (kg/m3); none when the text is not one.
std::optional<double> parse_density(std::string_view text) {
  text = trim(text);
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || !std::isfinite(value)) return std::nullopt;
  const std::string_view unit = trim(std::string_view(end, static_cast<std::size_t>(text.data() + text.size() - end)));
  if (unit.empty()) return value;
  for (const DensityUnit& u : kDensityUnits)
    if (unit == u.symbol) return value * u.kg_per_m3;
  return std::nullopt;
}

// A density key: a number (kg/m3) or a string with its unit.
double read_density(const TomlSection& s, const toml::node& node, std::string_view key) {
  if (node.is_number()) return *s.number(key, kPositive);
  const std::optional<double> value = parse_density(s.required(s.string(key), key, "a density"));
  if (!value || !(*value > 0.0))
    s.fail(key, fmt::format("\"{}\" is not a density; expected a positive number in kg/m3, or a string with its unit: "
                            "\"1580 kg/m3\", \"98.6 lb/ft3\" (also kg/m^3, lb/ft^3, pcf, g/cm3, t/m3)",
                            *s.string(key)));
  return *value;
}

void read_specific_gravity(const TomlSection& s, AggregateMaterial& m) {
  const double sg = s.required(s.number("specific_gravity", {}), "specific_gravity",
                               "the bulk specific gravity (relative density) of ASTM C127 or C128, such as 2.65");
  if (!(sg >= kLeastSpecificGravity && sg <= kMostSpecificGravity))
    s.fail("specific_gravity",
           fmt::format("{:g} is no aggregate's bulk specific gravity; expected {} to {} (lightweight aggregates from "
                       "about 1.0, normal-weight 2.4 to 2.9, heavyweight such as barite or magnetite up to 5)",
                       sg, kLeastSpecificGravity, kMostSpecificGravity));
  m.specific_gravity = sg;
  m.basis = s.choice("specific_gravity_basis", kSpecificGravityBasisNames).value_or(SpecificGravityBasis::OvenDry);
  m.absorption_percent = s.number("absorption_percent", kAbsorption);
  if (m.basis == SpecificGravityBasis::SaturatedSurfaceDry && !m.absorption_percent)
    s.missing("absorption_percent",
              "the absorption (percent of the oven-dry mass, ASTM C127 / C128) with specific_gravity_basis = \"ssd\": "
              "it turns the SSD specific gravity into the oven-dry one that densities and voids use");
}

void read_c29(const TomlSection& c29, const toml::node& table, AggregateMaterial& m) {
  c29.allow_only({"bulk_density", "method"});
  const toml::node* given = table.as_table()->get("bulk_density");
  if (!given) c29.missing("bulk_density", "the bulk density, such as \"1580 kg/m3\" or \"98.6 lb/ft3\"");
  LabBulkDensity lab;
  lab.kg_per_m3 = read_density(c29, *given, "bulk_density");
  lab.method = c29.required(c29.choice("method", kC29MethodNames), "method",
                            "how the measure was filled: \"shovelling\", \"rodding\" or \"jigging\"");
  const double solid = oven_dry_specific_gravity(m) * kWaterDensity;
  if (lab.kg_per_m3 >= solid)
    c29.fail("bulk_density", fmt::format("{:.1f} kg/m3 is at or above the density of the solid grains ({:.1f} kg/m3: "
                                         "oven-dry specific gravity {:.4g} x {} kg/m3): no voids or fewer; expected a "
                                         "bulk density below it (the specific gravity may be wrong)",
                                         lab.kg_per_m3, solid, oven_dry_specific_gravity(m), kWaterDensity));
  if (lab.kg_per_m3 < kLeastBulkFraction * solid)
    c29.fail("bulk_density", fmt::format("{:.1f} kg/m3 is below {:.0f} % of the solid's density ({:.1f} kg/m3), "
                                         "over {:.0f} % voids; expected a bulk density from {:.1f} to {:.1f} kg/m3 "
                                         "(a unit slip? a bare number is kg/m3)",
                                         lab.kg_per_m3, 100 * kLeastBulkFraction, solid,
                                         100 * (1 - kLeastBulkFraction), kLeastBulkFraction * solid, solid));
  m.c29 = lab;
}

void read_c1252(const TomlSection& c1252, AggregateMaterial& m) {
  c1252.allow_only({"voids_percent", "method"});
  LabUncompactedVoids lab;
  lab.percent = c1252.required(c1252.number("voids_percent", {0.0, 100.0, true, true}), "voids_percent",
                               "the uncompacted void content, percent, such as 44.5");
  if (lab.percent < kLeastPlausibleVoids || lab.percent > kMostPlausibleVoids)
    c1252.fail("voids_percent",
               fmt::format("{:g} % is not a plausible uncompacted void content; expected {:g} to {:g} % (fine "
                           "aggregates measure some 38 to 52 %; a packing fraction or a fraction for a percent?)",
                           lab.percent, kLeastPlausibleVoids, kMostPlausibleVoids));
  lab.method = c1252.required(c1252.choice("method", kC1252MethodNames), "method",
                              "the C1252 method: \"A\" (standard grading), \"B\" (single sizes) or \"C\" (as received)");
  m.c1252 = lab;
}

void read_lab(const TomlSection& lab, const toml::table& root, AggregateMaterial& m) {
  lab.allow_only({"c29", "c1252"});
  if (const auto c29 = lab.table("c29")) read_c29(*c29, *root.at_path("lab.c29").node(), m);
  if (const auto c1252 = lab.table("c1252")) read_c1252(*c1252, m);
}

AggregateMaterial read_material_table(const toml::table& root, const std::filesystem::path& file) {
  const ScenarioOrigin origin{file.string(), {}, "the material file"};
  const TomlSection s(root, "", origin);
  s.allow_only({"name", "notes", "specific_gravity", "specific_gravity_basis", "absorption_percent", "grading", "shape",
                "contact", "lab", "calibration"});
  AggregateMaterial m;
  m.file = file;
  m.name = s.string("name").value_or(file.stem().string());
  m.notes = s.string("notes").value_or("");
  read_specific_gravity(s, m);
  const TomlSection grading = s.required(s.table("grading"), "grading",
                                         "a [grading] table: the sieve analysis (file, name, sieves or law)");
  grading.allow_only({"name", "file", "length_unit", "percent_column", "sieves", "law", "law_d_max", "q", "law_d_min",
                      "d_min", "d_max", "band"});
  m.grading = read_grading_source(grading, file.parent_path());
  m.shape_name = "spheres";
  if (const auto shape = s.table("shape")) {
    ShapeTable read = read_shape_table(*shape);
    m.shape = read.spec;
    m.shape_name = read.name;
  }
  m.material.density = oven_dry_particle_density(m);
  if (const auto contact = s.table("contact")) {
    contact->allow_only(kContactKeys);
    read_contact_keys(*contact, m.material.contact);
  }
  if (const auto lab = s.table("lab")) read_lab(*lab, root, m);
  if (s.table("calibration")) m.calibration = json_of(*root.get("calibration"));
  return m;
}

}  // namespace

namespace {
// The calibration `aggpack calibrate --test` appended: its [calibration.contact] values take the
// place of [contact]'s, so that every reader of the file's contact keys sees the fitted ones.
toml::table with_calibration(toml::table root) {
  const toml::table* fitted = root.at_path("calibration.contact").as_table();
  if (!fitted) return root;
  if (!root["contact"].as_table()) root.insert("contact", toml::table{});
  toml::table& contact = *root["contact"].as_table();
  for (const auto& [key, value] : *fitted) contact.insert_or_assign(key, value);
  return root;
}
}  // namespace

MaterialFileRead read_material_file(const std::filesystem::path& file) {
  // A material file is a page of TOML: 1 MiB is far beyond any real one.
  const std::string text = read_input_text(file, "the material file", std::uintmax_t{1} << 20);
  MaterialFileRead read{{}, with_calibration(parse_toml(text, file))};
  read.material = read_material_table(read.root, file);
  return read;
}

AggregateMaterial load_material_file(const std::filesystem::path& file) { return read_material_file(file).material; }

bool looks_like_material_file(const std::filesystem::path& file) {
  if (file.extension() != ".toml" || !std::filesystem::is_regular_file(file)) return false;
  try {
    return parse_toml(read_input_text(file, "the file", std::uintmax_t{1} << 20), file).contains("specific_gravity");
  } catch (const std::exception&) {
    return false;  // not TOML: the scenario's reader says what is wrong with it
  }
}

AggregateMaterial parse_material_file(std::string_view text, const std::filesystem::path& file) {
  return read_material_table(with_calibration(parse_toml(text, file)), file);
}

toml::table material_file_tables(const std::filesystem::path& file) { return read_material_file(file).root; }

double oven_dry_specific_gravity(const AggregateMaterial& m) {
  // C127: SG(SSD) = B / (B - C), SG(OD) = A / (B - C), absorption = (B - A) / A: OD = SSD / (1 + absorption).
  if (m.basis == SpecificGravityBasis::OvenDry) return m.specific_gravity;
  return m.specific_gravity / (1.0 + m.absorption_percent.value_or(0.0) / 100.0);
}

double oven_dry_particle_density(const AggregateMaterial& m) {
  return oven_dry_specific_gravity(m) * kWaterDensityAt23C;
}

double voids_percent(const AggregateMaterial& m, double bulk_density_kg_m3) {
  return 100.0 * (1.0 - bulk_density_kg_m3 / (oven_dry_specific_gravity(m) * kWaterDensity));
}

}  // namespace aggpack
