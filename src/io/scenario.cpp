#include "aggpack/io/scenario.hpp"

#include <set>
#include <variant>

#include <unistd.h>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "aggpack/core/error.hpp"
#include "aggpack/core/input_file.hpp"
#include "aggpack/core/overloaded.hpp"
#include "aggpack/core/units.hpp"
#include "aggpack/dynamics/contact_law_registry.hpp"
#include "aggpack/io/toml_reader.hpp"
#include "aggpack/sizes/grading.hpp"

namespace aggpack {

namespace {
constexpr NumberRange kFraction{0.0, 1.0, true, false};

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

Container read_container(const TomlSection& s) {
  s.allow_only({"side", "height", "sides"});
  const double side = s.required(s.length("side"), "side", "a length such as \"12 in\"");
  const double height = s.required(s.length("height"), "height", "a length such as \"24 in\"");
  const bool periodic = s.choice("sides", {"walls", "periodic"}).value_or("walls") == "periodic";
  return Container::square(side, height, periodic);
}

SizeClass read_size_class(const TomlSection& s) {
  s.allow_only({"diameter", "count", "volume_fraction"});
  SizeClass c;
  c.diameter = s.required(s.length("diameter", kPositive, kLargestBareGrain), "diameter", "a length such as \"0.5 in\"");
  if (const auto n = s.integer("count", 1, 1'000'000'000)) c.count = static_cast<std::size_t>(*n);
  c.volume_fraction = s.number("volume_fraction", kFraction);
  if (c.count.has_value() == c.volume_fraction.has_value())
    s.fail(c.count ? "volume_fraction" : "diameter",
           "give exactly one of 'count' and 'volume_fraction' for each size class");
  return c;
}

std::filesystem::path relative_to(const std::filesystem::path& dir, const std::string& file) {
  return std::filesystem::path(file).is_absolute() ? std::filesystem::path(file) : dir / file;
}

// The input file that `key` names, from the scenario's folder: one that is not there is
// refused at the key, with the path it was looked for at (absolute) and the path as given.
// (One that is there but is no regular file is refused when it is read, saying what it is.)
std::filesystem::path input_file_at(const TomlSection& s, std::string_view key, const std::filesystem::path& scenario_dir,
                                    const std::string& given, std::string_view what) {
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

GradingSource read_grading_source(const TomlSection& s, const std::filesystem::path& scenario_dir) {
  s.allow_only({"name", "file", "length_unit", "percent_column", "sieves", "law", "law_d_max", "q", "law_d_min",
                "d_min", "d_max", "band"});
  GradingSource g;
  g.key = s.path();
  const int ways = int(s.has("name")) + int(s.has("file")) + int(s.has("sieves")) + int(s.has("law"));
  if (ways != 1)
    s.fail(ways == 0 ? "name" : "file", "give exactly one of 'name' (a shipped grading), 'file' (a CSV sieve "
                                        "analysis), 'sieves' (a list) or 'law' (a grading law)");
  if (const auto name = s.string("name")) {
    const auto named = named_grading(*name);
    if (!named)
      s.fail("name", fmt::format("unknown grading \"{}\"; shipped gradings: {}", *name,
                                 fmt::join(named_grading_names(), ", ")));
    g.grading = *named;
  } else if (const auto file = s.string("file")) {
    // The unit of a bare `opening` column only: without it such a column is refused (a sand in
    // mm was once read in inches by default).
    std::optional<double> length_unit;
    if (const auto unit = s.string("length_unit")) {
      const auto factor = metres_per_unit(*unit);
      if (!factor)
        s.fail("length_unit", fmt::format("unknown length unit \"{}\"; expected m, cm, mm, um, in, ft or yd", *unit));
      length_unit = static_cast<double>(*factor);
    }
    g.grading = read_grading_csv(input_file_at(s, "file", scenario_dir, *file, "the sieve file").string(), length_unit,
                                 s.string("percent_column").value_or("percent_passing"));
  } else if (const auto law = s.choice("law", kGradingLawNames)) {
    GradingLaw l;
    l.kind = *law;
    l.d_max = s.required(s.length("law_d_max", kPositive, kLargestBareGrain), "law_d_max",
                         "the largest size of the law, such as \"1 in\"");
    l.q = s.number("q", kPositive).value_or(l.kind == GradingLawKind::Andreasen ? 0.37 : 0.5);
    l.d_min = s.length("law_d_min", kPositive, kLargestBareGrain).value_or(0.0);
    try {
      g.grading = grading_from_law(l);
    } catch (const InputError& e) {
      s.fail("law", e.what());
    }
  } else {
    std::vector<Sieve> sieves;
    std::vector<std::string> rows;
    const auto list = *s.table_array("sieves");
    for (std::size_t i = 0; i < list.size(); ++i) {
      const TomlSection& row = list[i];
      row.allow_only({"sieve", "opening", "passing"});
      Sieve sieve;
      sieve.name = row.string("sieve").value_or("");
      sieve.opening = row.required(row.length("opening", kPositive, kLargestBareGrain), "opening", "a length such as \"0.5 in\"");
      sieve.percent_passing = row.required(row.number("passing", {0.0, 100.0, false, false}), "passing",
                                           "percent passing, 0 to 100");
      sieves.push_back(sieve);
      rows.push_back(row.path());
    }
    g.grading = make_grading(g.key, std::move(sieves), s.location("sieves"), rows);
  }
  g.d_min = s.length("d_min", kPositive, kLargestBareGrain);
  g.d_max = s.length("d_max", kPositive, kLargestBareGrain);
  // A cut-off at or below the smallest sieve cuts nothing: taken silently as "no cut-off" it
  // hides a slip (a value in the wrong unit, or a whole-grading series that repeats one bed).
  if (g.d_min && !(*g.d_min > g.grading.smallest()))
    s.fail("d_min", fmt::format("{:.4g} mm is at or below the smallest sieve of grading '{}' ({:.4g} mm), so it cuts "
                                "nothing; expected a d_min above {:.4g} mm, or no d_min for the whole grading",
                                1e3 * *g.d_min, g.grading.name, 1e3 * g.grading.smallest(), 1e3 * g.grading.smallest()));
  if (const auto band = s.string("band")) {
    g.band = named_band(*band);
    if (!g.band)
      s.fail("band", fmt::format("unknown band \"{}\"; shipped bands: {}", *band, fmt::join(named_band_names(), ", ")));
  }
  cut_grading(g.grading, g.d_min, g.d_max, s.location(g.d_min ? "d_min" : "d_max") + ": " + g.key);
  return g;
}

GradedParticles read_graded(const TomlSection& s, const std::filesystem::path& scenario_dir,
                            const Container& container) {
  GradedParticles p;
  const bool mix = s.has("coarse") || s.has("fine");
  if (mix) {
    if (s.has("grading")) s.fail("grading", "give either 'grading' or a 'coarse' and 'fine' mix, not both");
    p.main = read_grading_source(s.required(s.table("coarse"), "coarse", "a [particles.coarse] table"), scenario_dir);
    p.fine = read_grading_source(s.required(s.table("fine"), "fine", "a [particles.fine] table"), scenario_dir);
    p.ca_fa = s.required(s.number("ca_fa", kPositive), "ca_fa", "the coarse/fine volume ratio, such as 1.52");
  } else {
    if (s.has("ca_fa")) s.fail("ca_fa", "applies only to a coarse/fine mix");
    p.main = read_grading_source(*s.table("grading"), scenario_dir);
  }
  p.sampling = s.choice("sampling", kSamplingModeNames).value_or(SamplingMode::Mass);
  p.order = s.choice("order", kMixOrderNames).value_or(mix ? MixOrder::Interleaved : MixOrder::Shuffled);
  if (!mix && p.order == MixOrder::Interleaved) s.fail("order", "'interleaved' applies only to a coarse/fine mix");
  const auto count = s.integer("count", 1, 1'000'000'000);
  const auto solid_volume = s.number("solid_volume", kPositive);
  p.fill_height = s.length("fill_height");
  p.expected_density = s.number("expected_density", {0.0, 1.0, true, false}).value_or(p.expected_density);
  if (s.has("expected_density") && !p.fill_height)
    s.fail("expected_density", "applies only with 'fill_height'");
  if (int(count.has_value()) + int(solid_volume.has_value()) + int(p.fill_height.has_value()) != 1)
    s.fail("count", "say how much to generate with exactly one of 'count', 'solid_volume' (m^3) or 'fill_height' "
                    "(with 'expected_density', default 0.6)");
  if (count) p.amount.count = static_cast<std::size_t>(*count);
  if (solid_volume) p.amount.solid_volume = solid_volume;
  if (p.fill_height) {
    if (*p.fill_height > container.height())
      s.fail("fill_height", "is above the container height");
    p.amount.solid_volume = container.length_x() * container.length_y() * *p.fill_height * p.expected_density;
  }
  return p;
}

ParticleSource read_particles(const TomlSection& s, const std::filesystem::path& scenario_dir,
                              const Container& container) {
  s.allow_only({"diameter", "count", "classes", "solid_volume", "order", "from", "length_unit", "grading", "coarse",
                "fine", "ca_fa", "sampling", "fill_height", "expected_density", "boundary_overlap_tolerance",
                "overlap_tolerance", "soft_contacts", "timestep"});
  ParticleSource source;
  const bool graded = s.has("grading") || s.has("coarse") || s.has("fine");
  const int ways = int(s.has("diameter")) + int(s.has("classes")) + int(s.has("from")) + int(graded);
  if (ways != 1)
    s.fail(ways == 0 ? "diameter" : (s.has("from") ? "from" : (s.has("classes") ? "classes" : "diameter")),
           "give exactly one of 'diameter' (monosized, with 'count'), 'classes' (a list of size classes), "
           "'grading' (a sieve grading), 'coarse' and 'fine' (a mix) or 'from' (a particle file)");
  if (graded) {
    source.graded = read_graded(s, scenario_dir, container);
    return source;
  }
  for (auto k : {"sampling", "fill_height", "expected_density", "ca_fa"})
    if (s.has(k)) s.fail(k, "applies only to particles sampled from a grading");
  if (const auto file = s.string("from")) {
    for (auto k : {"count", "solid_volume", "order"})
      if (s.has(k)) s.fail(k, "does not apply to particles read from a file");
    const std::string unit = s.string("length_unit").value_or("m");
    const auto factor = metres_per_unit(unit);
    if (!factor) s.fail("length_unit", fmt::format("unknown length unit \"{}\"; expected m, cm, mm, um, in, ft or yd", unit));
    source.file_length_unit = static_cast<double>(*factor);
    source.boundary_overlap_tolerance =
        s.number("boundary_overlap_tolerance", {0.0, 1.0, false, true}).value_or(source.boundary_overlap_tolerance);
    source.overlap_tolerance = s.number("overlap_tolerance", {0.0, 1.0, false, true}).value_or(source.overlap_tolerance);
    source.soft_contacts = s.boolean("soft_contacts").value_or(false);
    source.file_timestep = s.integer("timestep", 0, std::numeric_limits<std::int64_t>::max());
    source.file = input_file_at(s, "from", scenario_dir, *file, "the particle file");  // after its keys are checked
    return source;
  }
  for (auto k : {"length_unit", "boundary_overlap_tolerance", "overlap_tolerance", "soft_contacts", "timestep"})
    if (s.has(k)) s.fail(k, "applies only to particles read with 'from'");
  SizeSpec spec;
  spec.order = s.choice("order", kSizeOrderNames).value_or(SizeOrder::Shuffled);
  const auto count = s.integer("count", 1, 1'000'000'000);
  const auto solid_volume = s.number("solid_volume", kPositive);
  if (const auto d = s.length("diameter", kPositive, kLargestBareGrain)) {
    if (solid_volume) s.fail("solid_volume", "monosized particles take a 'count'");
    spec.classes.push_back({*d, static_cast<std::size_t>(s.required(count, "count", "a positive integer")), {}});
  } else {
    const auto classes = *s.table_array("classes");
    if (classes.empty()) s.fail("classes", "expected at least one size class");
    for (const auto& c : classes) spec.classes.push_back(read_size_class(c));
    const bool by_fraction = spec.classes.front().volume_fraction.has_value();
    for (std::size_t i = 0; i < spec.classes.size(); ++i)
      if (spec.classes[i].volume_fraction.has_value() != by_fraction)
        classes[i].fail("diameter", "size classes must all give a count or all give a volume_fraction");
    if (by_fraction) {
      double sum = 0.0;
      for (const auto& c : spec.classes) sum += *c.volume_fraction;
      if (std::abs(sum - 1.0) > 1e-6)
        s.fail("classes", fmt::format("volume fractions must add up to 1, they add up to {:.6g}", sum));
      if (count.has_value() == solid_volume.has_value())
        s.fail("classes", "classes given by volume_fraction need exactly one of 'count' (total particles) "
                          "and 'solid_volume' (m^3)");
      if (count) spec.total_count = static_cast<std::size_t>(*count);
      spec.solid_volume = solid_volume;
    } else if (count || solid_volume) {
      s.fail(count ? "count" : "solid_volume", "classes with their own counts take no total");
    }
  }
  source.sizes = spec;
  return source;
}

Material read_material(const TomlSection& s) {
  s.allow_only({"density", "youngs_modulus", "poisson_ratio", "wall_youngs_modulus", "wall_poisson_ratio",
                "friction_particle", "friction_wall", "restitution", "rolling_friction"});
  Material m;
  ContactParameters& c = m.contact;
  const NumberRange poisson{-1.0, 0.5, true, true};
  m.density = s.number("density", kPositive).value_or(m.density);
  c.youngs_modulus = s.number("youngs_modulus", kPositive).value_or(c.youngs_modulus);
  c.poisson_ratio = s.number("poisson_ratio", poisson).value_or(c.poisson_ratio);
  c.wall_youngs_modulus = s.number("wall_youngs_modulus", kPositive).value_or(c.wall_youngs_modulus);
  c.wall_poisson_ratio = s.number("wall_poisson_ratio", poisson).value_or(c.wall_poisson_ratio);
  c.friction_particle = s.number("friction_particle", kNonNegative).value_or(c.friction_particle);
  c.friction_wall = s.number("friction_wall", kNonNegative).value_or(c.friction_wall);
  c.restitution = s.number("restitution", kFraction).value_or(c.restitution);
  c.rolling_friction = s.number("rolling_friction", kNonNegative).value_or(c.rolling_friction);
  return m;
}

// [dynamics]; its friction_model chooses the contact law of `material`.
DynamicsStage read_dynamics(const TomlSection& s, Material& material) {
  s.allow_only({"friction_model", "time_step", "time_step_safety", "max_time", "sample_interval", "quiet_window",
                "quiet_kinetic_fraction", "density_tolerance", "layers", "skin", "gravity",
                "allow_unstable_time_step", "engine", "lammps_ranks", "lammps_binary"});
  DynamicsStage d;
  d.engine = s.choice("engine", kDemEngineNames).value_or(d.engine);
  d.lammps_ranks = static_cast<int>(s.integer("lammps_ranks", 1, 4096).value_or(d.lammps_ranks));
  d.lammps_binary = s.string("lammps_binary").value_or(d.lammps_binary);
  if (d.engine != DemEngine::Lammps)
    for (const char* k : {"lammps_ranks", "lammps_binary"})
      if (s.has(k)) s.fail(k, "applies only with engine = \"lammps\"");
  std::vector<std::string_view> laws;
  for (const ContactLawEntry& law : contact_laws()) laws.push_back(law.name);
  material.contact.friction_model = s.choice("friction_model", laws).value_or(material.contact.friction_model);
  d.time_step.fixed = s.number("time_step", {0.0, 1.0, true, false});
  d.time_step.safety = s.number("time_step_safety", {0.0, 1.0, true, false}).value_or(d.time_step.safety);
  QuietCriterion& q = d.quiet;
  q.max_time = s.number("max_time", {0.0, 1e4, true, false}).value_or(q.max_time);
  q.sample_interval = s.number("sample_interval", {0.0, 1e3, true, false}).value_or(q.sample_interval);
  q.window = s.number("quiet_window", kPositive).value_or(q.window);
  if (q.window < q.sample_interval)
    s.fail("quiet_window", fmt::format("{} s is shorter than the sample interval {} s; expected at least one "
                                       "sample interval", q.window, q.sample_interval));
  q.kinetic_fraction = s.number("quiet_kinetic_fraction", kPositive).value_or(q.kinetic_fraction);
  q.density_tolerance = s.number("density_tolerance", kPositive).value_or(q.density_tolerance);
  d.layers = static_cast<std::size_t>(s.integer("layers", 1, 10'000).value_or(1));
  d.dem.skin = s.length("skin").value_or(d.dem.skin);
  d.allow_unstable_time_step = s.boolean("allow_unstable_time_step").value_or(false);
  d.dem.gravity = {0.0, 0.0, -s.number("gravity", kPositive).value_or(-d.dem.gravity.z)};
  return d;
}

DepositionSettings read_deposition(const TomlSection& s, const Container& container) {
  s.allow_only({"method", "tolerance", "max_events", "max_redrops", "fill_height"});
  s.choice("method", {"drop_and_roll"});
  DepositionSettings d;
  d.tolerance = s.number("tolerance", {0.0, 1e-3, true, false}).value_or(d.tolerance);
  d.max_events = static_cast<std::size_t>(s.integer("max_events", 10, 1'000'000).value_or(
      static_cast<std::int64_t>(d.max_events)));
  d.max_redrops = static_cast<std::size_t>(s.integer("max_redrops", 0, 1'000'000).value_or(
      static_cast<std::int64_t>(d.max_redrops)));
  d.fill_height = s.length("fill_height").value_or(container.height());
  if (d.fill_height > container.height())
    s.fail("fill_height", fmt::format("{:.6g} m is above the container height ({:.6g} m)", d.fill_height,
                                      container.height()));
  return d;
}

PourSettings read_pour(const TomlSection& s) {
  s.allow_only({"solid_fraction", "batches", "velocity", "gap"});
  PourSettings p;
  p.solid_fraction = s.number("solid_fraction", {0.0, 0.3, true, false}).value_or(p.solid_fraction);
  p.batches = static_cast<std::size_t>(s.integer("batches", 1, 10000).value_or(1));
  p.velocity = s.number("velocity", {0.0, 100.0, false, false}).value_or(p.velocity);
  // No gap is allowed: the gas's spheres lie inside their slab, so none starts in the bed.
  p.gap = s.length("gap", kNonNegative);
  return p;
}

TappingSettings read_tapping(const TomlSection& s) {
  s.allow_only({"taps", "intensity", "frequency", "rest_time", "rest_until_quiet"});
  TappingSettings t;
  t.taps = static_cast<std::size_t>(s.integer("taps", 1, 100000).value_or(static_cast<std::int64_t>(t.taps)));
  t.intensity = s.number("intensity", {0.0, 100.0, true, false}).value_or(t.intensity);
  t.frequency = s.number("frequency", {0.0, 10000.0, true, false}).value_or(t.frequency);
  t.rest_time = s.number("rest_time", {0.0, 100.0, true, false}).value_or(t.rest_time);
  t.rest_until_quiet = s.boolean("rest_until_quiet").value_or(t.rest_until_quiet);
  return t;
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
  s.allow_only({"max_particles", "max_memory_gib", "max_grid_cells", "max_input_file_gib", "max_profile_bins"});
  RunLimits l;
  l.max_particles = static_cast<double>(s.integer("max_particles", 1, 4'000'000'000).value_or(
      static_cast<std::int64_t>(l.max_particles)));
  l.max_memory_gib = s.number("max_memory_gib", {0.0, 1e6, true, false});
  l.max_grid_cells = static_cast<double>(s.integer("max_grid_cells", 1, std::int64_t{1} << 31).value_or(
      static_cast<std::int64_t>(l.max_grid_cells)));
  l.max_input_file_gib = s.number("max_input_file_gib", {0.0, 1e6, true, false}).value_or(l.max_input_file_gib);
  l.max_profile_bins = static_cast<double>(s.integer("max_profile_bins", 1, 1'000'000'000).value_or(
      static_cast<std::int64_t>(l.max_profile_bins)));
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
    for (const auto& f : *formats) {
      if (f == "csv") o.csv = true;
      else if (f == "vtp") o.vtp = true;
      else s.fail("formats", fmt::format("unknown format \"{}\"; expected \"csv\" and/or \"vtp\" "
                                         "(summary.json is always written)", f));
    }
  }
  return o;
}
}  // namespace

// [[protocol]]: the steps in order, each checked against the tables that give its settings.
Protocol read_protocol(const TomlSection& root, const std::vector<TomlSection>& entries, const Scenario& sc) {
  if (entries.empty()) root.fail("protocol", "expected at least one step");
  if (sc.dynamics && sc.dynamics->layers > 1)
    root.table("dynamics")->fail("layers", "with [[protocol]], give the layers on the deposit steps (layer, layers)");
  Protocol p;
  std::optional<std::uint32_t> layers;        // every deposit step's `layers`
  std::vector<std::size_t> deposited_by;      // the entry that deposits each part (+1; 0: none yet)
  std::size_t settles = 0, deposits = 0, pours = 0, taps = 0;
  std::vector<std::size_t> export_entries;  // the entries of the export_lammps steps, in order
  // The names taken by each kind of step, looked up in a set: a scenario of 16 MiB holds
  // some 3x10^5 steps, and comparing each with all before it took minutes.
  std::set<std::string> export_names, snapshot_names, analyse_names;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const TomlSection& e = entries[i];
    const std::string kind =
        e.required(e.choice("step", {"deposit", "pour", "settle", "tap", "analyse", "snapshot", "export_lammps",
                                     "import_lammps"}),
                   "step",
                   "the kind of step: \"deposit\", \"pour\", \"settle\", \"tap\", \"analyse\", \"snapshot\", "
                   "\"export_lammps\" or \"import_lammps\"");
    if (kind == "deposit" || kind == "pour") {
      e.allow_only({"step", "layer", "layers"});
      if (kind == "deposit" && !sc.deposition)
        e.fail("step", "a deposit step places generated particles with the [deposition] settings; add a "
                       "[deposition] table (it may be empty) and give particles by size");
      if (kind == "pour" && !sc.pour)
        e.fail("step", "a pour step inserts generated particles with the [pour] settings; add a [pour] table "
                       "(it may be empty) and give particles by size");
      if (kind == "pour" && !sc.dynamics)
        e.fail("step", "a pour falls through the DEM with the [dynamics] settings; add a [dynamics] table");
      DepositStep d;
      d.layers = static_cast<std::uint32_t>(e.integer("layers", 1, 10000).value_or(1));
      if (layers && *layers != d.layers)
        e.fail("layers", fmt::format("every deposit and pour step splits the drop sequence alike; an earlier one has "
                                     "layers = {}, this one {}",
                                     *layers, d.layers));
      d.layer = static_cast<std::uint32_t>(e.integer("layer", 0, d.layers - 1).value_or(0));
      layers = d.layers;
      deposited_by.resize(d.layers, 0);
      if (deposited_by[d.layer] != 0)
        e.fail("layer", fmt::format("part {} of {} is already deposited by {}", d.layer, d.layers,
                                    entries[deposited_by[d.layer] - 1].path()));
      deposited_by[d.layer] = i + 1;
      if (kind == "pour") {
        p.steps.push_back({"pour", PourStep{d.layer, d.layers}});
        ++pours;
      } else {
        p.steps.push_back({"deposition", d});
        ++deposits;
      }
    } else if (kind == "settle") {
      e.allow_only({"step", "layer"});
      if (!sc.dynamics) e.fail("step", "a settle step takes its settings from a [dynamics] table; add one");
      SettleStep st;
      st.layer = static_cast<std::uint32_t>(e.integer("layer", 0, layers.value_or(1) - 1).value_or(0));
      ++settles;
      p.steps.push_back({"dynamics", st});
    } else if (kind == "tap") {
      e.allow_only({"step"});
      if (!sc.tapping) e.fail("step", "a tap step takes its settings from a [tapping] table; add one");
      if (!sc.dynamics) e.fail("step", "a tap step moves the bed through the DEM of a [dynamics] table; add one");
      ++taps;
      p.steps.push_back({"tapping", TapStep{}});
    } else if (kind == "export_lammps") {
      e.allow_only({"step", "name"});
      if (!sc.dynamics)
        e.fail("step", "an export_lammps step writes a deck of the DEM step after it, with the [dynamics] settings; "
                       "add a [dynamics] table");
      const std::string name = e.required(e.string("name"), "name", "the name of its folder, <output>/lammps/<name>");
      if (name.empty() || name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-") !=
                              std::string::npos)
        e.fail("name", "expected letters, digits, '_' or '-' (it names a folder)");
      if (!export_names.insert(name).second)
        e.fail("name", fmt::format("another export_lammps step is already named \"{}\"", name));
      // Its deck is of the next DEM step, filled in below; it belongs to the stage before it.
      p.steps.push_back({p.steps.empty() ? std::string("input") : p.steps.back().stage, ExportLammpsStep{name, {}}});
      export_entries.push_back(i);
    } else if (kind == "import_lammps") {
      e.allow_only({"step", "file", "timestep"});
      const std::string file =
          e.required(e.string("file"), "file", "the LAMMPS dump or data file to take the positions from");
      const std::filesystem::path path = input_file_at(e, "file", sc.file.parent_path(), file, "the LAMMPS file");
      ImportLammpsStep import{path, std::nullopt};
      if (e.has("timestep")) import.timestep = e.integer("timestep", 0, std::numeric_limits<std::int64_t>::max());
      p.steps.push_back({"import_lammps", import});
    } else if (kind == "snapshot") {
      e.allow_only({"step", "name"});
      const std::string name = e.required(e.string("name"), "name", "the name of its file, particles_<name>.csv");
      if (name.empty() || name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-") !=
                              std::string::npos)
        e.fail("name", "expected letters, digits, '_' or '-' (it names a file)");
      if (!snapshot_names.insert(name).second)
        e.fail("name", fmt::format("another snapshot step is already named \"{}\"", name));
      // A snapshot belongs to the stage before it: --stop-after that stage keeps it.
      p.steps.push_back({p.steps.empty() ? std::string("input") : p.steps.back().stage, SnapshotStep{name}});
    } else {
      e.allow_only({"step", "name"});
      const std::string name = e.required(e.string("name"), "name",
                                          "the name of its results in summary.json (stages.<name>)");
      if (name.empty() || name == "dynamics")
        e.fail("name", "expected a name other than \"dynamics\" (whose density is the final analysis)");
      if (!analyse_names.insert(name).second)
        e.fail("name", fmt::format("another analyse step is already named \"{}\"", name));
      p.steps.push_back({name, AnalyseStep{name}});
    }
  }
  // Each export_lammps step's deck is of the first DEM step after it: one pass from the last
  // step back (a search forward from each export was quadratic in the steps).
  std::optional<DemStep> next;
  std::optional<std::size_t> unfollowed;  // the first export_lammps entry that no DEM step follows
  std::size_t exports_left = export_entries.size();
  for (std::size_t j = p.steps.size(); j-- > 0;)
    std::visit(Overloaded{[&](const SettleStep& s) { next = s; }, [&](const PourStep& s) { next = s; },
                          [&](const TapStep& s) { next = s; },
                          [&](ExportLammpsStep& step) {
                            --exports_left;
                            if (next) step.next = *next;
                            else unfollowed = export_entries[exports_left];
                          },
                          [](const auto&) {}},
               p.steps[j].kind);
  if (unfollowed)
    entries[*unfollowed].fail("step", "an export_lammps step writes a deck of the DEM step after it (settle, pour or "
                                      "tap), and none follows");
  if (sc.deposition && deposits == 0)
    root.fail("protocol", "[deposition] is given but no deposit step places the particles");
  if (sc.pour && pours == 0) root.fail("protocol", "[pour] is given but no pour step places the particles");
  for (std::size_t k = 0; k < deposited_by.size(); ++k)
    if (deposited_by[k] == 0)
      root.fail("protocol", fmt::format("no deposit or pour step places part {} of {}: each part is placed once", k,
                                        deposited_by.size()));
  if (sc.tapping && taps == 0) root.fail("protocol", "[tapping] is given but no tap step uses it");
  if (sc.dynamics && settles == 0 && pours == 0 && taps == 0)
    root.fail("protocol", "[dynamics] is given but no settle, pour or tap step uses it");
  return p;
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

Scenario parse_scenario(std::string_view text, const std::filesystem::path& file, const ScenarioOverrides& overrides) {
  ScenarioOrigin origin{file.string(), {}};
  toml::table root;
  try {
    root = toml::parse(text, file.string());
  } catch (const toml::parse_error& e) {
    const auto& src = e.source();
    throw InputError(fmt::format("{}:{}:{}: TOML syntax error: {}", file.string(), src.begin.line,
                                 src.begin.column, e.description()));
  }
  for (const auto& assignment : overrides.set) {
    const auto typed = overrides.typed_as.find(assignment);
    apply_override(root, assignment, typed != overrides.typed_as.end() ? typed->second : "--set " + assignment, origin);
  }

  const TomlSection s(root, "", origin);
  s.allow_only({"title", "seed", "container", "particles", "material", "analysis", "output", "deposition", "pour",
                "tapping", "dynamics", "protocol", "limits", "models"});

  Scenario sc;
  sc.file = file;
  sc.overrides = overrides.set;
  sc.title = s.string("title").value_or(file.stem().string());
  sc.seed = static_cast<std::uint64_t>(s.integer("seed", 0, std::numeric_limits<std::int64_t>::max()).value_or(1));
  if (overrides.seed) {
    // The file's range, so that no seed reads back as another (2^64 - 1 as -1 in a signed reader).
    if (*overrides.seed > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
      throw InputError(fmt::format("{}: seed {}: expected an integer from 0 to {}", file.string(), *overrides.seed,
                                   std::numeric_limits<std::int64_t>::max()));
    sc.seed = *overrides.seed;
  }
  const TomlSection container = s.required(s.table("container"), "container", "a [container] table");
  sc.container = read_container(container);
  sc.written_length_unit = container.written_unit("side").value_or("");
  if (sc.written_length_unit == "m") sc.written_length_unit.clear();
  sc.particles = read_particles(s.required(s.table("particles"), "particles", "a [particles] table"),
                                file.parent_path(), sc.container);
  if (const auto m = s.table("material")) sc.material = read_material(*m);
  if (const auto d = s.table("deposition")) sc.deposition = read_deposition(*d, sc.container);
  if (const auto p = s.table("pour")) sc.pour = read_pour(*p);
  if (const auto t = s.table("tapping")) {
    sc.tapping = read_tapping(*t);
    if (!s.table("dynamics"))
      s.fail("tapping", "tapping moves the bed through the DEM with the [dynamics] settings; add a [dynamics] "
                        "table (it may be empty)");
  }
  if (const auto d = s.table("dynamics")) {
    sc.dynamics = read_dynamics(*d, sc.material);
    if (sc.dynamics->layers > 1 && sc.pour)
      d->fail("layers", "a pour settles as it goes; to pour in parts, give [[protocol]] pour steps with layer and "
                        "layers, and expected layers = 1 here");
    if (sc.dynamics->layers > 1 && !sc.deposition)
      d->fail("layers", "layer by layer settling deposits each layer, so it needs a [deposition] table; "
                        "expected layers = 1 for a bed read from a file");
  }
  if (const auto a = s.table("analysis")) sc.analysis = read_analysis(*a);
  if (const auto l = s.table("limits")) sc.limits = read_limits(*l);
  if (const auto m = s.table("models")) {
    m->allow_only({"calibration"});
    if (const auto f = m->string("calibration")) {
      std::filesystem::path path = *f;
      if (path.is_relative()) path = file.parent_path() / path;
      if (!std::filesystem::is_regular_file(path))
        m->fail("calibration", fmt::format("{} is not a file (a calibration written by aggpack calibrate; relative "
                                           "paths are from the scenario's folder)",
                                           path.string()));
      sc.models_calibration = path;
    }
  }
  if (const auto o = s.table("output")) sc.output = read_output(*o, file);
  else sc.output.directory = "out/" + file.stem().string();
  if (overrides.output_directory) sc.output.directory = *overrides.output_directory;

  // Cross-checks that need several sections.
  if (sc.particles.sizes || sc.particles.graded) {
    double d_max = 0.0;
    if (sc.particles.sizes)
      for (const auto& c : sc.particles.sizes->classes) d_max = std::max(d_max, c.diameter);
    if (const auto& g = sc.particles.graded) {
      d_max = cut_grading(g->main.grading, g->main.d_min, g->main.d_max, g->main.key).d_hi;
      if (g->fine) d_max = std::max(d_max, cut_grading(g->fine->grading, g->fine->d_min, g->fine->d_max, "").d_hi);
    }
    const TomlSection particles = *s.table("particles");
    const std::string where = particles.location(particles.has("diameter")  ? "diameter"
                                                 : particles.has("classes") ? "classes"
                                                 : particles.has("grading") ? "grading"
                                                                            : "coarse");
    if (d_max >= sc.container.length_x())
      throw InputError(fmt::format("{}: particles: the largest diameter ({:.6g} m) does not fit in the container "
                                   "(side {:.6g} m)", where, d_max, sc.container.length_x()));
    // The nearest periodic image must be unique within a roll's reach (two diameters each way).
    if (sc.container.periodic && sc.container.length_x() <= 4.0 * d_max)
      throw InputError(fmt::format("{}: container.side: with periodic sides the side ({:.6g} m) must exceed four "
                                   "times the largest diameter ({:.6g} m)", file.string(), sc.container.length_x(),
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
  if (sc.pour && !sc.dynamics)
    s.fail("pour", "a pour falls through the DEM with the [dynamics] settings; add a [dynamics] table (it may be "
                   "empty)");
  const auto steps = s.table_array("protocol");
  if (sc.pour && sc.deposition && !steps)
    s.fail("pour", "with both [deposition] and [pour], give the order of their steps as [[protocol]] (for example "
                   "deposit part 0 of 2, then pour part 1 of 2)");
  if (steps) sc.protocol = read_protocol(s, *steps, sc);
  return sc;
}

nlohmann::json to_json(const Protocol& protocol) {
  nlohmann::json steps = nlohmann::json::array();
  for (const Step& step : protocol.steps)
    std::visit(Overloaded{[&](const DepositStep& d) {
                            steps.push_back({{"step", "deposit"}, {"layer", d.layer}, {"layers", d.layers}});
                          },
                          [&](const PourStep& d) {
                            steps.push_back({{"step", "pour"}, {"layer", d.layer}, {"layers", d.layers}});
                          },
                          [&](const SettleStep& st) { steps.push_back({{"step", "settle"}, {"layer", st.layer}}); },
                          [&](const TapStep&) { steps.push_back({{"step", "tap"}}); },
                          [&](const AnalyseStep& a) { steps.push_back({{"step", "analyse"}, {"name", a.report_as}}); },
                          [&](const SnapshotStep& snap) { steps.push_back({{"step", "snapshot"}, {"name", snap.name}}); },
                          [&](const ExportLammpsStep& x) { steps.push_back({{"step", "export_lammps"}, {"name", x.name}}); },
                          [&](const ImportLammpsStep& x) {
                            nlohmann::json j{{"step", "import_lammps"}, {"file", x.file.string()}};
                            if (x.timestep) j["timestep"] = *x.timestep;
                            steps.push_back(std::move(j));
                          }},
               step.kind);
  return steps;
}

nlohmann::json to_json(const Scenario& sc) {
  nlohmann::json j;
  if (sc.protocol) j["protocol"] = to_json(*sc.protocol);
  j["title"] = sc.title;
  j["seed"] = sc.seed;
  j["file"] = sc.file.string();
  j["container"] = {{"side_m", sc.container.length_x()},
                    {"height_m", sc.container.height()},
                    {"sides", sc.container.periodic ? "periodic" : "walls"}};
  auto& p = j["particles"];
  if (sc.particles.file) {
    p["from"] = sc.particles.file->string();
    p["length_unit_m"] = sc.particles.file_length_unit;
    p["boundary_overlap_tolerance"] = sc.particles.boundary_overlap_tolerance;
    if (sc.particles.file_timestep) p["timestep"] = *sc.particles.file_timestep;
  }
  if (sc.particles.sizes) {
    const SizeSpec& spec = *sc.particles.sizes;
    for (const auto& c : spec.classes) {
      nlohmann::json cj{{"diameter_m", c.diameter}};
      if (c.count) cj["count"] = *c.count;
      if (c.volume_fraction) cj["volume_fraction"] = *c.volume_fraction;
      p["classes"].push_back(cj);
    }
    if (spec.total_count) p["count"] = *spec.total_count;
    if (spec.solid_volume) p["solid_volume_m3"] = *spec.solid_volume;
    p["order"] = name_of(kSizeOrderNames, spec.order);
  }
  if (const auto& g = sc.particles.graded) {
    const auto source = [](const GradingSource& gs) {
      nlohmann::json out{{"key", gs.key}, {"grading", gs.grading.name}};
      for (const Sieve& s : gs.grading.sieves)
        out["sieves"].push_back({{"sieve", s.name}, {"opening_m", s.opening}, {"percent_passing", s.percent_passing}});
      if (gs.d_min) out["d_min_m"] = *gs.d_min;
      if (gs.d_max) out["d_max_m"] = *gs.d_max;
      if (gs.band) out["band"] = gs.band->name;
      return out;
    };
    p["gradings"] = nlohmann::json::array({source(g->main)});  // {x} alone is x itself under clang
    if (g->fine) {
      p["gradings"].push_back(source(*g->fine));
      p["ca_fa"] = g->ca_fa;
    }
    p["sampling"] = name_of(kSamplingModeNames, g->sampling);
    p["order"] = name_of(kMixOrderNames, g->order);
    if (g->amount.count) p["count"] = *g->amount.count;
    if (g->amount.solid_volume) p["solid_volume_m3"] = *g->amount.solid_volume;
    if (g->fill_height) {
      p["fill_height_m"] = *g->fill_height;
      p["expected_density"] = g->expected_density;
    }
  }
  if (sc.deposition) {
    const DepositionSettings& d = *sc.deposition;
    j["deposition"] = {{"method", "drop_and_roll"},
                       {"tolerance", d.tolerance},
                       {"max_events", d.max_events},
                       {"max_redrops", d.max_redrops},
                       {"fill_height_m", d.fill_height}};
  }
  if (sc.pour) {
    const PourSettings& pour = *sc.pour;
    j["pour"] = {{"solid_fraction", pour.solid_fraction}, {"batches", pour.batches}, {"velocity_m_s", pour.velocity}};
    if (pour.gap) j["pour"]["gap_m"] = *pour.gap;
  }
  if (sc.tapping) {
    const TappingSettings& t = *sc.tapping;
    j["tapping"] = {{"taps", t.taps},
                    {"intensity", t.intensity},
                    {"frequency_hz", t.frequency},
                    {"rest_time_s", t.rest_time},
                    {"rest_until_quiet", t.rest_until_quiet}};
  }
  if (sc.dynamics) {
    const DynamicsStage& d = *sc.dynamics;
    const QuietCriterion& q = d.quiet;
    j["dynamics"] = {{"friction_model", sc.material.contact.friction_model},
                     {"time_step_safety", d.time_step.safety},
                     {"max_time_s", q.max_time},
                     {"sample_interval_s", q.sample_interval},
                     {"quiet_window_s", q.window},
                     {"quiet_kinetic_fraction", q.kinetic_fraction},
                     {"density_tolerance", q.density_tolerance},
                     {"layers", d.layers},
                     {"gravity_m_s2", -d.dem.gravity.z}};
    if (d.time_step.fixed) j["dynamics"]["time_step_s"] = *d.time_step.fixed;
    if (d.allow_unstable_time_step) j["dynamics"]["allow_unstable_time_step"] = true;
    if (d.engine == DemEngine::Lammps) {
      j["dynamics"]["engine"] = "lammps";
      j["dynamics"]["lammps_ranks"] = d.lammps_ranks;
      j["dynamics"]["lammps_binary"] = d.lammps_binary;
    }
    if (d.dem.skin > 0.0) j["dynamics"]["skin_m"] = d.dem.skin;
  }
  const Material& m = sc.material;
  const ContactParameters& c = m.contact;
  j["material"] = {{"density_kg_m3", m.density},
                   {"youngs_modulus_pa", c.youngs_modulus},
                   {"poisson_ratio", c.poisson_ratio},
                   {"wall_youngs_modulus_pa", c.wall_youngs_modulus},
                   {"wall_poisson_ratio", c.wall_poisson_ratio},
                   {"friction_particle", c.friction_particle},
                   {"friction_wall", c.friction_wall},
                   {"restitution", c.restitution},
                   {"rolling_friction", c.rolling_friction}};
  j["analysis"] = {{"box_sides_m", sc.analysis.box_sides},
                   {"placement", "centered"},
                   {"contact_tolerance", sc.analysis.contact_tolerance}};
  if (sc.analysis.slice_thickness) j["analysis"]["slice_thickness_m"] = *sc.analysis.slice_thickness;
  if (sc.analysis.shell_thickness) j["analysis"]["shell_thickness_m"] = *sc.analysis.shell_thickness;
  nlohmann::json formats = nlohmann::json::array();
  if (sc.output.csv) formats.push_back("csv");
  if (sc.output.vtp) formats.push_back("vtp");
  j["output"] = {{"directory", sc.output.directory.string()},
                 {"formats", formats},
                 {"vtp_encoding", sc.output.vtp_encoding == VtpEncoding::Ascii ? "ascii" : "binary"},
                 {"checkpoint", sc.output.checkpoint},
                 {"checkpoint_every_s", sc.output.checkpoint_every}};
  if (sc.output.frame_interval) j["output"]["frame_interval_s"] = *sc.output.frame_interval;
  return j;
}

}  // namespace aggpack
