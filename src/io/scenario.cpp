// The scenario reader's entry points: the file's text parsed, the --set overrides applied, and
// each table read in order (by the readers of scenario_tables.hpp), then the checks that need
// several tables.
#include "aggpack/io/scenario.hpp"

#include <algorithm>
#include <map>
#include <sstream>
#include <limits>

#include <unistd.h>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/core/input_file.hpp"
#include "aggpack/io/toml_reader.hpp"
#include "aggpack/sizes/grading.hpp"
#include "scenario_tables.hpp"

namespace aggpack {

namespace {
// Applies "a.b.c=value" to the table; the value is TOML, or a bare string. Messages about the
// key quote `typed`, the option as the user typed it.
void apply_override(toml::table& root, const std::string& assignment, const std::string& typed,
                    ScenarioOrigin& origin) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError(fmt::format("--set {}: expected key.path=value, for example --set container.side=\"10 in\"",
                                 assignment));
  const std::string key = assignment.substr(0, eq);
  const std::string value_text = assignment.substr(eq + 1);
  toml::table parsed;
  try {
    parsed = toml::parse("value = " + value_text);
  } catch (const toml::parse_error&) {
    parsed = toml::table{{"value", value_text}};  // a bare word such as periodic
  }
  toml::table* table = &root;
  std::size_t start = 0;
  for (std::size_t dot = key.find('.'); dot != std::string::npos; dot = key.find('.', start)) {
    const std::string part = key.substr(start, dot - start);
    toml::node* child = table->get(part);
    if (!child) child = &table->insert_or_assign(part, toml::table{}).first->second;
    if (!child->is_table())
      throw InputError(fmt::format("--set {}: '{}' is not a table in the scenario", assignment, key.substr(0, dot)));
    table = child->as_table();
    start = dot + 1;
  }
  const std::string leaf = key.substr(start);
  if (leaf.empty()) throw InputError(fmt::format("--set {}: the key ends with '.'", assignment));
  table->insert_or_assign(leaf, *parsed.get("value"));
  origin.overrides[key] = typed;
}

std::filesystem::path relative_to(const std::filesystem::path& dir, const std::string& file) {
  return std::filesystem::path(file).is_absolute() ? std::filesystem::path(file) : dir / file;
}

// calibrated_by: a DEM calibration file or a list of them (relative to the scenario's folder).
// Each one's assignments replace the scenario's values, after --set. A key given two values (by
// two files, or by a file and --set) is refused: which one is meant cannot be known.
std::vector<DemCalibrationFile> apply_calibrations(toml::table& root, const TomlSection& s,
                                                   const std::filesystem::path& file, ScenarioOrigin& origin) {
  if (!s.has("calibrated_by")) return {};
  const toml::node* given = root.get("calibrated_by");
  const std::vector<std::string> names =
      given->is_string() ? std::vector<std::string>{*s.string("calibrated_by")} : *s.string_list("calibrated_by");
  std::map<std::string, std::string> set_by = origin.overrides;  // key -> what set it
  std::vector<DemCalibrationFile> applied;
  for (const std::string& name : names) {
    const std::filesystem::path path = relative_to(file.parent_path(), name);
    DemCalibrationFile calibration;
    try {
      calibration = read_dem_calibration(path);
    } catch (const InputError& e) {
      s.fail("calibrated_by", e.what());
    }
    for (const std::string& assignment : calibration.assignments) {
      const std::string key = assignment.substr(0, assignment.find('='));
      if (key.starts_with("materials.")) {
        const std::string material = key.substr(10, key.rfind('.') - 10);
        const toml::table* materials = root.get("materials") ? root.get("materials")->as_table() : nullptr;
        if (!materials || !materials->get(material))
          s.fail("calibrated_by", fmt::format("{} sets {}, but this scenario has no [materials.{}]: it calibrated "
                                              "another scenario's materials",
                                              path.string(), key, material));
      }
      if (const auto other = set_by.find(key); other != set_by.end())
        s.fail("calibrated_by", fmt::format("{} sets {}, which {} sets too: give each key one value", path.string(),
                                            key, other->second));
      const std::string typed = "calibrated_by " + path.string();
      apply_override(root, assignment, typed, origin);
      set_by[key] = typed;
    }
    applied.push_back(std::move(calibration));
  }
  return applied;
}

// The file's seed, checked even when --seed replaces it.
std::uint64_t read_seed(const TomlSection& s, const std::filesystem::path& file, const ScenarioOverrides& overrides) {
  const auto seed =
      static_cast<std::uint64_t>(s.integer("seed", 0, std::numeric_limits<std::int64_t>::max()).value_or(1));
  if (!overrides.seed) return seed;
  // The file's range, so that no seed reads back as another (2^64 - 1 as -1 in a signed reader).
  if (*overrides.seed > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
    throw InputError(fmt::format("{}: seed {}: expected an integer from 0 to {}", file.string(), *overrides.seed,
                                 std::numeric_limits<std::int64_t>::max()));
  return *overrides.seed;
}

// [deposition], [pour], [tapping] and [dynamics], with the checks of each against the others.
void read_stages(const TomlSection& s, Scenario& sc) {
  if (const auto d = s.table("deposition")) {
    if (sc.container.is_cylinder())
      s.fail("deposition", "container.shape = \"cylinder\": drop-and-roll deposition needs a box (its walls are "
                           "planes); pour the particles instead ([pour], [dynamics] and, with [[protocol]], a pour "
                           "step)");
    sc.deposition = read_deposition(*d, sc.container);
  }
  if (const auto p = s.table("pour")) sc.pour = read_pour(*p);
  if (const auto t = s.table("tapping")) {
    sc.tapping = read_tapping(*t);
    if (!s.table("dynamics"))
      s.fail("tapping", "tapping moves the bed through the DEM with the [dynamics] settings; add a [dynamics] "
                        "table (it may be empty)");
  }
  for (const char* name : {"rodding", "jigging"}) {
    const auto t = s.table(name);
    if (!t) continue;
    if (name == std::string_view("rodding")) sc.rodding = read_rodding(*t);
    else sc.jigging = read_jigging(*t);
    if (!s.table("dynamics"))
      s.fail(name, fmt::format("{} moves the bed through the DEM with the [dynamics] settings; add a [dynamics] "
                               "table (it may be empty)", name));
  }
  if (const auto d = s.table("dynamics")) {
    sc.dynamics = read_dynamics(*d, sc.material);
    if (sc.dynamics->layers > 1 && sc.pour)
      d->fail("layers", "a pour settles as it goes; to pour in parts, give [[protocol]] pour steps with layer and "
                        "layers, and expected layers = 1 here");
    if (sc.dynamics->engine == DemEngine::Lammps)
      for (const char* name : {"rodding", "jigging"})
        if (s.table(name))
          s.fail(name, fmt::format("{} runs in aggpack's own DEM only (no LAMMPS deck moves a rod or drops the "
                                   "measure); expected dynamics.engine = \"aggpack\"", name));
    if (sc.dynamics->engine == DemEngine::Lammps && sc.pour && sc.pour->release_height)
      s.fail("pour.release_height",
             "the pour's release height is aggpack's own DEM's (the LAMMPS deck lets its "
             "batches in at pour.velocity); expected dynamics.engine = \"aggpack\", or "
             "pour.velocity instead");
    if (sc.dynamics->layers > 1 && !sc.deposition)
      d->fail("layers", "layer by layer settling deposits each layer, so it needs a [deposition] table; "
                        "expected layers = 1 for a bed read from a file");
  }
}

// The largest diameter of the generated particles.
double largest_diameter(const Scenario& sc) {
  double d_max = 0.0;
  if (sc.particles.sizes)
    for (const auto& c : sc.particles.sizes->classes) d_max = std::max(d_max, c.diameter);
  if (const auto& g = sc.particles.graded) {
    d_max = cut_grading(g->main.grading, g->main.d_min, g->main.d_max, g->main.key).d_hi;
    if (g->fine) d_max = std::max(d_max, cut_grading(g->fine->grading, g->fine->d_min, g->fine->d_max, "").d_hi);
  }
  return d_max;
}

// Generated particles fit in the container and a stage places them; positions from a file
// have no stage that places particles.
void check_particles_placed(const TomlSection& s, const Scenario& sc) {
  if (sc.particles.sizes || sc.particles.graded) {
    const double d_max = largest_diameter(sc);
    const TomlSection particles = *s.table("particles");
    const std::string where = particles.location(particles.has("diameter")  ? "diameter"
                                                 : particles.has("classes") ? "classes"
                                                 : particles.has("grading") ? "grading"
                                                                            : "coarse");
    if (d_max >= sc.container.length_x())
      throw InputError(fmt::format("{}: particles: the largest diameter ({:.6g} m) does not fit in the container "
                                   "({} {:.6g} m)", where, d_max, sc.container.is_cylinder() ? "diameter" : "side",
                                   sc.container.length_x()));
    // The nearest periodic image must be unique within a roll's reach (two diameters each way).
    if (sc.container.periodic && sc.container.length_x() <= 4.0 * d_max)
      throw InputError(fmt::format("{}: container.side: with periodic sides the side ({:.6g} m) must exceed four "
                                   "times the largest diameter ({:.6g} m)", sc.file.string(), sc.container.length_x(),
                                   4.0 * d_max));
    if (!sc.deposition && !sc.pour)
      throw InputError(fmt::format("{}: particles are given by size but no stage places them; add a [deposition] "
                                   "or a [pour] table (it may be empty) or give positions with particles.from",
                                   where));
  } else if (sc.deposition) {
    s.table("deposition")->fail("method", "deposition places generated particles, but particles.from gives "
                                          "positions already; remove [deposition] or give sizes instead");
  } else if (sc.pour) {
    s.fail("pour", "a pour places generated particles, but particles.from gives positions already; remove [pour] "
                   "or give sizes instead");
  }
}

// The stages' order: [[protocol]] as given, and when none is, whether the default order is
// enough.
void read_order(const TomlSection& s, Scenario& sc) {
  if (sc.pour && !sc.dynamics)
    s.fail("pour", "a pour falls through the DEM with the [dynamics] settings; add a [dynamics] table (it may be "
                   "empty)");
  const auto steps = s.table_array("protocol");
  if (sc.pour && sc.deposition && !steps)
    s.fail("pour", "with both [deposition] and [pour], give the order of their steps as [[protocol]] (for example "
                   "deposit part 0 of 2, then pour part 1 of 2)");
  if (steps) sc.protocol = read_protocol(s, *steps, sc);
}
}  // namespace

toml::table parse_toml(std::string_view text, const std::filesystem::path& file) {
  try {
    return toml::parse(text, file.string());
  } catch (const toml::parse_error& e) {
    const auto& src = e.source();
    throw InputError(fmt::format("{}:{}:{}: TOML syntax error: {}", file.string(), src.begin.line,
                                 src.begin.column, e.description()));
  }
}

// The input file that `key` names, from the scenario's folder: one that is not there is
// refused at the key, with the path it was looked for at (absolute) and the path as given.
// (One that is there but is no regular file is refused when it is read, saying what it is.)
std::filesystem::path input_file_at(const TomlSection& s, std::string_view key,
                                    const std::filesystem::path& scenario_dir, const std::string& given,
                                    std::string_view what) {
  const std::filesystem::path path = relative_to(scenario_dir, given);
  std::error_code exists_error;
  if (!std::filesystem::exists(path, exists_error)) {
    std::error_code ec;
    const std::filesystem::path absolute = std::filesystem::absolute(path, ec);
    const std::string at = (ec ? path : absolute).lexically_normal().string();
    if (exists_error)  // a folder on the way that cannot be searched, say
      s.fail(key, fmt::format("{} \"{}\" cannot be looked for at {}: {}", what, given, at, exists_error.message()));
    s.fail(key, fmt::format("{} \"{}\" is not a file: looked for at {} (a relative path is taken from the scenario's "
                            "folder)",
                            what, given, at));
  }
  return path;
}

double memory_limit_bytes(const RunLimits& limits) {
  if (limits.max_memory_gib) return *limits.max_memory_gib * double(1u << 30);
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0 ? 0.8 * static_cast<double>(pages) * static_cast<double>(page) : 16.0 * (1u << 30);
}

std::string read_scenario_text(const std::filesystem::path& file) {
  // A scenario is a page of TOML: 16 MiB is far beyond any real one.
  return read_input_text(file, "the scenario", std::uintmax_t{16} << 20);
}

Scenario load_scenario(const std::filesystem::path& file, const ScenarioOverrides& overrides) {
  return parse_scenario(read_scenario_text(file), file, overrides);
}

namespace {

// The file's table with the command line's assignments applied (a calibrated_by among them
// refused when the file has one), as the readers then read it.
toml::table overridden_table(std::string_view text, const std::filesystem::path& file,
                             const ScenarioOverrides& overrides, ScenarioOrigin& origin) {
  toml::table root = parse_toml(text, file);
  // The command line's calibration files replace the scenario's list: refused rather than one
  // list silently dropped.
  for (const auto& assignment : overrides.set)
    if (assignment.starts_with("calibrated_by=") && root.contains("calibrated_by")) {
      const auto typed = overrides.typed_as.find(assignment);
      throw InputError(fmt::format("{}: the scenario has calibrated_by, and {} would replace it: name every "
                                   "calibration file in one place (the scenario's calibrated_by, or --calibration)",
                                   file.string(),
                                   typed != overrides.typed_as.end() ? typed->second : "--set " + assignment));
    }
  for (const auto& assignment : overrides.set) {
    const auto typed = overrides.typed_as.find(assignment);
    apply_override(root, assignment, typed != overrides.typed_as.end() ? typed->second : "--set " + assignment, origin);
  }
  return root;
}

}  // namespace

// A TOML value as JSON's (a date or time as its TOML text).
nlohmann::json json_of(const toml::node& node) {
  if (const auto* table = node.as_table()) {
    nlohmann::json j = nlohmann::json::object();
    for (const auto& [key, value] : *table) j[std::string(key.str())] = json_of(value);
    return j;
  }
  if (const auto* array = node.as_array()) {
    nlohmann::json j = nlohmann::json::array();
    for (const toml::node& value : *array) j.push_back(json_of(value));
    return j;
  }
  if (const auto* v = node.as_string()) return v->get();
  if (const auto* v = node.as_integer()) return v->get();
  if (const auto* v = node.as_floating_point()) return v->get();
  if (const auto* v = node.as_boolean()) return v->get();
  std::ostringstream text;
  node.visit([&](const auto& value) { text << value; });
  return text.str();
}

nlohmann::json scenario_keys(std::string_view text, const std::filesystem::path& file,
                             const ScenarioOverrides& overrides) {
  ScenarioOrigin origin{file.string(), {}};
  nlohmann::json keys = json_of(overridden_table(text, file, overrides, origin));
  if (overrides.seed) keys["seed"] = *overrides.seed;
  if (overrides.output_directory) keys["output"]["directory"] = overrides.output_directory->string();
  return keys;
}

Scenario parse_scenario(std::string_view text, const std::filesystem::path& file, const ScenarioOverrides& overrides) {
  ScenarioOrigin origin{file.string(), {}};
  toml::table root = overridden_table(text, file, overrides, origin);

  const TomlSection s(root, "", origin);
  s.allow_only({"title", "seed", "calibrated_by", "container", "particles", "material", "materials", "material_pairs",
                "analysis", "output", "deposition", "pour", "tapping", "rodding", "jigging", "dynamics", "protocol", "limits", "models"});

  Scenario sc;
  sc.file = file;
  sc.overrides = overrides.set;
  sc.calibrations = apply_calibrations(root, s, file, origin);
  apply_material_files(root, file, origin);
  sc.title = s.string("title").value_or(file.stem().string());
  sc.seed = read_seed(s, file, overrides);
  const TomlSection container = s.required(s.table("container"), "container", "a [container] table");
  sc.container = read_container(container);
  sc.written_length_unit = container.written_unit(sc.container.is_cylinder() ? "diameter" : "side").value_or("");
  if (sc.written_length_unit == "m") sc.written_length_unit.clear();
  if (const auto m = s.table("material")) sc.material = read_material(*m);
  if (const auto m = s.table("materials")) sc.materials = read_named_materials(*m, sc.material);
  check_rolling_resistance(s, sc);
  std::vector<std::string> material_names;
  for (std::size_t k = 0; k < material_count(sc); ++k) material_names.push_back(material_name(sc, k));
  if (const auto pairs = s.table_array("material_pairs")) sc.material_pairs = read_material_pairs(*pairs, material_names, sc.material.contact.rolling_model);
  bool imports_beds = false;  // an import_lammps step (its file's tolerances are [particles]')
  if (const auto steps = s.table_array("protocol"))
    for (const TomlSection& step : *steps) imports_beds = imports_beds || step.string("step") == "import_lammps";
  sc.particles = read_particles(s.required(s.table("particles"), "particles", "a [particles] table"),
                                file.parent_path(), sc.container, material_names, imports_beds);
  read_stages(s, sc);
  // One contact law for the run: [dynamics] chose it for [material].
  for (NamedMaterial& m : sc.materials) m.material.contact.friction_model = sc.material.contact.friction_model;
  if (const auto a = s.table("analysis")) sc.analysis = read_analysis(*a);
  if (const auto l = s.table("limits")) sc.limits = read_limits(*l);
  if (const auto m = s.table("models")) sc.models_calibration = read_models(*m, file);
  if (const auto o = s.table("output")) sc.output = read_output(*o, file);
  else sc.output.directory = "out/" + file.stem().string();
  if (overrides.output_directory) sc.output.directory = *overrides.output_directory;

  // Checks that need several tables.
  check_particles_placed(s, sc);
  read_order(s, sc);
  return sc;
}

}  // namespace aggpack
