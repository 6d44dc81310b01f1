// A lab test's scenario: the material's file and the standard's numbers written as a scenario
// the run engine runs (and a user can read and run again). Only the mapping lives here; the
// physics is the run engine's (the cylinder, the pour, rodding, jigging, the exact strike-off).
#include "test_scenario.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <cmath>
#include <numbers>
#include <sstream>

#include "aggpack/core/error.hpp"
#include "aggpack/grains/grain_library.hpp"

namespace aggpack {

namespace {

constexpr double kGravity = 9.81;
// The measure filled to overflowing, 15 % more than its volume at the expected density (a
// denser bed than expected still reaches above the rim), and at least two largest particles
// above the rim (a short representative measure's 15 % is less: its rim would cut the heap's
// loose surface layer).
constexpr double kOverfill = 0.15;
constexpr double kOverfillSizes = 2.0;
// The walls of the simulated measure go on above its rim, a collar holding the overfill that
// the lab lets heap above the rim before striking it off: 30 % of the rim, at least the overfill
// and two largest particles more.
constexpr double kCollar = 0.3;

double overfill(const SimulatedMeasure& m) {
  return std::max(kOverfill * m.rim_m, kOverfillSizes * m.largest_size_m);
}

}  // namespace

std::string metres(double m) { return fmt::format("{:.10g} m", m); }

// The material file's table `key` (none: an empty table), its `file` made absolute.
toml::table material_table(const std::filesystem::path& material_file, const std::string& key) {
  const toml::table root = material_file_tables(material_file);
  toml::table out;
  if (const toml::table* t = root[key].as_table()) out = *t;
  if (const auto* file = out.get_as<std::string>("file")) {
    const std::filesystem::path p(file->get());
    const std::filesystem::path folder = std::filesystem::absolute(material_file).parent_path();
    out.insert_or_assign("file", (p.is_absolute() ? p : folder / p).lexically_normal().string());
  }
  return out;
}

// The grains' Young's modulus when the material file gives none: a rock's 50 GPa over 1000, the
// DEM's reduced stiffness (a time step 30 times longer; the contacts' overlaps stay below 1e-3 of
// a radius under a measure's weight).
constexpr double kReducedYoungsModulus = 50e6;

// [material]: the aggregate's oven-dry particle density and the material file's contact keys.
toml::table material_keys(const AggregateMaterial& m, std::vector<std::string>& modelling) {
  toml::table t = material_table(m.file, "contact");
  t.insert_or_assign("density", oven_dry_particle_density(m));
  if (!t.contains("youngs_modulus")) {
    t.insert("youngs_modulus", kReducedYoungsModulus);
    modelling.push_back(fmt::format("reduced stiffness: the grains' Young's modulus {:g} Pa (a rock's 50 GPa / 1000), "
                                    "the material file giving none",
                                    kReducedYoungsModulus));
  }
  return t;
}

namespace {

toml::table cylinder(const SimulatedMeasure& m) {
  const double collar = std::max(kCollar * m.rim_m, overfill(m) + kOverfillSizes * m.largest_size_m);
  return toml::table{{"shape", "cylinder"},
                     {"diameter", metres(m.diameter_m)},
                     {"height", metres(m.rim_m + collar)},
                     {"rim", metres(m.rim_m)}};
}

// The amount: the measure filled to overflowing at the expected packing. Grains are counted as
// the generator counts them, each the sphere of its size: their own solid is less by the ratio.
toml::table amount(const SimulatedMeasure& m, double expected_packing, std::vector<std::string>& modelling) {
  const double fill = m.rim_m + overfill(m);
  if (m.grain_volume_ratio == 1.0)
    return toml::table{{"fill_height", metres(fill)}, {"expected_density", expected_packing}};
  const double solid = 0.25 * std::numbers::pi * m.diameter_m * m.diameter_m * fill * expected_packing;
  modelling.push_back(fmt::format(
      "the amount: the grains' solid for the measure filled {:.1f} mm deep at a packing of {:.3f}, generated as "
      "solid_volume {:.4g} m^3 (the generator counts each grain as the sphere of its sieve size; the grains' own "
      "volume is {:.3f} of that, the mean of their templates)",
      fill * 1e3, expected_packing, solid / m.grain_volume_ratio, m.grain_volume_ratio));
  return toml::table{{"solid_volume", solid / m.grain_volume_ratio}};
}

}  // namespace

toml::table step(std::string kind) { return toml::table{{"step", std::move(kind)}}; }
toml::table layer_step(std::string kind, int layer, int layers) {
  toml::table t = step(std::move(kind));
  t.insert("layer", layer);
  t.insert("layers", layers);
  return t;
}

// The header: what the file is and every modelling choice, as TOML comments.
std::string header(const std::string& title, const std::vector<std::string>& modelling) {
  std::string out = fmt::format("# {}\n# Written by aggpack test; run it again with `aggpack run`.\n", title);
  for (const std::string& m : modelling) out += fmt::format("# - {}\n", m);
  return out + "\n";
}

double impact_speed(double height) { return std::sqrt(2.0 * kGravity * height); }

std::string text_of(const toml::table& root) {
  std::ostringstream os;
  os << toml::toml_formatter{root};
  return os.str() + "\n";
}

double grain_volume_ratio(const AggregateMaterial& m) {
  if (!m.shape) return 1.0;
  // The sizes the library is fitted at (a shape measure's fit needs them): the grading's sieves.
  std::vector<double> sizes;
  for (const Sieve& s : m.grading.grading.sieves)
    if (s.opening > m.grading.grading.smallest()) sizes.push_back(s.opening);
  // Twice the templates a run draws: a library of 12 varies by some 5 % in this mean (the
  // overfill covers what is left, and the run checks that the bed reached above the rim).
  GrainShapeSpec spec = *m.shape;
  spec.templates = 2 * spec.templates;
  const GrainLibrary library = make_grain_library(spec, sizes, 1);
  double sum = 0.0;
  for (const LibraryGrain& g : library.grains) {
    const double reach_per_width = g.reach / g.grain.dimensions.width;
    sum += g.unit_volume * std::pow(reach_per_width, 3) / (std::numbers::pi / 6.0);
  }
  return sum / static_cast<double>(library.grains.size());
}

double expected_packing(const AggregateMaterial& m, LabTestKind test) {
  if (test == LabTestKind::C29 && m.c29) return 1.0 - voids_percent(m, m.c29->kg_per_m3) / 100.0;
  if (test == LabTestKind::C1252 && m.c1252) return 1.0 - m.c1252->percent / 100.0;
  return test == LabTestKind::C29 ? 0.6 : 0.57;
}

std::string c29_scenario(const C29Setup& s, std::vector<std::string>& modelling) {
  const AggregateMaterial& m = *s.material;
  const std::string title = fmt::format("ASTM C29 {}: {}", name_of(kC29MethodNames, s.method), m.name);
  toml::table root{{"title", title}, {"seed", 1}};
  root.insert("container", cylinder(s.simulated));
  toml::table particles = amount(s.simulated, s.expected_packing, modelling);
  toml::table grading = material_table(m.file, "grading");
  if (s.cut_off_m > 0.0) grading.insert_or_assign("d_min", metres(s.cut_off_m));
  toml::table shape = material_table(m.file, "shape");
  if (!shape.empty()) grading.insert_or_assign("shape", shape);
  particles.insert("grading", grading);
  root.insert("particles", particles);
  root.insert("material", material_keys(m, modelling));

  // Each layer a random gas that comes in just above the bed. Shovelled, it arrives as from the
  // standard's shovel, discharged from 50 mm above the rim: each grain at the speed of a fall
  // from there.
  toml::table pour{{"solid_fraction", 0.2}, {"batches", s.method == C29Method::Shovelling ? 3 : 1}};
  if (s.method == C29Method::Shovelling) pour.insert("release_height", metres(s.simulated.rim_m + kC29ShovelHeight));
  root.insert("pour", pour);
  toml::table dynamics{{"max_time", s.max_time_s}};
  root.insert("dynamics", dynamics);

  toml::array protocol;
  if (s.method == C29Method::Shovelling) {
    protocol.push_back(layer_step("pour", 0, 1));
    modelling.push_back(fmt::format(
        "shovelling: the aggregate poured as a random gas in batches, each grain arriving as if discharged from "
        "{:.0f} mm above the rim (the standard's most), at the speed of a free fall from there; the shovel's stream "
        "(where it lands, how fast it flows) is not modelled",
        kC29ShovelHeight * 1e3));
  } else {
    for (int layer = 0; layer < kC29Layers; ++layer) {
      protocol.push_back(layer_step("pour", layer, kC29Layers));
      protocol.push_back(step(s.method == C29Method::Rodding ? "rod" : "jig"));
    }
    if (s.method == C29Method::Rodding) {
      // C29: the bottom layer rodded through its depth, not striking the floor; the others
      // "to the previous layer" (the rod reaches its top: no penetration into it).
      root.insert("rodding", toml::table{{"strokes", kC29StrokesPerLayer},
                                         {"rod_diameter", metres(kC29RodDiameter)},
                                         {"penetration", metres(0.0)}});
    } else {
      root.insert("jigging", toml::table{{"drops", kC29DropsPerLayer}, {"height", metres(kC29DropHeight)}});
    }
    modelling.push_back(
        s.method == C29Method::Rodding
            ? fmt::format("rodding: {} strokes a layer, spread evenly over it, of a rigid {:.0f} mm rod with a "
                          "hemispherical tip, driven down and up (a stroke stops where the bed pushes back harder than "
                          "a hand's push), the bottom layer to just above the floor, the others to the top of the layer "
                          "below",
                          kC29StrokesPerLayer, kC29RodDiameter * 1e3)
            : fmt::format("jigging: {} drops a layer of the whole measure, lifted level {:.0f} mm and falling freely onto "
                          "a rigid base (the standard raises one side at a time: the tilt is not modelled)",
                          kC29DropsPerLayer, kC29DropHeight * 1e3));
  }
  root.insert("protocol", protocol);
  root.insert("output", toml::table{{"formats", toml::array{}}, {"checkpoint", false}});

  modelling.push_back(fmt::format(
      "the measure: {} modelled as a steel cylinder {:.1f} mm across and {:.1f} mm high (C29 6.1: height about "
      "the diameter), filled {:.0f} mm above its rim, its wall continued above the rim as a collar that holds "
      "the overfill",
      s.measure.name, s.measure.diameter_m * 1e3, s.measure.height_m * 1e3, overfill(s.simulated) * 1e3));
  modelling.push_back(
      "strike-off: the content below the rim plane, cut exactly (projections above the rim balance the voids "
      "below it, as C29 asks); the particles whose centre is below the rim, counted whole, are given beside it");
  return header(title, modelling) + text_of(root);
}

std::string c1252_scenario(const C1252Setup& s, std::vector<std::string>& modelling) {
  const AggregateMaterial& m = *s.material;
  const std::string title = fmt::format("ASTM C1252 {}: {}", s.label, m.name);
  toml::table root{{"title", title}, {"seed", 1}};
  root.insert("container", cylinder(s.simulated));
  toml::table particles = amount(s.simulated, s.expected_packing, modelling);
  toml::table grading;
  if (s.standard_grading) {
    toml::array sieves;
    for (const Sieve& sv : s.standard_grading->sieves)
      sieves.push_back(toml::table{{"opening", metres(sv.opening)}, {"passing", sv.percent_passing}});
    grading.insert("sieves", sieves);
  } else {
    grading = material_table(m.file, "grading");
    if (m.grading.grading.largest() > kC1252MethodCLargest)  // C1252 C: the sand passing 4.75 mm
      grading.insert_or_assign("d_max", metres(kC1252MethodCLargest));
  }
  if (s.cut_off_m > 0.0) grading.insert_or_assign("d_min", metres(s.cut_off_m));
  toml::table shape = material_table(m.file, "shape");
  if (!shape.empty()) grading.insert_or_assign("shape", shape);
  particles.insert("grading", grading);
  root.insert("particles", particles);
  root.insert("material", material_keys(m, modelling));
  // The funnel's stream reaches the heap at the speed of a fall from the funnel's height.
  root.insert("pour", toml::table{{"solid_fraction", 0.2},
                                  {"batches", 4},
                                  {"velocity", impact_speed(kC1252FunnelHeight)}});
  root.insert("dynamics", toml::table{{"max_time", s.max_time_s}});
  toml::array protocol;
  protocol.push_back(layer_step("pour", 0, 1));
  root.insert("protocol", protocol);
  root.insert("output", toml::table{{"formats", toml::array{}}, {"checkpoint", false}});
  modelling.push_back(fmt::format(
      "the funnel: the sand poured as a random gas over the measure's cross-section, arriving at {:.2f} m/s (a "
      "free fall from the funnel {:.0f} mm above the rim); the stream's narrow jet and its flow rate are not modelled",
      impact_speed(kC1252FunnelHeight), kC1252FunnelHeight * 1e3));
  return header(title, modelling) + text_of(root);
}

}  // namespace aggpack
