// A sieve fraction alone in a periodic bed, filled by a lab test's procedure: the scenario the
// simulation route's beds run (blends/simulated_betas.cpp maps the beds onto betas).
#include "aggpack/labtests/class_bed.hpp"

#include <fmt/format.h>

#include <cmath>
#include <numbers>

#include "aggpack/core/error.hpp"
#include "test_scenario.hpp"

namespace aggpack {

namespace {

constexpr double kMm = 1e-3;
// The bed's height above its analysis cube: two largest particles at the floor, two below the
// surface (the analysis keeps one clear of each) and the loose top layer.
constexpr double kMarginSizes = 5.0;
// Narrower than this many rods, a periodic bed would meet the rod's own image across its side.
constexpr double kLeastRodsAcross = 3.0;

// The fraction as a grading of two sieves.
toml::table fraction_grading(const ClassBedSetup& s) {
  toml::array sieves;
  sieves.push_back(toml::table{{"opening", metres(s.d_lo)}, {"passing", 0.0}});
  sieves.push_back(toml::table{{"opening", metres(s.d_hi)}, {"passing", 100.0}});
  toml::table grading{{"sieves", sieves}};
  toml::table shape = material_table(s.material->file, "shape");
  if (!shape.empty()) grading.insert("shape", shape);
  return grading;
}

// What the test does to its measure, done to the bed: the procedure's steps and tables.
std::string fill(const ClassBedSetup& s, const ClassBed& bed, toml::table& root, std::vector<std::string>& modelling) {
  toml::array protocol;
  const bool rodding = s.test == LabTestKind::C29 && s.method == "rodding";
  const bool jigging = s.test == LabTestKind::C29 && s.method == "jigging";
  const bool rod_fits = bed.side_m >= kLeastRodsAcross * kC29RodDiameter;
  toml::table pour{{"solid_fraction", 0.2}};
  if (s.test == LabTestKind::C1252) {
    pour.insert("velocity", impact_speed(kC1252FunnelHeight));
    modelling.push_back(fmt::format("poured as C1252's funnel pours: arriving at {:.2f} m/s (a fall of {:.0f} mm)",
                                    impact_speed(kC1252FunnelHeight), kC1252FunnelHeight / kMm));
  } else if (!(rodding || jigging) || (rodding && !rod_fits)) {
    pour.insert("release_height", metres(bed.fill_height_m + kC29ShovelHeight));
    modelling.push_back(fmt::format("poured as C29's shovel: each particle arriving as if from {:.0f} mm above the "
                                    "bed's top{}",
                                    kC29ShovelHeight / kMm,
                                    rodding ? fmt::format(" (the bed, {:.1f} mm across, is narrower than {:g} rods: "
                                                          "rodding it would not be the lab's rodding)",
                                                          bed.side_m / kMm, kLeastRodsAcross)
                                            : ""));
  }
  root.insert("pour", pour);
  if ((rodding && rod_fits) || jigging) {
    for (int layer = 0; layer < kC29Layers; ++layer) {
      protocol.push_back(layer_step("pour", layer, kC29Layers));
      protocol.push_back(step(rodding ? "rod" : "jig"));
    }
    if (rodding) {
      // C29's 25 strokes a layer over its measure's section: the same strokes per area here.
      const Measure measure = c29_measure(s.d_hi, s.material->file.string());
      const double strokes = std::max(1.0, std::round(kC29StrokesPerLayer * bed.side_m * bed.side_m /
                                                      (0.25 * std::numbers::pi * std::pow(measure.diameter_m, 2))));
      root.insert("rodding", toml::table{{"strokes", static_cast<int>(strokes)},
                                         {"rod_diameter", metres(kC29RodDiameter)},
                                         {"penetration", metres(0.0)}});
      modelling.push_back(fmt::format("rodded as C29 rods: three layers, each poured then rodded with {:.0f} strokes "
                                      "of a {:.0f} mm rod, the standard's strokes per area of its {} measure",
                                      strokes, kC29RodDiameter / kMm, measure.name));
    } else {
      root.insert("jigging", toml::table{{"drops", kC29DropsPerLayer}, {"height", metres(kC29DropHeight)}});
      modelling.push_back(fmt::format("jigged as C29 jigs: three layers, each dropped {} times from {:.0f} mm",
                                      kC29DropsPerLayer, kC29DropHeight / kMm));
    }
    root.insert("protocol", protocol);
    return rodding ? "rodded" : "jigged";
  }
  protocol.push_back(layer_step("pour", 0, 1));
  root.insert("protocol", protocol);
  return "poured";
}

}  // namespace

ClassBed class_bed(const ClassBedSetup& s) {
  if (!(s.d_lo > 0.0 && s.d_lo < s.d_hi))
    throw InputError(fmt::format("{}: a size class {:g}-{:g} mm; expected 0 < d_lo < d_hi", s.material->file.string(),
                                 s.d_lo / kMm, s.d_hi / kMm));
  if (s.test == LabTestKind::C29 && s.method != "shovelling" && s.method != "rodding" && s.method != "jigging")
    throw InputError(fmt::format("{}: C29 method '{}'; expected shovelling, rodding or jigging",
                                 s.material->file.string(), s.method));
  ClassBed bed;
  const AggregateMaterial& m = *s.material;
  const double ratio = grain_volume_ratio(m);
  // The generator's particle of this fraction, the sphere of a size uniform in log d by volume,
  // has a mean volume of about pi/6 d_g^3 (d_g the geometric mean of the sieves).
  const double d_g = std::sqrt(s.d_lo * s.d_hi);
  const double particle = std::numbers::pi / 6.0 * d_g * d_g * d_g * ratio;
  const double packing = 0.6;
  // A square side W and a cube of side W in the bed: N = packing W^2 (W + margin) / particle.
  double side = std::cbrt(s.particles * particle / packing);
  for (int it = 0; it < 50; ++it)
    side = std::sqrt(s.particles * particle / (packing * (side + kMarginSizes * s.d_hi)));
  side = std::max(side, 5.0 * s.d_hi);  // drop-free periodic sides need more than four largest across
  bed.side_m = side;
  bed.fill_height_m = side + kMarginSizes * s.d_hi;

  const std::string title =
      fmt::format("{} alone, {:g}-{:g} mm, in a periodic bed, as {} {}", m.name, s.d_lo / kMm, s.d_hi / kMm,
                  s.test == LabTestKind::C29 ? "ASTM C29" : "ASTM C1252", s.method);
  toml::table root{{"title", title}, {"seed", 1}};
  root.insert("container", toml::table{{"side", metres(side)},
                                       {"height", metres(2.0 * bed.fill_height_m)},
                                       {"sides", "periodic"}});
  const double solid = side * side * bed.fill_height_m * packing;
  toml::table particles{{"solid_volume", solid / ratio}, {"grading", fraction_grading(s)}};
  root.insert("particles", particles);
  root.insert("material", material_keys(m, bed.modelling));
  bed.modelling.push_back(fmt::format(
      "the bed: the {:g}-{:g} mm fraction alone, periodic sides {:.2f} mm apart (no wall), filled about {:.2f} mm "
      "deep, about {:.0f} particles; its packing read in the largest cube clear of the floor and the surface",
      s.d_lo / kMm, s.d_hi / kMm, side / kMm, bed.fill_height_m / kMm, s.particles));
  bed.procedure = fill(s, bed, root, bed.modelling);
  root.insert("dynamics", toml::table{{"max_time", s.max_time_s}});
  root.insert("output", toml::table{{"formats", toml::array{}}, {"checkpoint", false}});
  bed.scenario_text = header(title, bed.modelling) + text_of(root);
  return bed;
}

}  // namespace aggpack
