// [particles]: sizes by class, sampled from gradings (a coarse/fine mix), or positions from a file.
#include <cmath>
#include <limits>
#include <span>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "aggpack/core/error.hpp"
#include "aggpack/core/units.hpp"
#include "aggpack/sizes/grading.hpp"
#include "scenario_tables.hpp"

namespace aggpack {

namespace {

// The material a component's table names (`material`), as its index; 0 ([material]) by default.
std::uint8_t component_material(const TomlSection& s, std::span<const std::string> names) {
  return s.has("material") ? material_index(s, "material", names) : 0;
}

SizeClass read_size_class(const TomlSection& s) {
  s.allow_only({"diameter", "count", "volume_fraction", "material", "shape"});
  SizeClass c;
  c.diameter = s.required(s.length("diameter", kPositive, kLargestBareGrain), "diameter", "a length such as \"0.5 in\"");
  if (const auto n = s.integer("count", 1, 1'000'000'000)) c.count = static_cast<std::size_t>(*n);
  c.volume_fraction = s.number("volume_fraction", kFraction);
  if (c.count.has_value() == c.volume_fraction.has_value())
    s.fail(c.count ? "volume_fraction" : "diameter",
           "give exactly one of 'count' and 'volume_fraction' for each size class");
  return c;
}

// [[particles.classes]] into `spec`; returns each class's material.
std::vector<std::uint8_t> read_classes(const std::vector<TomlSection>& classes, SizeSpec& spec,
                                       std::span<const std::string> material_names,
                                       std::vector<std::optional<GrainShapeSpec>>& shapes) {
  std::vector<std::uint8_t> materials;
  for (const auto& c : classes) {
    spec.classes.push_back(read_size_class(c));
    materials.push_back(component_material(c, material_names));
    shapes.push_back(read_grain_shape(c));
    // A diameter is one size: two classes of it cannot be of two materials.
    for (std::size_t k = 0; k + 1 < spec.classes.size(); ++k)
      if (spec.classes[k].diameter == spec.classes.back().diameter && materials[k] != materials.back())
        c.fail("material", "another size class of the same diameter is of another material: make them one class "
                           "per material with different diameters, or one material");
  }
  const bool by_fraction = spec.classes.front().volume_fraction.has_value();
  for (std::size_t i = 0; i < spec.classes.size(); ++i)
    if (spec.classes[i].volume_fraction.has_value() != by_fraction)
      classes[i].fail("diameter", "size classes must all give a count or all give a volume_fraction");
  return materials;
}

// A graded component's table: its grading, material and shape.
GradingSource read_component_grading(const TomlSection& s, const std::filesystem::path& scenario_dir) {
  s.allow_only({"name", "file", "length_unit", "percent_column", "sieves", "law", "law_d_max", "q", "law_d_min",
                "d_min", "d_max", "band", "material", "shape"});
  return read_grading_source(s, scenario_dir);
}

}  // namespace

GradingSource read_grading_source(const TomlSection& s, const std::filesystem::path& scenario_dir) {
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

namespace {

GradedParticles read_graded(const TomlSection& s, const std::filesystem::path& scenario_dir,
                            const Container& container, std::span<const std::string> material_names,
                            std::vector<std::uint8_t>& component_materials,
                            std::vector<std::optional<GrainShapeSpec>>& component_shapes) {
  GradedParticles p;
  const bool mix = s.has("coarse") || s.has("fine");
  if (mix) {
    if (s.has("grading")) s.fail("grading", "give either 'grading' or a 'coarse' and 'fine' mix, not both");
    const TomlSection coarse = s.required(s.table("coarse"), "coarse", "a [particles.coarse] table");
    const TomlSection fine = s.required(s.table("fine"), "fine", "a [particles.fine] table");
    p.main = read_component_grading(coarse, scenario_dir);
    p.fine = read_component_grading(fine, scenario_dir);
    p.ca_fa = s.required(s.number("ca_fa", kPositive), "ca_fa", "the coarse/fine volume ratio, such as 1.52");
    component_materials = {component_material(coarse, material_names), component_material(fine, material_names)};
    component_shapes = {read_grain_shape(coarse), read_grain_shape(fine)};
  } else {
    if (s.has("ca_fa")) s.fail("ca_fa", "applies only to a coarse/fine mix");
    const TomlSection grading = *s.table("grading");
    p.main = read_component_grading(grading, scenario_dir);
    component_materials = {component_material(grading, material_names)};
    component_shapes = {read_grain_shape(grading)};
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
    p.amount.solid_volume = container.cross_section_area() * *p.fill_height * p.expected_density;
  }
  return p;
}

}  // namespace

namespace {
// What a file of the bed may hold: overlaps of the floor and walls, of two spheres.
void read_file_tolerances(const TomlSection& s, ParticleSource& source) {
  source.boundary_overlap_tolerance =
      s.number("boundary_overlap_tolerance", {0.0, 1.0, false, true}).value_or(source.boundary_overlap_tolerance);
  source.overlap_tolerance = s.number("overlap_tolerance", {0.0, 1.0, false, true}).value_or(source.overlap_tolerance);
  source.soft_contacts = s.boolean("soft_contacts").value_or(false);
}
// particles.from: a particle file's path and how to read it, or "-", a bed the caller gives.
void read_file_source(const TomlSection& s, const std::filesystem::path& scenario_dir, const std::string& file,
                      ParticleSource& source) {
  if (s.has("shape")) s.fail("shape", "a particle file holds spheres: grains are generated from sizes and poured");
  for (auto k : {"count", "solid_volume", "order"})
    if (s.has(k)) s.fail(k, "does not apply to particles read from a file");
  read_file_tolerances(s, source);
  if (file == kBedFromCaller) {  // the library's caller (Python's aggpack.run(..., bed=)) hands the bed over
    for (auto k : {"length_unit", "timestep"})
      if (s.has(k)) s.fail(k, "a bed given by the caller (from = \"-\") is in metres and has one snapshot");
    source.file = std::filesystem::path(kBedFromCaller);
    return;
  }
  const std::string unit = s.string("length_unit").value_or("m");
  const auto factor = metres_per_unit(unit);
  if (!factor) s.fail("length_unit", fmt::format("unknown length unit \"{}\"; expected m, cm, mm, um, in, ft or yd", unit));
  source.file_length_unit = static_cast<double>(*factor);
  source.file_timestep = s.integer("timestep", 0, std::numeric_limits<std::int64_t>::max());
  source.file = input_file_at(s, "from", scenario_dir, file, "the particle file");  // after its keys are checked
}
}  // namespace

ParticleSource read_particles(const TomlSection& s, const std::filesystem::path& scenario_dir,
                              const Container& container, std::span<const std::string> material_names,
                              bool imports_beds) {
  s.allow_only({"diameter", "count", "classes", "solid_volume", "order", "from", "length_unit", "grading", "coarse",
                "fine", "ca_fa", "sampling", "fill_height", "expected_density", "boundary_overlap_tolerance",
                "overlap_tolerance", "soft_contacts", "timestep", "material", "shape"});
  ParticleSource source;
  const bool graded = s.has("grading") || s.has("coarse") || s.has("fine");
  const int ways = int(s.has("diameter")) + int(s.has("classes")) + int(s.has("from")) + int(graded);
  if (ways != 1)
    s.fail(ways == 0 ? "diameter" : (s.has("from") ? "from" : (s.has("classes") ? "classes" : "diameter")),
           "give exactly one of 'diameter' (monosized, with 'count'), 'classes' (a list of size classes), "
           "'grading' (a sieve grading), 'coarse' and 'fine' (a mix) or 'from' (a particle file)");
  if (graded) {
    if (s.has("material"))
      s.fail("material", "a grading's material is given in its own table ([particles.grading], [particles.coarse], "
                         "[particles.fine])");
    if (s.has("shape"))
      s.fail("shape", "a grading's grains are given in its own table ([particles.grading.shape], "
                      "[particles.coarse.shape], [particles.fine.shape])");
    source.graded =
        read_graded(s, scenario_dir, container, material_names, source.component_material, source.component_shape);
    return source;
  }
  if (s.has("classes") && s.has("material"))
    s.fail("material", "each size class names its own material ([[particles.classes]] material = \"...\")");
  // A monosized bed or a particle file: one material for all.
  source.component_material = {component_material(s, material_names)};
  for (auto k : {"sampling", "fill_height", "expected_density", "ca_fa"})
    if (s.has(k)) s.fail(k, "applies only to particles sampled from a grading");
  if (const auto file = s.string("from")) {
    read_file_source(s, scenario_dir, *file, source);
    return source;
  }
  for (auto k : {"length_unit", "timestep"})
    if (s.has(k)) s.fail(k, "applies only to particles read with 'from'");
  // The tolerances of a file of the bed: 'from', or an import_lammps step's.
  for (auto k : {"boundary_overlap_tolerance", "overlap_tolerance", "soft_contacts"})
    if (s.has(k) && !imports_beds)
      s.fail(k, "applies only to particles read with 'from' or a bed taken back by an import_lammps step");
  read_file_tolerances(s, source);
  SizeSpec spec;
  spec.order = s.choice("order", kSizeOrderNames).value_or(SizeOrder::Shuffled);
  const auto count = s.integer("count", 1, 1'000'000'000);
  const auto solid_volume = s.number("solid_volume", kPositive);
  if (const auto d = s.length("diameter", kPositive, kLargestBareGrain)) {
    if (solid_volume) s.fail("solid_volume", "monosized particles take a 'count'");
    spec.classes.push_back({*d, static_cast<std::size_t>(s.required(count, "count", "a positive integer")), {}});
    source.component_shape = {read_grain_shape(s)};
  } else {
    const auto classes = *s.table_array("classes");
    if (classes.empty()) s.fail("classes", "expected at least one size class");
    if (s.has("shape")) s.fail("shape", "each size class gives its own shape ([[particles.classes]] shape = {...})");
    source.component_material = read_classes(classes, spec, material_names, source.component_shape);
    const bool by_fraction = spec.classes.front().volume_fraction.has_value();
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

}  // namespace aggpack
