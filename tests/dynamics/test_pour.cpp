// The pour's release height: a particle comes in at the speed of a free fall from it.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "aggpack/core/rng.hpp"
#include "aggpack/dynamics/dem_system.hpp"
#include "aggpack/dynamics/pour.hpp"

namespace aggpack {
namespace {

constexpr double kG = 9.81;

TEST(Pour, TheSpeedAtInsertionIsAFreeFallFromTheReleaseHeight) {
  PourSettings s;
  s.velocity = 0.3;
  EXPECT_DOUBLE_EQ(poured_speed(s, kG, 0.05), 0.3);  // no release height: the velocity
  s.release_height = 0.2;
  EXPECT_NEAR(poured_speed(s, kG, 0.05), std::sqrt(0.09 + 2.0 * kG * 0.15), 1e-15);
  EXPECT_DOUBLE_EQ(poured_speed(s, kG, 0.2), 0.3);
  EXPECT_DOUBLE_EQ(poured_speed(s, kG, 0.25), 0.3);  // above it: as released
  s.velocity = 0.0;
  EXPECT_NEAR(poured_speed(s, kG, 0.0), std::sqrt(2.0 * kG * 0.2), 1e-15);
}

// Spheres poured into a tall empty box from a release height H above its floor: while they fall
// freely, each keeps the energy of a sphere dropped from H, v^2 = 2 g (H - z), whatever height
// it came in at (an oracle independent of where the gas put it).
TEST(Pour, SpheresReleasedAboveTheBoxFallAsIfDroppedFromThere) {
  constexpr double kRelease = 0.9, kRadius = 0.002;
  const std::vector<double> radii(30, kRadius);
  ParticleStore store;
  const Container box = Container::square(0.1, 1.0, false);
  ContactParameters p;
  p.youngs_modulus = p.wall_youngs_modulus = 1e8;
  DemSettings dem_settings;
  dem_settings.time_step = 2e-6;
  DemSystem dem(store, box, make_contact_model(p), dem_settings);
  PourSettings pouring;
  pouring.solid_fraction = 0.01;
  pouring.gap = 0.3;  // the slab, 3 cm tall, from 0.3 m: well below the release height
  pouring.release_height = kRelease;
  QuietCriterion quiet;
  quiet.max_time = 0.05;  // the spheres are still in the air at its end
  PourLoop loop = begin_pour(dem, pouring, radii, Rng(7, 1));
  PourHooks hooks;
  int samples = 0;
  hooks.on_sample = [&](const SettleSample&, std::string_view) {
    ++samples;
    for (std::size_t i = 0; i < store.size(); ++i) {
      ASSERT_GT(store.position[i].z, 0.1) << "sphere " << i << " reached the floor";
      const double v = -store.velocity[i].z;
      EXPECT_NEAR(v * v, 2.0 * kG * (kRelease - store.position[i].z), 1e-6) << "sphere " << i;
      EXPECT_EQ(store.velocity[i].x, 0.0);
    }
  };
  hooks.at_safe_point = [](std::string_view) {};
  pour(dem, store, box, radii, pouring, 0, SphereMaterials::all_of(2650.0), PouredShapes{}, quiet, loop, false, hooks);
  ASSERT_EQ(store.size(), radii.size());
  EXPECT_GT(samples, 2);
  EXPECT_EQ(loop.report.release_height, kRelease);
}

}  // namespace
}  // namespace aggpack
