#include "aggpack/dynamics/contact_law.hpp"
#include "aggpack/dynamics/contact_law_registry.hpp"

#include <cstdio>
#include <gtest/gtest.h>

#include <cmath>

#include "aggpack/core/error.hpp"

namespace aggpack {
namespace {

TEST(ContactFormulas, EffectiveModuliOfEqualSpheres) {
  const double e = 3e9, nu = 0.3;
  EXPECT_NEAR(effective_youngs_modulus(e, nu, e, nu), e / (2.0 * (1.0 - nu * nu)), 1e-6 * e);
  const double g = e / (2.0 * (1.0 + nu));
  EXPECT_NEAR(effective_shear_modulus(e, nu, e, nu), g / (2.0 * (2.0 - nu)), 1e-6 * g);
  // A rigid wall leaves the sphere's own compliance.
  EXPECT_NEAR(effective_youngs_modulus(e, nu, 1e30, 0.0), e / (1.0 - nu * nu), 1e-6 * e);
}

TEST(ContactFormulas, StaticOverlapBalancesTheHertzForce) {
  const double e_star = 2e9, r = 0.01, weight = 3.0;
  const double overlap = hertz_static_overlap(weight, e_star, r);
  EXPECT_NEAR(hertz_normal_force(e_star, r, overlap), weight, 1e-12 * weight);
}

TEST(ContactFormulas, HertzContactTimeConstantIsTheTextbookOne) {
  // t = 2.868 (m*^2 / (R* E*^2 v))^(1/5) (e.g. Johnson 1985, section 11.4).
  const double m = 0.02, r = 0.01, e_star = 1e9, v = 0.7;
  const double scale = std::pow(m * m / (r * e_star * e_star * v), 0.2);
  EXPECT_NEAR(hertz_contact_time(m, r, e_star, v) / scale, 2.868, 2e-3);
}

TEST(ContactFormulas, RestitutionDampingRoundTrips) {
  EXPECT_NEAR(restitution_of_damping(0.0), 1.0, 1e-6);
  double previous = 1.0;
  for (const double e : {0.9, 0.7, 0.5, 0.3, 0.1}) {
    const double a = damping_for_restitution(e);
    EXPECT_NEAR(restitution_of_damping(a), e, 1e-6) << e;
    EXPECT_GT(a, 0.0);
    EXPECT_LT(e, previous);
    previous = e;
  }
  EXPECT_EQ(damping_for_restitution(1.0), 0.0);
  EXPECT_THROW(damping_for_restitution(0.0), InputError);
  EXPECT_THROW(damping_for_restitution(1.2), InputError);
}

ContactCoefficients coefficients(double friction) {
  return {1e9, 4e8, damping_for_restitution(0.5), friction, 0.0};
}

ContactKinematics contact(Vec3 velocity) {
  ContactKinematics k;
  k.normal = {0, 0, -1};  // i sits on j (or on the floor)
  k.overlap = 1e-5;
  k.velocity = velocity;
  k.r_eff = 0.005;
  k.m_eff = 0.01;
  return k;
}

TEST(HertzMindlin, NormalForceAtRestIsHertz) {
  const HertzMindlin law{coefficients(0.5)};
  Vec3 spring;
  const ContactForce f = law.evaluate(contact({}), spring, 1e-6);
  const double hertz = hertz_normal_force(1e9, 0.005, 1e-5);
  EXPECT_NEAR(f.normal, hertz, 1e-12 * hertz);
  EXPECT_NEAR(f.force.z, hertz, 1e-12 * hertz);  // pushes i up, away from j
  EXPECT_EQ(f.tangential.x, 0.0);
}

TEST(HertzMindlin, DampingAddsWhileApproachingAndNeverPulls) {
  const HertzMindlin law{coefficients(0.5)};
  Vec3 spring;
  const double hertz = hertz_normal_force(1e9, 0.005, 1e-5);
  EXPECT_GT(law.evaluate(contact({0, 0, -0.1}), spring, 1e-6).normal, hertz);
  EXPECT_LT(law.evaluate(contact({0, 0, 0.1}), spring, 1e-6).normal, hertz);
  EXPECT_EQ(law.evaluate(contact({0, 0, 1e3}), spring, 1e-6).normal, 0.0);
}

TEST(HertzMindlin, TangentialSpringSticksThenSlidesAtCoulomb) {
  const ContactCoefficients c = coefficients(0.3);
  const HertzMindlin law{c};
  const double dt = 1e-7;
  const double kt = 8.0 * c.g_star * std::sqrt(0.005 * 1e-5);
  const double eta_t = c.damping * std::sqrt(0.01 * (2.0 / 3.0) * kt);
  Vec3 spring;
  // A tiny slip: the spring holds, F_t = -k_t xi - eta_t v_t with xi = v_t dt.
  ContactForce f = law.evaluate(contact({1e-6, 0, 0}), spring, dt);
  EXPECT_NEAR(spring.x, 1e-13, 1e-25);
  const double expected = -(kt * 1e-13 + eta_t * 1e-6);
  EXPECT_NEAR(f.tangential.x, expected, 1e-12 * std::abs(expected));
  EXPECT_LT(std::abs(f.tangential.x), 0.3 * f.normal);
  // A long slide: capped at mu F_n, against the sliding; the spring holds just that force.
  for (int i = 0; i < 100000; ++i) f = law.evaluate(contact({0.5, 0, 0}), spring, dt);
  EXPECT_NEAR(norm(f.tangential), 0.3 * f.normal, 1e-9 * f.normal);
  EXPECT_LT(f.tangential.x, 0.0);
  EXPECT_NEAR(-kt * spring.x - eta_t * 0.5, f.tangential.x, 1e-9 * f.normal);
}

TEST(HertzMindlin, MirroredContactGivesExactlyOppositeForces) {
  const HertzMindlin law{coefficients(0.3)};
  ContactKinematics a = contact({0.01, -0.02, 0.03});
  a.normal = {0.6, 0.0, -0.8};
  a.spin = {1.0, 2.0, -3.0};
  ContactKinematics b = a;
  b.normal = -a.normal;
  b.velocity = -a.velocity;
  b.spin = -a.spin;
  Vec3 spring_a{1e-7, 2e-7, 0}, spring_b = -spring_a;
  for (int i = 0; i < 3; ++i) {
    const ContactForce fa = law.evaluate(a, spring_a, 1e-6);
    const ContactForce fb = law.evaluate(b, spring_b, 1e-6);
    EXPECT_EQ(fa.force, -fb.force);
    EXPECT_EQ(spring_a, -spring_b);
  }
}

TEST(SlidingFrictionFu2003, FrictionIsMuTimesNormalAgainstSliding) {
  const SlidingFrictionFu2003 law{coefficients(0.17)};
  Vec3 spring{1, 1, 1};
  const ContactForce f = law.evaluate(contact({0.2, 0, 0}), spring, 1e-6);
  EXPECT_NEAR(f.tangential.x, -0.17 * f.normal, 1e-12 * f.normal);
  EXPECT_EQ(spring, Vec3{});
}

TEST(RollingResistance, OpposesSpinWithMuRTimesRTimesFn) {
  ContactCoefficients c = coefficients(0.3);
  c.rolling = 0.1;
  const HertzMindlin law{c};
  ContactKinematics k = contact({});
  k.spin = {0, 5.0, 0};
  Vec3 spring;
  const ContactForce f = law.evaluate(k, spring, 1e-6);
  EXPECT_NEAR(f.rolling_torque.y, -0.1 * k.r_eff * f.normal, 1e-12);
}

TEST(MakeContactModel, ChoosesTheLawByNameAndRejectsBadValues) {
  ContactParameters p;
  EXPECT_TRUE(std::holds_alternative<HertzMindlin>(make_contact_model(p).particle));
  p.friction_model = "fu2003";
  const ContactModel fu = make_contact_model(p);
  EXPECT_TRUE(std::holds_alternative<SlidingFrictionFu2003>(fu.particle));
  EXPECT_TRUE(std::holds_alternative<SlidingFrictionFu2003>(fu.wall));
  p.friction_model = "coulomb";
  try {
    make_contact_model(p);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("\"coulomb\" is unknown"), std::string::npos);
  }
  p = {};
  p.poisson_ratio = 0.7;
  EXPECT_THROW(make_contact_model(p), InputError);
  p = {};
  p.restitution = 0.0;
  EXPECT_THROW(make_contact_model(p), InputError);
}

}  // namespace
}  // namespace aggpack

namespace aggpack {
namespace {

// One table: each entry builds its own law, describes it and gives LAMMPS keywords that carry
// the parameters it was given.
TEST(ContactLawRegistry, EveryLawBuildsDescribesAndTranslatesItself) {
  ASSERT_EQ(contact_laws().size(), 2u);
  ContactParameters p;
  p.youngs_modulus = 3e9;
  p.poisson_ratio = 0.3;
  p.wall_youngs_modulus = 200e9;
  p.wall_poisson_ratio = 0.3;
  p.friction_particle = 0.17;
  p.friction_wall = 0.5;
  for (const ContactLawEntry& law : contact_laws()) {
    p.friction_model = std::string(law.name);
    EXPECT_EQ(&contact_law(law.name), &law);
    EXPECT_EQ(make_contact_model(p).particle.index(), law.make(ContactCoefficients{}).index()) << law.name;
    EXPECT_NE(law.describe(p).find("e = 0.5"), std::string::npos) << law.describe(p);
    const std::string particle = law.lammps_keywords(p, false), wall = law.lammps_keywords(p, true);
    EXPECT_EQ(particle.rfind("hertz/material 3e+09 0.5 0.3 damping tsuji", 0), 0u) << particle;
    // The wall's E and nu are those whose E* and G* by LAMMPS 2022's fix wall/gran formulas,
    // E/(2(1 - nu)) and E/(4(2 - nu)(1 + nu)), are aggpack's (Hertz and Mindlin of sphere and wall).
    double e = 0.0, nu = 0.0;
    ASSERT_EQ(std::sscanf(wall.c_str(), "hertz/material %lf 0.5 %lf damping tsuji", &e, &nu), 2) << wall;
    EXPECT_NEAR(e / (2.0 * (1.0 - nu)), effective_youngs_modulus(3e9, 0.3, 200e9, 0.3), 1e-8 * e) << wall;
    EXPECT_NEAR(e / (4.0 * (2.0 - nu) * (1.0 + nu)), effective_shear_modulus(3e9, 0.3, 200e9, 0.3), 1e-8 * e) << wall;
    EXPECT_NE(particle.find(" 0.17"), std::string::npos) << particle;
    // LAMMPS's normal force never pulls either, as aggpack's does not.
    EXPECT_NE(particle.find("damping tsuji limit_damping tangential"), std::string::npos) << particle;
    EXPECT_NE(wall.find("damping tsuji limit_damping tangential"), std::string::npos) << wall;
    EXPECT_NE(wall.find(" 0.5"), std::string::npos) << wall;
    EXPECT_FALSE(law.lammps_differences.empty());
  }
  // The Mindlin tangential damping ratio is aggpack's sqrt(4 G*/E*), which for one material is
  // sqrt(2 (1 - nu) / (2 - nu)) = 0.907485213 at nu = 0.3.
  p.friction_model = "mindlin";
  EXPECT_NE(contact_law("mindlin").lammps_keywords(p, false).find("tangential mindlin NULL 0.907485213 0.17"),
            std::string::npos)
      << contact_law("mindlin").lammps_keywords(p, false);
  EXPECT_THROW((void)contact_law("coulomb"), InputError);
  // Rolling resistance: sds itself for the spring-dashpot, a stiff sds for the constant torque;
  // the differences and the note say which.
  p.rolling_friction = 0.1;
  for (const ContactLawEntry& law : contact_laws()) {
    p.friction_model = std::string(law.name);
    p.rolling_model = RollingModel::ConstantTorque;
    EXPECT_NE(law.lammps_keywords(p, true).find(" rolling sds 1e12 0 0.1"), std::string::npos);
    EXPECT_NE(law.describe(p).find("constant-torque rolling resistance 0.1"), std::string::npos) << law.describe(p);
    p.rolling_model = RollingModel::SpringDashpot;
    p.rolling_stiffness = 250.0;
    p.rolling_damping = 0.5;
    EXPECT_TRUE(law.lammps_keywords(p, false).ends_with(" rolling sds 250 0.5 0.1")) << law.lammps_keywords(p, false);
    EXPECT_NE(law.describe(p).find("spring-dashpot rolling resistance (LAMMPS's sds: k_roll 250 N/m"),
              std::string::npos) << law.describe(p);
    for (const char* said : {"spring_dashpot", "constant_torque", "epsd2"})
      EXPECT_NE(law.lammps_differences.find(said), std::string::npos) << law.name << ": " << said;
  }
  p.rolling_friction = 0.0;
  p.rolling_model = RollingModel::ConstantTorque;
  p.friction_model = "mindlin";
  // The default time step's scale is the Rayleigh time of the smallest sphere.
  EXPECT_DOUBLE_EQ(stable_time_scale(p, 0.005, 2650.0), rayleigh_time(0.005, 2650.0, 3e9, 0.3));
}

}  // namespace
}  // namespace aggpack
