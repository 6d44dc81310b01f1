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

// What a bed is filled by: a test's procedure, for its largest particles.
struct Procedure {
  LabTestKind test = LabTestKind::C29;
  std::string method;
  double d_hi = 0.0;   // m: the largest particles (C29's measure for them sets the strokes per area)
  std::string source;  // the material file, for messages
};

// What the test does to its measure, done to the bed: the procedure's steps and tables.
std::string fill(const Procedure& s, const ClassBed& bed, toml::table& root, std::vector<std::string>& modelling) {
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
    modelling.push_back(
        fmt::format("poured as C29's shovel: each particle arriving as if from {:.0f} mm above the "
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
      const Measure measure = c29_measure(s.d_hi, s.source);
      const double strokes = std::max(1.0, std::round(kC29StrokesPerLayer * bed.side_m * bed.side_m /
                                                      (0.25 * std::numbers::pi * std::pow(measure.diameter_m, 2))));
      root.insert("rodding", toml::table{{"strokes", static_cast<int>(strokes)},
                                         {"rod_diameter", metres(kC29RodDiameter)},
                                         {"penetration", metres(0.0)}});
      modelling.push_back(
          fmt::format("rodded as C29 rods: three layers, each poured then rodded with {:.0f} strokes "
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

void check_method(LabTestKind test, const std::string& method, const std::filesystem::path& file) {
  if (test == LabTestKind::C29 && method != "shovelling" && method != "rodding" && method != "jigging")
    throw InputError(
        fmt::format("{}: C29 method '{}'; expected shovelling, rodding or jigging", file.string(), method));
}

// The side W of a periodic square holding a bed W + margin deep whose solid is `particles`
// particles of volume `particle` at a packing of 0.6; at least five `d_hi` (drop-free periodic
// sides need more than four largest across).
double bed_side(double particles, double particle, double margin, double d_hi) {
  constexpr double kPacking = 0.6;
  double side = std::cbrt(particles * particle / kPacking);
  for (int it = 0; it < 50; ++it) side = std::sqrt(particles * particle / (kPacking * (side + margin)));
  return std::max(side, 5.0 * d_hi);
}

toml::table periodic_container(const ClassBed& bed) {
  return toml::table{{"side", metres(bed.side_m)}, {"height", metres(2.0 * bed.fill_height_m)}, {"sides", "periodic"}};
}

toml::table material_file_table(const AggregateMaterial& m, std::vector<std::string>& modelling) {
  toml::table t{{"file", std::filesystem::absolute(m.file).lexically_normal().string()}};
  if (!material_table(m.file, "contact").contains("youngs_modulus")) {
    toml::table keys = material_keys(m, modelling);  // says the reduced stiffness
    t.insert("youngs_modulus", *keys.get("youngs_modulus"));
  }
  return t;
}

}  // namespace

ClassBed class_bed(const ClassBedSetup& s) {
  if (!(s.d_lo > 0.0 && s.d_lo < s.d_hi))
    throw InputError(fmt::format("{}: a size class {:g}-{:g} mm; expected 0 < d_lo < d_hi", s.material->file.string(),
                                 s.d_lo / kMm, s.d_hi / kMm));
  check_method(s.test, s.method, s.material->file);
  ClassBed bed;
  const AggregateMaterial& m = *s.material;
  const double ratio = grain_volume_ratio(m);
  // The generator's particle of this fraction, the sphere of a size uniform in log d by volume,
  // has a mean volume of about pi/6 d_g^3 (d_g the geometric mean of the sieves).
  const double d_g = std::sqrt(s.d_lo * s.d_hi);
  const double particle = std::numbers::pi / 6.0 * d_g * d_g * d_g * ratio;
  const double packing = 0.6;
  const double side = bed_side(s.particles, particle, kMarginSizes * s.d_hi, s.d_hi);
  bed.side_m = side;
  bed.fill_height_m = side + kMarginSizes * s.d_hi;

  const std::string title = fmt::format("{} alone, {:g}-{:g} mm, in a periodic bed, as {} {}", m.name, s.d_lo / kMm,
                                        s.d_hi / kMm, s.test == LabTestKind::C29 ? "ASTM C29" : "ASTM C1252", s.method);
  toml::table root{{"title", title}, {"seed", 1}};
  root.insert("container", periodic_container(bed));
  const double solid = side * side * bed.fill_height_m * packing;
  toml::table particles{{"solid_volume", solid / ratio}, {"grading", fraction_grading(s)}};
  root.insert("particles", particles);
  root.insert("material", material_keys(m, bed.modelling));
  bed.modelling.push_back(fmt::format(
      "the bed: the {:g}-{:g} mm fraction alone, periodic sides {:.2f} mm apart (no wall), filled about {:.2f} mm "
      "deep, about {:.0f} particles; its packing read in the largest cube clear of the floor and the surface",
      s.d_lo / kMm, s.d_hi / kMm, side / kMm, bed.fill_height_m / kMm, s.particles));
  bed.procedure = fill({s.test, s.method, s.d_hi, m.file.string()}, bed, root, bed.modelling);
  root.insert("dynamics", toml::table{{"max_time", s.max_time_s}});
  root.insert("output", toml::table{{"formats", toml::array{}}, {"checkpoint", false}});
  bed.scenario_text = header(title, bed.modelling) + text_of(root);
  return bed;
}

ClassBed blend_bed(const BlendBedSetup& s) {
  const AggregateMaterial& coarse = *s.coarse;
  const AggregateMaterial& fine = *s.fine;
  check_method(s.test, s.method, coarse.file);
  if (!(s.fine_volume_fraction > 0.0 && s.fine_volume_fraction < 1.0))
    throw InputError(fmt::format("a blend bed's fine fraction {}; expected between 0 and 1", s.fine_volume_fraction));
  ClassBed bed;
  const double d_max = std::max(maximum_size(coarse.grading.grading), maximum_size(fine.grading.grading));
  // The coarse material's mean particle, the sphere of its sieve sizes: pi/6 d^3 by volume.
  const ModelDistribution classes = grading_classes(coarse.grading.grading);
  double inverse_volume = 0.0;  // per unit solid, the number of particles
  for (const ModelClass& c : classes.classes) inverse_volume += c.volume_fraction / std::pow(c.diameter, 3);
  const double coarse_particle = std::numbers::pi / 6.0 / inverse_volume;
  const double coarse_share = 1.0 - s.fine_volume_fraction;
  const double side = bed_side(s.coarse_particles / coarse_share, coarse_particle, kMarginSizes * d_max, d_max);
  bed.side_m = side;
  bed.fill_height_m = side + kMarginSizes * d_max;
  // The generator counts a grain as the sphere of its size: each material's amount divided by
  // its grains' volume ratio, the ratio of the two as the generator's coarse/fine.
  const double r_coarse = grain_volume_ratio(coarse), r_fine = grain_volume_ratio(fine);
  const double solid = side * side * bed.fill_height_m * 0.6;
  const double generated = solid * (coarse_share / r_coarse + s.fine_volume_fraction / r_fine);
  const double ca_fa = (coarse_share / r_coarse) / (s.fine_volume_fraction / r_fine);

  const std::string title =
      fmt::format("{} and {} ({:.1f} % by volume), in a periodic bed, as {} {}", coarse.name, fine.name,
                  100.0 * s.fine_volume_fraction, s.test == LabTestKind::C29 ? "ASTM C29" : "ASTM C1252", s.method);
  toml::table root{{"title", title}, {"seed", 1}};
  root.insert("container", periodic_container(bed));
  toml::table fine_component{{"material", "fine"}};
  if (s.fine_d_min > 0.0) fine_component.insert("d_min", metres(s.fine_d_min));
  root.insert("particles", toml::table{{"solid_volume", generated},
                                       {"ca_fa", ca_fa},
                                       {"coarse", toml::table{{"material", "coarse"}}},
                                       {"fine", fine_component}});
  std::vector<std::string> stiffness;  // said once, for both
  root.insert("materials", toml::table{{"coarse", material_file_table(coarse, stiffness)},
                                       {"fine", material_file_table(fine, stiffness)}});
  if (!stiffness.empty()) bed.modelling.push_back(stiffness.front());
  bed.modelling.push_back(fmt::format(
      "the bed: {} and {} at {:.1f} % of the solid volume{}, periodic sides {:.2f} mm apart (no wall), filled about "
      "{:.2f} mm deep; its packing read in the largest cube clear of the floor and the surface",
      coarse.name, fine.name, 100.0 * s.fine_volume_fraction,
      s.fine_d_min > 0.0 ? fmt::format(" (cut at {:g} mm)", s.fine_d_min / kMm) : "", side / kMm,
      bed.fill_height_m / kMm));
  if (r_coarse != 1.0 || r_fine != 1.0)
    bed.modelling.push_back(
        fmt::format("the amounts: the generator's coarse/fine ratio {:.4g}, the grains' own volume "
                    "ratios {:.3f} and {:.3f} taken out",
                    ca_fa, r_coarse, r_fine));
  bed.procedure = fill({s.test, s.method, d_max, coarse.file.string()}, bed, root, bed.modelling);
  root.insert("dynamics", toml::table{{"max_time", s.max_time_s}});
  root.insert("output", toml::table{{"formats", toml::array{}}, {"checkpoint", false}});
  bed.scenario_text = header(title, bed.modelling) + text_of(root);
  return bed;
}

}  // namespace aggpack
