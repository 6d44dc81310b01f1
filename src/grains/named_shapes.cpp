// The named default shapes. Proportions are I/L (elongation) and S/I (flatness) means, each
// drawn ± 0.1 (triangular), as a component's shape table takes them. The values are
// representative, chosen to follow the literature's comparisons, not quoted from one source
// or one sample; the literature they follow:
//  - crushed stone: angular, I/L 0.67, S/I 0.6. Kwan, Mora and Chan (1999), "Particle shape
//    analysis of coarse aggregate using digital image processing", Cem. Concr. Res. 29,
//    1403-1410 (mean length/breadth and thickness/breadth of crushed rock aggregates).
//  - gravel: rounded and more equant than crushed rock (I/L 0.75, S/I 0.7). Fernlund (2005),
//    "Image analysis method for determining 3-D shape of coarse aggregate", Cem. Concr. Res.
//    35, 1629-1637 (L, I and S of every grain of a coarse aggregate, by image analysis).
//  - natural sand: rounded, nearly spherical (I/L 0.8, S/I 0.8). Cho, Dodds and Santamarina
//    (2006), "Particle shape effects on packing density, stiffness, and strength: natural and
//    crushed sands", J. Geotech. Geoenviron. Eng. 132(5), 591-602; Villalobos, Lange and
//    Roesler (2005), Univ. of Illinois Tech Note 15 (crushed manufactured and natural sands compared).
//  - manufactured sand: angular and cubical, some flat or elongated (I/L 0.7, S/I 0.65). Marek
//    (1995), "Importance of fine aggregate shape and grading on properties of concrete", ICAR
//    symposium (Vulcan Materials); Cho et al. (2006), crushed sands.
// Sands take fewer member spheres (6): their grains are many, and each member sphere costs.
#include "aggpack/grains/named_shapes.hpp"

#include <array>

namespace aggpack {

namespace {

struct NamedShape {
  std::string_view name;
  GrainFamily family;
  std::size_t spheres;
  double elongation, flatness;  // I/L and S/I means
};

constexpr std::array kNamedShapes{
    NamedShape{"crushed_stone", GrainFamily::Angular, 8, 0.67, 0.60},
    NamedShape{"gravel", GrainFamily::Rounded, 8, 0.75, 0.70},
    NamedShape{"natural_sand", GrainFamily::Rounded, 6, 0.80, 0.80},
    NamedShape{"manufactured_sand", GrainFamily::Angular, 6, 0.70, 0.65},
};

constexpr double kSpread = 0.1;

}  // namespace

std::optional<GrainShapeSpec> named_grain_shape(std::string_view name) {
  for (const NamedShape& n : kNamedShapes) {
    if (n.name != name) continue;
    GrainShapeSpec spec;
    spec.family = n.family;
    spec.spheres = n.spheres;
    spec.proportions = {n.elongation, kSpread, n.flatness, kSpread};
    return spec;
  }
  return std::nullopt;
}

std::vector<std::string_view> named_grain_shape_names() {
  std::vector<std::string_view> names;
  for (const NamedShape& n : kNamedShapes) names.push_back(n.name);
  return names;
}

}  // namespace aggpack
