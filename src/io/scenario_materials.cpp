// [materials.NAME] and [[material_pairs]]: the materials of a run beside [material], and the
// coefficients of pairs of them that do not follow the mixing rule.
#include <algorithm>
#include <span>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "aggpack/core/error.hpp"
#include "scenario_tables.hpp"

namespace aggpack {

namespace {

// Materials are bytes in the particle store; LAMMPS gets two atom types and a group of each,
// and holds at most 32 groups (two are its own `all` and aggpack's `mobile`).
constexpr std::size_t kMostMaterials = 30;

bool is_plain_name(const std::string& name) {
  return !name.empty() && name.size() <= 64 && std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
  });
}

}  // namespace

std::vector<NamedMaterial> read_named_materials(const TomlSection& table, const Material& base) {
  std::vector<NamedMaterial> materials;
  for (const std::string& name : table.keys()) {
    if (!is_plain_name(name) || name == "default")
      table.fail(name, "a material's name is made of letters, digits and '_' (at most 64: it names LAMMPS groups and "
                       "fixes), and is not \"default\" (the [material] table's own name)");
    const TomlSection s =
        table.required(table.table(name), name, fmt::format("a table [{}] of the material's keys", table.key_path(name)));
    for (const char* k : {"wall_youngs_modulus", "wall_poisson_ratio"})
      if (s.has(k)) s.fail(k, "the walls are the container's, one for every material: give it in [material]");
    if (s.has("rolling_model"))
      s.fail("rolling_model", "one rolling model for the run: give it in [material] (each material may give its "
                              "own rolling_friction, rolling_stiffness and rolling_damping)");
    materials.push_back({name, read_material(s, base)});
  }
  if (materials.size() + 1 > kMostMaterials)
    table.fail(materials[kMostMaterials - 1].name, fmt::format("at most {} materials, [material] included", kMostMaterials));
  return materials;
}

void check_rolling_resistance(const TomlSection& root, const Scenario& sc) {
  if (sc.material.contact.rolling_model != RollingModel::SpringDashpot) return;
  for (std::size_t k = 0; k < material_count(sc); ++k)
    if (material_of(sc, k).contact.rolling_friction > 0.0) return;
  const TomlSection material = *root.table("material");
  material.fail("rolling_friction", "must be > 0 with rolling_model = \"spring_dashpot\" (it caps the rolling "
                                    "torque), in [material] or a [materials.NAME] table");
}

std::uint8_t material_index(const TomlSection& s, std::string_view key, std::span<const std::string> names) {
  const std::string name = *s.string(key);
  const auto found = std::find(names.begin(), names.end(), name);
  if (found == names.end())
    s.fail(key, fmt::format("no material is named \"{}\"; expected \"default\" ([material]){}", name,
                            names.size() > 1 ? fmt::format(" or one of [materials]: \"{}\"",
                                                           fmt::join(names.subspan(1), "\", \""))
                                             : std::string(", or a [materials.NAME] table of that name")));
  return static_cast<std::uint8_t>(found - names.begin());
}

std::vector<MaterialPairCoefficients> read_material_pairs(const std::vector<TomlSection>& entries,
                                                          std::span<const std::string> names, RollingModel rolling) {
  std::vector<MaterialPairCoefficients> pairs;
  for (const TomlSection& e : entries) {
    e.allow_only({"materials", "friction", "restitution", "rolling_friction", "rolling_stiffness", "rolling_damping"});
    const auto pair = e.required(e.string_list("materials"), "materials", "two material names, such as [\"stone\", \"sand\"]");
    if (pair.size() != 2) e.fail("materials", fmt::format("expected two material names, got {}", pair.size()));
    MaterialPairCoefficients p;
    for (std::size_t k = 0; k < 2; ++k) {
      const auto found = std::find(names.begin(), names.end(), pair[k]);
      if (found == names.end())
        e.fail("materials", fmt::format("no material is named \"{}\"; the materials are \"{}\"", pair[k],
                                        fmt::join(names, "\", \"")));
      (k == 0 ? p.first : p.second) = static_cast<std::uint8_t>(found - names.begin());
    }
    if (p.first == p.second)
      e.fail("materials", fmt::format("\"{}\" against itself is the material's own table: give its values there",
                                      pair[0]));
    if (p.first > p.second) std::swap(p.first, p.second);
    for (const MaterialPairCoefficients& q : pairs)
      if (q.first == p.first && q.second == p.second)
        e.fail("materials", fmt::format("the pair \"{}\", \"{}\" is given twice", pair[0], pair[1]));
    p.friction = e.number("friction", kNonNegative);
    p.restitution = e.number("restitution", kFraction);
    p.rolling_friction = e.number("rolling_friction", kNonNegative);
    for (const char* k : {"rolling_stiffness", "rolling_damping"})
      if (rolling != RollingModel::SpringDashpot && e.has(k))
        e.fail(k, "applies only with rolling_model = \"spring_dashpot\" (in [material])");
    p.rolling_stiffness = e.number("rolling_stiffness", kPositive);
    p.rolling_damping = e.number("rolling_damping", kNonNegative);
    if (!p.friction && !p.restitution && !p.rolling_friction && !p.rolling_stiffness && !p.rolling_damping)
      e.fail("materials", "the pair gives no coefficient: expected friction, restitution, rolling_friction, "
                          "rolling_stiffness or rolling_damping");
    pairs.push_back(p);
  }
  return pairs;
}

const Material& material_of(const Scenario& sc, std::size_t index) {
  return index == 0 ? sc.material : sc.materials.at(index - 1).material;
}

std::string material_name(const Scenario& sc, std::size_t index) {
  return index == 0 ? std::string("default") : sc.materials.at(index - 1).name;
}

std::vector<std::size_t> used_materials(const Scenario& sc) {
  std::vector<std::size_t> used;
  for (std::size_t k = 0; k < material_count(sc); ++k) {
    const auto& of = sc.particles.component_material;
    if ((of.empty() && k == 0) || std::find(of.begin(), of.end(), k) != of.end()) used.push_back(k);
  }
  return used;
}

std::vector<double> material_densities(const Scenario& sc) {
  std::vector<double> densities;
  for (std::size_t k = 0; k < material_count(sc); ++k) densities.push_back(material_of(sc, k).density);
  return densities;
}

void assign_file_materials(ParticleStore& particles, const std::vector<std::string>& names, const Scenario& sc,
                           const std::string& file) {
  if (names.empty()) return;
  if (names.size() != particles.size())
    throw InputError(fmt::format("{}: {} material names for {} spheres", file, names.size(), particles.size()));
  for (std::size_t i = 0; i < names.size(); ++i) {
    std::size_t k = 0;
    while (k < material_count(sc) && material_name(sc, k) != names[i]) ++k;
    if (k == material_count(sc))
      throw InputError(fmt::format("{}: sphere {} (row {} of the data) is of material \"{}\", which the scenario does "
                                   "not name; expected \"default\" or a [materials.NAME] of the scenario",
                                   file, i + 1, i + 1, names[i]));
    particles.material[i] = static_cast<std::uint8_t>(k);
    particles.mass[i] = ParticleStore::sphere_mass(particles.radius[i], material_of(sc, k).density);
  }
}

std::vector<ContactParameters> material_contacts(const Scenario& sc) {
  std::vector<ContactParameters> contacts;
  for (std::size_t k = 0; k < material_count(sc); ++k) contacts.push_back(material_of(sc, k).contact);
  return contacts;
}

}  // namespace aggpack
