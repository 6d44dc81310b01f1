// Several materials in one run: the coefficients of a pair of them (Hertz and Mindlin from
// both moduli, the geometric mean of the rest unless a pair gives its own), of a material
// against the walls, and the DEM's use of them contact by contact, checked against Hertz's
// static overlap and the motion of a sphere on an incline.
#include "aggpack/dynamics/materials.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <variant>
#include <vector>

#include "aggpack/core/error.hpp"
#include "aggpack/core/rng.hpp"
#include "aggpack/deposition/drop_and_roll.hpp"
#include "aggpack/dynamics/dem_system.hpp"

namespace aggpack {
namespace {

constexpr double kG = 9.81;
constexpr double kDensity = 2650.0;

ContactParameters soft(double modulus, double poisson) {
  ContactParameters p;
  p.youngs_modulus = modulus;
  p.poisson_ratio = poisson;
  p.wall_youngs_modulus = 1e8;
  p.wall_poisson_ratio = 0.3;
  return p;
}

// Three materials of different moduli and coefficients; material 0 gives the walls.
std::vector<ContactParameters> three_materials() {
  ContactParameters a = soft(1e8, 0.3), b = soft(3e8, 0.2), c = soft(5e7, 0.35);
  a.friction_particle = 0.2, b.friction_particle = 0.8, c.friction_particle = 0.45;
  a.friction_wall = 0.1, b.friction_wall = 0.6, c.friction_wall = 0.3;
  a.restitution = 0.3, b.restitution = 0.8, c.restitution = 0.5;
  a.rolling_friction = 0.01, b.rolling_friction = 0.04, c.rolling_friction = 0.02;
  b.wall_youngs_modulus = 7e9;  // the walls are material 0's: these are never read
  c.wall_poisson_ratio = 0.1;
  return {a, b, c};
}

ContactCoefficients coefficients_of(const ContactLaw& law) {
  return std::visit([](const auto& l) { return l.c; }, law);
}

void expect_same(const ContactCoefficients& x, const ContactCoefficients& y, const char* what) {
  EXPECT_EQ(x.e_star, y.e_star) << what;
  EXPECT_EQ(x.g_star, y.g_star) << what;
  EXPECT_EQ(x.damping, y.damping) << what;
  EXPECT_EQ(x.friction, y.friction) << what;
  EXPECT_EQ(x.rolling, y.rolling) << what;
  EXPECT_EQ(x.rolling_model, y.rolling_model) << what;
  EXPECT_EQ(x.rolling_stiffness, y.rolling_stiffness) << what;
  EXPECT_EQ(x.rolling_damping, y.rolling_damping) << what;
}

TEST(Materials, APairTakesHertzAndMindlinModuliAndTheGeometricMeanOfTheRest) {
  const auto m = three_materials();
  for (std::size_t a = 0; a < 3; ++a)
    for (std::size_t b = 0; b < 3; ++b) {
      const ContactCoefficients c = pair_coefficients(m, {}, a, b);
      expect_same(c, pair_coefficients(m, {}, b, a), "symmetry");
      EXPECT_DOUBLE_EQ(c.e_star, 1.0 / ((1 - m[a].poisson_ratio * m[a].poisson_ratio) / m[a].youngs_modulus +
                                        (1 - m[b].poisson_ratio * m[b].poisson_ratio) / m[b].youngs_modulus));
      const double ga = m[a].youngs_modulus / (2 * (1 + m[a].poisson_ratio));
      const double gb = m[b].youngs_modulus / (2 * (1 + m[b].poisson_ratio));
      EXPECT_DOUBLE_EQ(c.g_star, 1.0 / ((2 - m[a].poisson_ratio) / ga + (2 - m[b].poisson_ratio) / gb));
      EXPECT_DOUBLE_EQ(c.friction, std::sqrt(m[a].friction_particle * m[b].friction_particle));
      EXPECT_DOUBLE_EQ(c.rolling, std::sqrt(m[a].rolling_friction * m[b].rolling_friction));
      const double e = std::sqrt(m[a].restitution * m[b].restitution);
      EXPECT_DOUBLE_EQ(c.damping, damping_for_restitution(e));
      // The damping gives back the mixed restitution (an independent check of the inversion).
      EXPECT_NEAR(restitution_of_damping(c.damping), e, 1e-6);
      EXPECT_EQ(c.rolling_model, RollingModel::ConstantTorque);
      EXPECT_EQ(c.rolling_stiffness, 0.0);
    }
  // Not the arithmetic mean: 0.2 and 0.8 give 0.4.
  EXPECT_DOUBLE_EQ(pair_coefficients(m, {}, 0, 1).friction, 0.4);
}

TEST(Materials, APairsOwnCoefficientsWinAndTheOthersAreMixed) {
  const auto m = three_materials();
  MaterialPairCoefficients given;
  given.first = 0, given.second = 2;
  given.friction = 0.9;
  given.restitution = 0.65;
  const std::vector<MaterialPairCoefficients> pairs{given};
  for (const auto& [a, b] : {std::pair{0u, 2u}, std::pair{2u, 0u}}) {
    const ContactCoefficients c = pair_coefficients(m, pairs, a, b);
    EXPECT_EQ(c.friction, 0.9);
    EXPECT_DOUBLE_EQ(c.damping, damping_for_restitution(0.65));
    EXPECT_DOUBLE_EQ(c.rolling, std::sqrt(m[0].rolling_friction * m[2].rolling_friction));  // not given: mixed
    EXPECT_EQ(c.e_star, pair_coefficients(m, {}, a, b).e_star);
  }
  // Other pairs are untouched by it.
  expect_same(pair_coefficients(m, pairs, 0, 1), pair_coefficients(m, {}, 0, 1), "another pair");
  expect_same(pair_coefficients(m, pairs, 2, 2), pair_coefficients(m, {}, 2, 2), "a material with itself");
  const PairValues v = pair_values(m, pairs, 2, 0);
  EXPECT_EQ(v.friction, 0.9);
  EXPECT_EQ(v.restitution, 0.65);
}

TEST(Materials, TheRollingSpringIsMixedOrThePairsUnderTheRunsRollingModel) {
  auto m = three_materials();
  for (ContactParameters& p : m) p.rolling_model = RollingModel::SpringDashpot;
  m[0].rolling_stiffness = 100.0, m[1].rolling_stiffness = 400.0, m[2].rolling_stiffness = 900.0;
  m[0].rolling_damping = 0.5, m[1].rolling_damping = 2.0, m[2].rolling_damping = 1.0;
  const ContactCoefficients c = pair_coefficients(m, {}, 0, 1);
  EXPECT_EQ(c.rolling_model, RollingModel::SpringDashpot);
  EXPECT_DOUBLE_EQ(c.rolling_stiffness, 200.0);
  EXPECT_DOUBLE_EQ(c.rolling_damping, 1.0);
  MaterialPairCoefficients given;
  given.first = 1, given.second = 2;
  given.rolling_stiffness = 321.0;
  const ContactCoefficients g = pair_coefficients(m, std::vector{given}, 2, 1);
  EXPECT_EQ(g.rolling_stiffness, 321.0);
  EXPECT_DOUBLE_EQ(g.rolling_damping, std::sqrt(2.0));
  // The wall takes the material's own spring.
  EXPECT_EQ(wall_coefficients(m, 2).rolling_stiffness, 900.0);
}

TEST(Materials, AMaterialMeetsTheWallsOfMaterialZero) {
  const auto m = three_materials();
  for (std::size_t a = 0; a < 3; ++a) {
    const ContactCoefficients c = wall_coefficients(m, a);
    EXPECT_DOUBLE_EQ(c.e_star, effective_youngs_modulus(m[a].youngs_modulus, m[a].poisson_ratio,
                                                        m[0].wall_youngs_modulus, m[0].wall_poisson_ratio));
    EXPECT_DOUBLE_EQ(c.g_star, effective_shear_modulus(m[a].youngs_modulus, m[a].poisson_ratio,
                                                       m[0].wall_youngs_modulus, m[0].wall_poisson_ratio));
    EXPECT_EQ(c.friction, m[a].friction_wall);
    EXPECT_DOUBLE_EQ(c.damping, damping_for_restitution(m[a].restitution));
    EXPECT_EQ(c.rolling, m[a].rolling_friction);
  }
}

TEST(Materials, TheModelOfOneMaterialIsTheSingleMaterialModel) {
  for (const char* law : {"mindlin", "fu2003"}) {
    ContactParameters p = three_materials()[1];
    p.friction_model = law;
    const ContactModel one = make_contact_model(p);
    const ContactModel listed = make_contact_model(std::vector{p}, {});
    EXPECT_EQ(listed.materials, 1u);
    EXPECT_TRUE(listed.pairs.empty());
    EXPECT_TRUE(listed.walls.empty());
    EXPECT_EQ(listed.particle.index(), one.particle.index()) << law;
    expect_same(coefficients_of(listed.particle), coefficients_of(one.particle), law);
    expect_same(coefficients_of(listed.wall), coefficients_of(one.wall), law);
  }
}

TEST(Materials, TheModelOfSeveralHoldsEachPairAndEachWall) {
  const auto m = three_materials();
  MaterialPairCoefficients given;
  given.first = 1, given.second = 2;
  given.friction = 0.05;
  const std::vector<MaterialPairCoefficients> pairs{given};
  const ContactModel model = make_contact_model(m, pairs);
  ASSERT_EQ(model.materials, 3u);
  ASSERT_EQ(model.pairs.size(), 9u);
  ASSERT_EQ(model.walls.size(), 3u);
  for (std::size_t a = 0; a < 3; ++a) {
    expect_same(coefficients_of(model.walls[a]), wall_coefficients(m, a), "wall");
    for (std::size_t b = 0; b < 3; ++b)
      expect_same(coefficients_of(model.pairs[a * 3 + b]), pair_coefficients(m, pairs, a, b), "pair");
  }
  EXPECT_EQ(coefficients_of(model.pairs[2 * 3 + 1]).friction, 0.05);
  // A bad parameter of a named material is refused with its index.
  auto bad = m;
  bad[2].restitution = 0.0;
  try {
    (void)make_contact_model(bad, {});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("material 2"), std::string::npos) << e.what();
  }
}

// ---- The DEM with several materials ----------------------------------------------------

// A deposited bed of `count` spheres, 4-6 mm radius, in a 6 cm box.
ParticleStore deposited_bed(std::size_t count, std::uint64_t seed) {
  Rng sizes(seed, 1);
  std::vector<double> radii(count);
  for (double& r : radii) r = sizes.uniform(0.004, 0.006);
  ParticleStore bed;
  DropAndRoll deposition(bed, Container::square(0.06, 1.0, false), radii, DepositionSettings{}, Rng(seed, 2));
  deposition.deposit(radii, SphereMaterials::all_of(kDensity));
  return bed;
}

// Two materials of the same parameters are one material: the DEM evaluates them contact by
// contact with the pair's law, and must give the bytes of the one-material kernel.
TEST(MaterialsDem, TwoIdenticalMaterialsGiveTheBytesOfOne) {
  const ParticleStore deposited = deposited_bed(200, 11);
  const Container box = Container::square(0.06, 1.0, false);
  ContactParameters p = soft(1e8, 0.3);
  p.friction_particle = 0.4, p.friction_wall = 0.3, p.rolling_friction = 0.02;
  const auto run = [&](const ContactModel& model, bool split) {
    ParticleStore bed = deposited;
    if (split)
      for (std::size_t i = 0; i < bed.size(); i += 2) bed.material[i] = 1;
    DemSettings settings;
    settings.time_step = 2e-5;
    settings.threads = 1;
    DemSystem dem(bed, box, model, settings);
    dem.run(400);
    return bed;
  };
  const ParticleStore one = run(make_contact_model(p), false);
  const ParticleStore two = run(make_contact_model(std::vector{p, p}, {}), true);
  ASSERT_EQ(one.size(), two.size());
  EXPECT_EQ(0, std::memcmp(one.position.data(), two.position.data(), one.size() * sizeof(Vec3)));
  EXPECT_EQ(0, std::memcmp(one.velocity.data(), two.velocity.data(), one.size() * sizeof(Vec3)));
  EXPECT_EQ(0, std::memcmp(one.angular_velocity.data(), two.angular_velocity.data(), one.size() * sizeof(Vec3)));
  double moved = 0.0;
  for (std::size_t i = 0; i < one.size(); ++i) moved = std::max(moved, norm(one.position[i] - deposited.position[i]));
  EXPECT_GT(moved, 1e-6);  // the bed was settling: not a comparison of two copies of the start
  // And a second material that differs does change the result (the material array is read).
  ContactParameters q = p;
  q.youngs_modulus = 3e8;
  const ParticleStore other = run(make_contact_model(std::vector{p, q}, {}), true);
  EXPECT_NE(0, std::memcmp(one.position.data(), other.position.data(), one.size() * sizeof(Vec3)));
}

// Material 1 on the floor and material 2 on a frozen sphere of material 1; material 0 only
// gives the walls (E = 1e8) and is worn by nothing. Hertz's static overlaps with each pair's E*.
TEST(MaterialsDem, RestingSpheresTakeTheirPairsHertzOverlap) {
  ContactParameters zero = soft(2e9, 0.2), a = soft(1.5e8, 0.25), b = soft(6e7, 0.35);
  for (ContactParameters* p : {&zero, &a, &b}) p->restitution = 0.3, p->friction_particle = p->friction_wall = 0.5;
  const std::vector<ContactParameters> m{zero, a, b};
  const double ra = 0.01, rb = 0.006, density_a = 2650.0, density_b = 1800.0;
  ParticleStore store;
  store.add({0.05, 0.05, ra}, ra, density_a, 0, 1);            // A on the floor
  store.add({0.15, 0.05, ra}, ra, density_a, 0, 1);            // A, frozen
  store.add({0.15, 0.05, 2 * ra + rb}, rb, density_b, 0, 2);   // B on it
  DemSettings settings;
  settings.time_step = 5e-6;
  DemSystem dem(store, Container::square(0.2, 0.1, false), make_contact_model(m, {}), settings, {0, 1, 0});
  dem.run(60000);
  const double e_wall = effective_youngs_modulus(a.youngs_modulus, a.poisson_ratio, zero.wall_youngs_modulus,
                                                 zero.wall_poisson_ratio);
  const double on_floor = hertz_static_overlap(store.mass[0] * kG, e_wall, ra);
  EXPECT_NEAR(ra - store.position[0].z, on_floor, 0.01 * on_floor);
  const double e_ab = effective_youngs_modulus(a.youngs_modulus, a.poisson_ratio, b.youngs_modulus, b.poisson_ratio);
  const double on_sphere = hertz_static_overlap(store.mass[2] * kG, e_ab, ra * rb / (ra + rb));
  EXPECT_NEAR(ra + rb - (store.position[2].z - store.position[1].z), on_sphere, 0.01 * on_sphere);
  EXPECT_LT(std::abs(store.velocity[2].z), 1e-6);
  // The masses are the materials' densities'.
  EXPECT_DOUBLE_EQ(store.mass[2], density_b * 4.0 / 3.0 * std::numbers::pi * rb * rb * rb);
  // The pair's E* differs from the walls' and from either material with itself by more than
  // the tolerance: the check tells them apart.
  EXPECT_GT(std::abs(hertz_static_overlap(store.mass[2] * kG, e_wall, ra * rb / (ra + rb)) - on_sphere),
            0.05 * on_sphere);
}

// On a floor tilted by theta (gravity tilted instead), a sphere of a frictionless material
// slides at g sin(theta) and one of a rough material rolls at (5/7) g sin(theta), side by side.
TEST(MaterialsDem, AFrictionlessSphereSlidesAndARoughOneRolls) {
  const double theta = 20.0 * std::numbers::pi / 180.0, r = 0.01;
  ContactParameters zero = soft(1e8, 0.3), smooth = zero, rough = zero;
  zero.friction_wall = 0.3;
  smooth.friction_wall = 0.0, smooth.friction_particle = 0.0;
  rough.friction_wall = 1.0, rough.friction_particle = 1.0;
  const std::vector<ContactParameters> m{zero, smooth, rough};
  const double e_wall = effective_youngs_modulus(1e8, 0.3, 1e8, 0.3);
  const double weight_normal = kDensity * 4.0 / 3.0 * std::numbers::pi * r * r * r * kG * std::cos(theta);
  const double overlap = hertz_static_overlap(weight_normal, e_wall, r);
  ParticleStore store;
  store.add({0.2, 0.03, r - overlap}, r, kDensity, 0, 1);
  store.add({0.2, 0.07, r - overlap}, r, kDensity, 0, 2);
  DemSettings settings;
  settings.gravity = {kG * std::sin(theta), 0, -kG * std::cos(theta)};
  settings.time_step = 1e-5;
  DemSystem dem(store, Container::square(1.0, 0.1, false), make_contact_model(m, {}), settings);
  dem.run(5000);
  const Vec3 v1{store.velocity[0].x, store.velocity[1].x, 0};
  const double t1 = dem.time();
  dem.run(20000);
  const double dt = dem.time() - t1;
  const double slides = (store.velocity[0].x - v1.x) / dt, rolls = (store.velocity[1].x - v1.y) / dt;
  const double g_sin = kG * std::sin(theta);
  EXPECT_NEAR(slides, g_sin, 0.01 * g_sin);
  EXPECT_NEAR(rolls, 5.0 / 7.0 * g_sin, 0.01 * 5.0 / 7.0 * g_sin);
  EXPECT_LT(std::abs(store.angular_velocity[0].y), 1e-9);  // no torque without friction
  EXPECT_NEAR(store.velocity[1].x - store.angular_velocity[1].y * r, 0.0, 1e-3 * store.velocity[1].x);
}

}  // namespace
}  // namespace aggpack
