// A cylindrical container's curved wall in the DEM: a sphere pressed into it feels the wall
// law's force for its overlap r - (R - rho), along the radius inwards, at the effective radius
// of a concave cylinder (2 R r / (2 R - r), as LAMMPS's region walls); one thrown at it bounces
// back along the radius with the law's restitution, as from a flat wall.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "aggpack/dynamics/dem_system.hpp"

namespace aggpack {
namespace {

constexpr double kDensity = 2650.0;
constexpr double kModulus = 1e8;
constexpr double kPoisson = 0.3;

ContactParameters material(double restitution) {
  ContactParameters p;
  p.youngs_modulus = p.wall_youngs_modulus = kModulus;
  p.poisson_ratio = p.wall_poisson_ratio = kPoisson;
  p.restitution = restitution;
  p.friction_particle = p.friction_wall = 0.0;
  return p;
}

DemSettings weightless(double time_step) {
  DemSettings s;
  s.gravity = {};
  s.time_step = time_step;
  s.threads = 1;
  return s;
}

TEST(CylinderWall, ASpherePressedIntoItFeelsTheLawsForceAlongTheRadius) {
  const Container c = Container::cylinder(0.1, 0.1);  // axis through (0.05, 0.05)
  const double r = 0.01, overlap = 2e-4;
  // Out from the axis along (3, 4) / 5, its surface `overlap` beyond the wall.
  const double rho = 0.05 - r + overlap;
  ParticleStore store;
  store.add({0.05 + 0.6 * rho, 0.05 + 0.8 * rho, 0.05}, r, kDensity);
  DemSystem dem(store, c, make_contact_model(material(0.5)), weightless(1e-7));
  const double e_star = effective_youngs_modulus(kModulus, kPoisson, kModulus, kPoisson);
  const double r_eff = 2.0 * 0.05 * r / (2.0 * 0.05 - r);
  const double expected = hertz_normal_force(e_star, r_eff, overlap);
  const Vec3 f = dem.force(0);
  EXPECT_NEAR(f.x, -0.6 * expected, 1e-9 * expected);
  EXPECT_NEAR(f.y, -0.8 * expected, 1e-9 * expected);
  EXPECT_EQ(f.z, 0.0);
  EXPECT_GT(expected, 0.0);
  // The same sphere against a box's flat wall at the same overlap: the flat law's force.
  ParticleStore flat;
  flat.add({0.1 - r + overlap, 0.05, 0.05}, r, kDensity);
  DemSystem box(flat, Container::square(0.1, 0.1, false), make_contact_model(material(0.5)), weightless(1e-7));
  const double flat_force = hertz_normal_force(e_star, r, overlap);
  EXPECT_NEAR(box.force(0).x, -flat_force, 1e-9 * flat_force);
  EXPECT_NEAR(expected / flat_force, std::sqrt(r_eff / r), 1e-12);
}

// Thrown from near the axis at the wall along (cos a, sin a): back along the same line, at e
// times the speed, as from a flat wall; it stays on its line (no force across the radius).
double rebound_ratio(const Container& c, const Vec3& direction, double restitution, double speed) {
  const double r = 0.005;
  ParticleStore store;
  const Vec3 start = Vec3{0.05, 0.05, 0.05} + 0.04 * direction;  // the wall touched at 0.045
  store.add(start, r, kDensity);
  store.velocity[0] = speed * direction;
  DemSystem dem(store, c, make_contact_model(material(restitution)), weightless(2e-6));  // ~270 steps a contact
  for (int s = 0; s < 2'000'000 && dot(store.velocity[0], direction) > 0.0; ++s) dem.run(1);
  for (int s = 0; s < 2'000'000; ++s) {
    const Vec3 offset = store.position[0] - Vec3{0.05, 0.05, 0.05};
    const Vec3 across = offset - dot(offset, direction) * direction;
    EXPECT_LT(norm(across), 1e-12);
    if (norm(offset) < 0.044) break;  // clear of the wall again
    dem.run(1);
  }
  return -dot(store.velocity[0], direction) / speed;
}

TEST(CylinderWall, ASphereBouncesBackAlongTheRadiusWithTheLawsRestitution) {
  const Container cylinder = Container::cylinder(0.1, 0.1), box = Container::square(0.1, 0.1, false);
  for (const double e : {0.3, 0.8}) {
    const double flat = rebound_ratio(box, {1.0, 0.0, 0.0}, e, 0.5);
    EXPECT_NEAR(flat, e, 0.01 * e);
    for (const double angle : {0.3, 2.0, 4.0}) {
      const Vec3 direction{std::cos(angle), std::sin(angle), 0.0};
      EXPECT_NEAR(rebound_ratio(cylinder, direction, e, 0.5), flat, 0.01 * e) << "e " << e << " angle " << angle;
    }
  }
}

}  // namespace
}  // namespace aggpack
