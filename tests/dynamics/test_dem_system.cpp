#include "aggpack/dynamics/dem_system.hpp"

#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "aggpack/core/error.hpp"
#include "aggpack/core/rng.hpp"
#include "aggpack/deposition/drop_and_roll.hpp"
#include "aggpack/dynamics/settle.hpp"

namespace aggpack {
namespace {

constexpr double kDensity = 2650.0;
constexpr double kModulus = 1e8;  // soft, so that contacts last many steps
constexpr double kPoisson = 0.3;

ContactParameters material(double restitution, double friction) {
  ContactParameters p;
  p.youngs_modulus = kModulus;
  p.poisson_ratio = kPoisson;
  p.wall_youngs_modulus = kModulus;
  p.wall_poisson_ratio = kPoisson;
  p.restitution = restitution;
  p.friction_particle = friction;
  p.friction_wall = friction;
  return p;
}

double sphere_mass(double r) { return kDensity * 4.0 / 3.0 * std::numbers::pi * r * r * r; }
const double kEStar = effective_youngs_modulus(kModulus, kPoisson, kModulus, kPoisson);

// Steps one step at a time until `done`, at most `limit` steps; returns the steps taken.
template <class Done>
std::size_t step_until(DemSystem& dem, std::size_t limit, Done&& done) {
  for (std::size_t s = 0; s < limit; ++s) {
    dem.run(1);
    if (done()) return s + 1;
  }
  return limit;
}

// One sphere of radius r just touching the floor of a 10 cm box.
ParticleStore sphere_on_the_floor(double r) {
  ParticleStore store;
  store.add({0.05, 0.05, r}, r, kDensity);
  return store;
}

TEST(DemSystem, SphereOnTheFloorRestsAtTheHertzStaticOverlap) {
  const double r = 0.01;
  ParticleStore store = sphere_on_the_floor(r);
  DemSettings settings;
  settings.time_step = 1e-5;
  DemSystem dem(store, Container::square(0.1, 0.1, false), make_contact_model(material(0.3, 0.5)), settings);
  dem.run(40000);
  const double expected = hertz_static_overlap(store.mass[0] * 9.81, kEStar, r);
  EXPECT_NEAR(r - store.position[0].z, expected, 0.01 * expected);
  EXPECT_LT(std::abs(store.velocity[0].z), 1e-6);
}

// A frozen sphere holds its place exactly and still carries the one resting on it: the upper
// sphere comes to rest at the static Hertz overlap with it, as on the floor but with R* = r/2.
TEST(DemSystem, AFrozenSphereDoesNotMoveAndCarriesTheOneAbove) {
  const double r = 0.01;
  ParticleStore store = sphere_on_the_floor(r);
  store.add({0.05, 0.05, 3.0 * r}, r, kDensity);
  const Vec3 below = store.position[0];
  DemSettings settings;
  settings.time_step = 1e-5;
  DemSystem dem(store, Container::square(0.1, 0.1, false), make_contact_model(material(0.3, 0.5)), settings, {1, 0});
  EXPECT_EQ(dem.free_count(), 1u);
  EXPECT_TRUE(dem.is_frozen(0));
  dem.run(40000);
  EXPECT_EQ(store.position[0], below);
  EXPECT_EQ(store.velocity[0], Vec3{});
  // Walls and spheres are one material here, so the pair's E* is the wall's; R* = r / 2.
  const double expected = hertz_static_overlap(store.mass[1] * 9.81, kEStar, 0.5 * r);
  EXPECT_NEAR(2.0 * r - (store.position[1].z - store.position[0].z), expected, 0.01 * expected);
  EXPECT_THROW(DemSystem(store, Container::square(0.1, 0.1, false), make_contact_model(material(0.3, 0.5)), settings,
                         {1}),
               std::invalid_argument);
}

struct Impact {
  double rebound_ratio;
  double contact_time;
};

Impact floor_impact(double restitution, double speed) {
  const double r = 0.01;
  ParticleStore store = sphere_on_the_floor(r);
  store.velocity[0] = {0, 0, -speed};
  DemSettings settings;
  settings.gravity = {};
  settings.time_step = 2e-7;
  DemSystem dem(store, Container::square(0.1, 0.1, false), make_contact_model(material(restitution, 0.0)), settings);
  std::size_t in_contact = 0;
  step_until(dem, 1'000'000, [&] {
    if (store.position[0].z < r) ++in_contact;
    return store.position[0].z > r && store.velocity[0].z > 0.0;
  });
  return {store.velocity[0].z / speed, static_cast<double>(in_contact) * settings.time_step};
}

TEST(DemSystem, FloorImpactReboundsWithTheRestitutionCoefficient) {
  for (const double e : {0.3, 0.5, 0.8}) {
    for (const double speed : {0.1, 1.0}) {
      const Impact impact = floor_impact(e, speed);
      EXPECT_NEAR(impact.rebound_ratio, e, 0.01 * e) << "e " << e << " speed " << speed;
    }
  }
}

TEST(DemSystem, ElasticFloorImpactLastsTheHertzContactTime) {
  const double r = 0.01, speed = 0.5;
  const Impact impact = floor_impact(1.0, speed);
  EXPECT_NEAR(impact.rebound_ratio, 1.0, 1e-3);
  const double expected = hertz_contact_time(sphere_mass(r), r, kEStar, speed);
  EXPECT_NEAR(impact.contact_time, expected, 0.03 * expected);
}

TEST(DemSystem, HeadOnImpactReboundsWithTheRestitutionAndHertzTime) {
  const double r = 0.01, speed = 0.4;
  for (const double e : {1.0, 0.5}) {
    ParticleStore store;
    store.add({0.05 - r, 0.05, 0.05}, r, kDensity);
    store.add({0.05 + r, 0.05, 0.05}, r, kDensity);
    store.velocity[0] = {speed, 0, 0};
    store.velocity[1] = {-speed, 0, 0};
    DemSettings settings;
    settings.gravity = {};
    settings.time_step = 2e-7;
    DemSystem dem(store, Container::square(0.1, 0.1, false), make_contact_model(material(e, 0.3)), settings);
    std::size_t in_contact = 0;
    step_until(dem, 1'000'000, [&] {
      const bool touching = store.position[1].x - store.position[0].x < 2 * r;
      in_contact += touching;
      return !touching && store.velocity[0].x < 0.0;
    });
    EXPECT_NEAR(-store.velocity[0].x / speed, e, 0.01 * e);
    EXPECT_EQ(store.velocity[0].x, -store.velocity[1].x);
    if (e == 1.0) {
      const double expected = hertz_contact_time(sphere_mass(r) / 2, r / 2, kEStar, 2 * speed);
      EXPECT_NEAR(static_cast<double>(in_contact) * settings.time_step, expected, 0.03 * expected);
    }
  }
}

// Acceleration along x of a sphere on a floor tilted by theta (gravity tilted instead).
struct Incline {
  double acceleration;
  double slip;  // v_x - omega_y R at the end
};

Incline incline(double theta, double friction) {
  const double r = 0.01, g = 9.81;
  ParticleStore store;
  const double weight_normal = sphere_mass(r) * g * std::cos(theta);
  const double overlap = hertz_static_overlap(weight_normal, kEStar, r);
  store.add({0.2, 0.5, r - overlap}, r, kDensity);
  DemSettings settings;
  settings.gravity = {g * std::sin(theta), 0, -g * std::cos(theta)};
  settings.time_step = 1e-5;
  DemSystem dem(store, Container::square(1.0, 0.1, false), make_contact_model(material(0.5, friction)), settings);
  dem.run(5000);
  const double v1 = store.velocity[0].x, t1 = dem.time();
  dem.run(20000);
  const double v2 = store.velocity[0].x, t2 = dem.time();
  return {(v2 - v1) / (t2 - t1), store.velocity[0].x - store.angular_velocity[0].y * r};
}

TEST(DemSystem, SphereOnAnInclineRollsWithoutSlipBelowTheFrictionLimit) {
  const double theta = 20.0 * std::numbers::pi / 180.0, mu = 0.5;  // tan 20 deg < 3.5 mu
  const Incline result = incline(theta, mu);
  const double expected = 5.0 / 7.0 * 9.81 * std::sin(theta);
  EXPECT_NEAR(result.acceleration, expected, 0.02 * expected);
  EXPECT_LT(std::abs(result.slip), 1e-3 * expected);
}

TEST(DemSystem, SphereOnASteepInclineSlidesWithCoulombFriction) {
  const double theta = 30.0 * std::numbers::pi / 180.0, mu = 0.1;  // tan 30 deg > 3.5 mu
  const Incline result = incline(theta, mu);
  const double expected = 9.81 * (std::sin(theta) - mu * std::cos(theta));
  EXPECT_NEAR(result.acceleration, expected, 0.02 * expected);
  EXPECT_GT(result.slip, 0.01);
}

// A pour admits new particles into a running system: the others keep their state and their
// contact history. Two spheres collide obliquely without gravity, the tangential spring of
// their contact loaded in stick. Admitting a far-away sphere mid-contact must leave the
// collision the same to the bit, while a system rebuilt from the store at that moment (the
// spring history lost) changes its outcome.
TEST(DemSystem, AdmittingParticlesKeepsTheOthersStateAndContactHistory) {
  const double r = 0.01;
  DemSettings settings;
  settings.time_step = 1e-5;
  settings.gravity = {};
  const Container box = Container::square(1.0, 1.0, false);
  const ContactModel model = make_contact_model(material(0.5, 1.0));
  const auto start = [&] {
    ParticleStore store;
    const Vec3 a{0.5, 0.5, 0.5}, offset{std::sqrt(4.0 * r * r - 0.36 * r * r), 0.6 * r, 0.0};  // just touching
    store.add(a, r, kDensity);
    store.add(a - offset, r, kDensity);
    store.velocity[1] = {0.5, 0.0, 0.0};  // the contact lasts about 1e-3 s, 100 steps
    return store;
  };
  const auto add_far_sphere = [&](ParticleStore& store) {
    store.add({0.1, 0.1, 0.1}, 0.5 * r, kDensity);
    store.velocity.back() = {0.0, 0.0, -0.3};
  };
  ParticleStore alone = start();
  DemSystem reference(alone, box, model, settings);
  reference.run(40);
  const Vec3 mid_spin = alone.angular_velocity[0];
  reference.run(160);
  ASSERT_GT(norm(mid_spin), 0.1);  // the contact carries a tangential force midway

  ParticleStore grown = start();
  DemSystem dem(grown, box, model, settings);
  dem.run(40);
  add_far_sphere(grown);
  dem.admit_new_particles();
  EXPECT_EQ(dem.free_count(), 3u);
  dem.run(160);
  for (std::size_t i : {0, 1}) {
    EXPECT_EQ(std::memcmp(&grown.position[i], &alone.position[i], sizeof(Vec3)), 0) << i;
    EXPECT_EQ(std::memcmp(&grown.velocity[i], &alone.velocity[i], sizeof(Vec3)), 0) << i;
    EXPECT_EQ(std::memcmp(&grown.angular_velocity[i], &alone.angular_velocity[i], sizeof(Vec3)), 0) << i;
  }
  EXPECT_NEAR(grown.position[2].z, 0.1 - 0.3 * 160 * settings.time_step, 1e-12);  // the new sphere moved on

  // The same admission through a new system (no history): the collision ends otherwise.
  ParticleStore restarted = start();
  {
    DemSystem first(restarted, box, model, settings);
    first.run(40);
  }
  add_far_sphere(restarted);
  DemSystem second(restarted, box, model, settings);
  second.run(160);
  EXPECT_GT(norm(restarted.angular_velocity[0] - alone.angular_velocity[0]), 1e-3 * norm(alone.angular_velocity[0]));
}

// A tap moves the container up and back (half a sine period). Below Gamma = 1 the floor never
// accelerates down faster than gravity, so a sphere resting on it rides along as a rigid body
// (its height above the moving floor stays the Hertz rest height within a few overlaps); above
// 1 the floor drops away faster than the sphere falls and it flies.
TEST(DemSystem, ATapBelowOneGDoesNotLiftASphereOffTheFloorAndAboveOneGDoes) {
  const double r = 0.01, f = 30.0, w = 2.0 * std::numbers::pi * f;
  for (const double gamma : {0.5, 3.0}) {
    ParticleStore store = sphere_on_the_floor(r);
    DemSettings settings;
    settings.time_step = 1e-5;
    DemSystem dem(store, Container::square(0.1, 0.1, false), make_contact_model(material(0.3, 0.5)), settings);
    dem.run(20000);  // at rest on the floor
    const double rest_height = store.position[0].z;
    const double overlap = r - rest_height;
    const ContainerMotion tap{dem.time(), gamma * 9.81 / (w * w), w, 0.5};
    dem.set_container_motion(tap);
    double largest_gap = 0.0, deepest = 0.0, highest_floor = 0.0;
    while (dem.time() < tap.end() + 0.05) {
      dem.run(1);
      const double above_floor = store.position[0].z - dem.container_offset();
      largest_gap = std::max(largest_gap, above_floor - rest_height);
      deepest = std::max(deepest, rest_height - above_floor);
      highest_floor = std::max(highest_floor, dem.container_offset());
    }
    EXPECT_NEAR(highest_floor, tap.amplitude, 1e-3 * tap.amplitude) << gamma;
    if (gamma < 1.0) {
      EXPECT_LT(largest_gap, 3.0 * overlap) << gamma;  // never off the floor (the overlap eases, no more)
    } else {
      EXPECT_GT(largest_gap, 0.1 * tap.amplitude) << gamma;  // flew
    }
    EXPECT_LT(deepest, 10.0 * overlap) << gamma;  // and lands without passing through it
    EXPECT_EQ(dem.container_offset(), 0.0);       // back at rest
  }
}

// An empty system can be poured into: it starts with no particles and admits them.
TEST(DemSystem, AnEmptySystemAdmitsParticles) {
  ParticleStore store;
  DemSettings settings;
  settings.time_step = 1e-5;
  DemSystem dem(store, Container::square(0.1, 0.1, false), make_contact_model(material(0.3, 0.5)), settings);
  dem.run(10);
  EXPECT_EQ(dem.free_count(), 0u);
  store.add({0.05, 0.05, 0.03}, 0.01, kDensity);
  dem.admit_new_particles();
  EXPECT_DOUBLE_EQ(dem.skin(), 0.1 * 0.02);
  dem.run(40000);
  const double expected = hertz_static_overlap(store.mass[0] * 9.81, kEStar, 0.01);
  EXPECT_NEAR(0.01 - store.position[0].z, expected, 0.02 * expected);
  // A new particle must touch nothing: one laid into the first (either side of it in the
  // list's order) is refused.
  for (const double dx : {-0.015, 0.015}) {
    ParticleStore two = store;
    DemSystem again(two, Container::square(0.1, 0.1, false), make_contact_model(material(0.3, 0.5)), settings);
    two.add(store.position[0] + Vec3{dx, 0.0, 0.0}, 0.01, kDensity);
    EXPECT_THROW(again.admit_new_particles(), std::invalid_argument) << dx;
  }
}

// A cloud of overlapping spheres with random velocities and spins.
ParticleStore random_cluster(std::size_t n, double overlap_fraction, std::uint64_t seed) {
  Rng rng(seed, 99);
  ParticleStore store;
  while (store.size() < n) {
    const double r = rng.uniform(0.004, 0.006);
    const Vec3 c{rng.uniform(0.03, 0.07), rng.uniform(0.03, 0.07), rng.uniform(0.01, 0.05)};
    bool too_deep = false;
    for (std::size_t j = 0; j < store.size(); ++j)
      if (norm(store.position[j] - c) < (1.0 - overlap_fraction) * (r + store.radius[j])) too_deep = true;
    if (too_deep) continue;
    store.add(c, r, kDensity);
    store.velocity.back() = {rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5)};
    store.angular_velocity.back() = {rng.uniform(-50, 50), rng.uniform(-50, 50), rng.uniform(-50, 50)};
  }
  return store;
}

TEST(DemSystem, PairForcesObeyNewtonsThirdLawExactly) {
  ParticleStore store = random_cluster(2, 0.02, 1);
  store.position[1] = store.position[0] + Vec3{0.36, 0.48, 0.8} * (0.9 * (store.radius[0] + store.radius[1]));
  DemSettings settings;
  settings.gravity = {};
  DemSystem dem(store, Container::square(0.1, 0.1, false), make_contact_model(material(0.5, 0.3)), settings);
  for (int s = 0; s < 5; ++s) {
    ASSERT_GT(norm(dem.force(0)), 0.0);
    EXPECT_EQ(dem.force(0), -dem.force(1));
    dem.run(1);
  }
  ParticleStore cloud = random_cluster(60, 0.03, 2);
  DemSystem crowd(cloud, Container::square(0.1, 0.1, false), make_contact_model(material(0.5, 0.3)), settings);
  crowd.run(20);
  Vec3 total;
  double largest = 0.0;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Vec3 f = crowd.force(i);
    total += f;
    largest = std::max(largest, norm(f));
  }
  ASSERT_GT(largest, 0.0);
  EXPECT_LT(norm(total), 1e-12 * largest * 60);
}

// Kinetic plus Hertz elastic energy (8/15) E* sqrt(R*) overlap^(5/2), walls included.
double total_energy(const ParticleStore& s, const Container& c, const DemSystem& dem) {
  double energy = dem.kinetic_energy().total();
  const double e_wall = effective_youngs_modulus(kModulus, kPoisson, kModulus, kPoisson);
  const auto elastic = [](double e_star, double r_star, double overlap) {
    return overlap > 0.0 ? 8.0 / 15.0 * e_star * std::sqrt(r_star) * std::pow(overlap, 2.5) : 0.0;
  };
  for (std::size_t i = 0; i < s.size(); ++i) {
    const Vec3& x = s.position[i];
    const double r = s.radius[i];
    for (std::size_t j = i + 1; j < s.size(); ++j)
      energy += elastic(kEStar, r * s.radius[j] / (r + s.radius[j]), r + s.radius[j] - norm(s.position[j] - x));
    for (const double gap : {x.z - c.bounds.lo.z, x.x - c.bounds.lo.x, c.bounds.hi.x - x.x, x.y - c.bounds.lo.y,
                             c.bounds.hi.y - x.y})
      energy += elastic(e_wall, r, r - gap);
  }
  return energy;
}

TEST(DemSystem, ElasticFrictionlessGasConservesEnergy) {
  ParticleStore store = random_cluster(20, 0.0, 3);
  const Container box = Container::square(0.1, 0.1, false);
  DemSettings settings;
  settings.gravity = {};
  settings.time_step = 1e-6;
  DemSystem dem(store, box, make_contact_model(material(1.0, 0.0)), settings);
  const double start = total_energy(store, box, dem);
  double worst = 0.0;
  for (int block = 0; block < 100; ++block) {
    dem.run(1000);
    worst = std::max(worst, std::abs(total_energy(store, box, dem) - start) / start);
  }
  EXPECT_LT(worst, 1e-4);
  EXPECT_GT(dem.steps(), 99'999u);
}

TEST(DemSystem, FrictionlessElasticClusterRetracesItsPathWhenTimeIsReversed) {
  ParticleStore store = random_cluster(30, 0.01, 4);
  for (Vec3& w : store.angular_velocity) w = {};
  const std::vector<Vec3> start = store.position;
  const Container box = Container::square(0.1, 0.1, false);
  DemSettings settings;
  settings.time_step = 1e-6;
  {
    DemSystem forward(store, box, make_contact_model(material(1.0, 0.0)), settings);
    forward.run(20000);
  }
  double moved = 0.0;
  for (std::size_t i = 0; i < store.size(); ++i) moved = std::max(moved, norm(store.position[i] - start[i]));
  ASSERT_GT(moved, 1e-3);
  for (Vec3& v : store.velocity) v = -v;
  // Gravity is not reversed: it pulls the same way whichever way time runs.
  DemSystem backward(store, box, make_contact_model(material(1.0, 0.0)), settings);
  backward.run(20000);
  for (std::size_t i = 0; i < store.size(); ++i) EXPECT_LT(norm(store.position[i] - start[i]), 1e-9) << i;
}

TEST(DemSystem, PermutingParticlesInMemoryDoesNotChangeTheResult) {
  ParticleStore a = random_cluster(40, 0.02, 5);
  ParticleStore b;
  for (std::size_t k = a.size(); k-- > 0;) {
    b.add(a.position[k], a.radius[k], kDensity);
    b.velocity.back() = a.velocity[k];
    b.angular_velocity.back() = a.angular_velocity[k];
  }
  const Container box = Container::square(0.1, 0.1, false);
  DemSettings settings;
  settings.time_step = 1e-6;
  DemSystem dem_a(a, box, make_contact_model(material(0.5, 0.4)), settings);
  DemSystem dem_b(b, box, make_contact_model(material(0.5, 0.4)), settings);
  dem_a.run(5000);
  dem_b.run(5000);
  const std::size_t n = a.size();
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_LT(norm(a.position[i] - b.position[n - 1 - i]), 1e-12) << i;
    EXPECT_LT(norm(a.angular_velocity[i] - b.angular_velocity[n - 1 - i]), 1e-7) << i;
  }
}

// A deposited bed of `count` spheres, 4-6 mm radius, in a 6 cm box.
ParticleStore deposited_bed(std::size_t count, bool periodic, std::uint64_t seed) {
  Rng sizes(seed, 1);
  std::vector<double> radii(count);
  for (double& r : radii) r = sizes.uniform(0.004, 0.006);
  ParticleStore bed;
  const Container box = Container::square(0.06, 1.0, periodic);
  DropAndRoll deposition(bed, box, radii, DepositionSettings{}, Rng(seed, 2));
  deposition.deposit(radii, SphereMaterials::all_of(kDensity));
  return bed;
}

TEST(DemSystem, SettledBedHasEveryNetForceFarBelowTheWeight) {
  ParticleStore bed = deposited_bed(300, false, 7);
  const Container box = Container::square(0.06, 1.0, false);
  DemSettings settings;
  settings.time_step = 2e-5;
  DemSystem dem(bed, box, make_contact_model(material(0.5, 0.5)), settings);
  QuietCriterion quiet;
  quiet.max_time = 3.0;
  quiet.kinetic_fraction = 1e-8;
  const SettleResult result = settle(dem, bed, quiet, nullptr, nullptr);
  EXPECT_EQ(result.end, SettleEnd::Quiet);
  double worst = 0.0;
  for (std::size_t i = 0; i < bed.size(); ++i)
    worst = std::max(worst, norm(dem.force(i)) / (bed.mass[i] * 9.81));
  EXPECT_LT(worst, 0.01);
  EXPECT_GT(result.last.contacts.coordination, 4.0);
}

// Several force blocks (2048 slots each), so that pairs reaching a later block go through
// the per-pair slots and their fixed-order gather, and neighbour lists rebuilt (and the
// records re-sorted) during the run: the same bytes for one and two threads.
TEST(DemSystem, SameBytesForOneAndTwoThreads) {
  const std::size_t count = 6000;
  const Container box = Container::square(0.12, 1.0, true);
  Rng sizes(8, 1);
  std::vector<double> radii(count);
  for (double& r : radii) r = sizes.uniform(0.002, 0.003);
  ParticleStore deposited;
  DropAndRoll deposition(deposited, box, radii, DepositionSettings{}, Rng(8, 2));
  deposition.deposit(radii, SphereMaterials::all_of(kDensity));
  const auto run = [&](int threads, bool adapt = false) {
    ParticleStore bed = deposited;
    DemSettings settings;
    settings.time_step = 1e-5;
    settings.skin = 5e-5;  // small, so that the list is rebuilt during the run
    settings.threads = threads;
    settings.adapt_threads = adapt;  // else the count asked for, throughout
    DemSystem dem(bed, box, make_contact_model(material(0.5, 0.3)), settings);
    EXPECT_EQ(dem.threads(), threads);
    EXPECT_GT(dem.cross_block_entries(), count / 20);
    dem.run(600);
    EXPECT_GE(dem.rebuilds(), 2u);  // the first, and at least one during the run
    // Governed: two threads for the first tenth of a second of steps, then one thread tried
    // (3.6e6 particle-steps take longer than that on any machine we know).
    EXPECT_EQ(dem.steps_on_fewer_threads() > 0, adapt);
    dem.finish();
    return bed;
  };
  // Governed, the steps run on one thread or two as the clock has it: the same bytes again.
  const ParticleStore one = run(1), two = run(2), governed = run(2, true);
  for (const ParticleStore* other : {&two, &governed}) {
    ASSERT_EQ(one.size(), other->size());
    EXPECT_EQ(0, std::memcmp(one.position.data(), other->position.data(), one.size() * sizeof(Vec3)));
    EXPECT_EQ(0, std::memcmp(one.velocity.data(), other->velocity.data(), one.size() * sizeof(Vec3)));
    EXPECT_EQ(0, std::memcmp(one.angular_velocity.data(), other->angular_velocity.data(), one.size() * sizeof(Vec3)));
  }
  // The bed moved (it is settling): the comparison is not of two copies of the start.
  double moved = 0.0;
  for (std::size_t i = 0; i < count; ++i) moved = std::max(moved, norm(one.position[i] - deposited.position[i]));
  EXPECT_GT(moved, 1e-6);
}

// A checkpoint's DEM state: a system restored from it (into a fresh system made from the
// store as it stood, with another thread count) goes on bit for bit as the original would
// have, through neighbour-list rebuilds, a moving container and the contact history; and
// settle() resumed from a saved loop ends as the whole run does.
std::string saved_state_of(const DemSystem& dem) {
  std::ostringstream out(std::ios::binary);
  dem.save_state(out);
  return std::move(out).str();
}
void restore(DemSystem& dem, const std::string& state) { dem.restore_state(state); }

TEST(DemSystem, ARestoredStateContinuesBitForBit) {
  const Container box = Container::square(0.12, 1.0, false);
  Rng sizes(9, 1);
  std::vector<double> radii(3000);
  for (double& r : radii) r = sizes.uniform(0.002, 0.003);
  ParticleStore deposited;
  DropAndRoll deposition(deposited, box, radii, DepositionSettings{}, Rng(9, 2));
  deposition.deposit(radii, SphereMaterials::all_of(kDensity));
  DemSettings settings;
  settings.time_step = 1e-5;
  settings.skin = 5e-5;  // rebuilt during the run
  const ContactModel model = make_contact_model(material(0.5, 0.3));
  const ContainerMotion tap{0.001, 2e-4, 2.0 * std::numbers::pi * 30.0, 0.5};

  ParticleStore whole = deposited;
  settings.threads = 1;
  DemSystem uninterrupted(whole, box, model, settings);
  uninterrupted.set_container_motion(tap);
  uninterrupted.run(400);

  ParticleStore first_half = deposited;
  DemSystem interrupted(first_half, box, model, settings);
  interrupted.set_container_motion(tap);
  interrupted.run(200);
  const std::string state = saved_state_of(interrupted);
  ParticleStore resumed_store = first_half;  // as a checkpoint holds it
  settings.threads = 2;
  DemSystem resumed(resumed_store, box, model, settings);
  restore(resumed, state);
  EXPECT_EQ(resumed.steps(), 200u);
  EXPECT_EQ(resumed.time(), interrupted.time());
  resumed.run(200);
  EXPECT_GE(resumed.rebuilds(), 2u);
  EXPECT_EQ(0, std::memcmp(whole.position.data(), resumed_store.position.data(), whole.size() * sizeof(Vec3)));
  EXPECT_EQ(0, std::memcmp(whole.velocity.data(), resumed_store.velocity.data(), whole.size() * sizeof(Vec3)));
  EXPECT_EQ(0, std::memcmp(whole.angular_velocity.data(), resumed_store.angular_velocity.data(),
                           whole.size() * sizeof(Vec3)));
  for (std::size_t i = 0; i < whole.size(); i += 97) EXPECT_EQ(uninterrupted.force(i), resumed.force(i)) << i;
  EXPECT_EQ(uninterrupted.container_offset(), resumed.container_offset());

  // Bytes that do not fit: another store, a truncated state.
  ParticleStore other = deposited;
  other.add({0.06, 0.06, 0.9}, 0.002, kDensity);
  DemSystem wrong(other, box, model, settings);
  EXPECT_THROW(restore(wrong, state), InputError);
  EXPECT_THROW(restore(resumed, state.substr(0, state.size() / 2)), InputError);

  // settle(): stopped at its 5th safe point, resumed from the loop saved there.
  QuietCriterion quiet;
  quiet.max_time = 0.02;
  quiet.sample_interval = 1e-3;
  quiet.window = 5e-3;
  ParticleStore settled_whole = deposited;
  settings.threads = 1;
  DemSystem a(settled_whole, box, model, settings);
  std::vector<double> energies_whole;
  const SettleResult all = settle(a, settled_whole, quiet, nullptr, [&](const SettleSample& s) {
    energies_whole.push_back(s.kinetic_energy.total());
  });
  ParticleStore settled_part = deposited;
  DemSystem b(settled_part, box, model, settings);
  std::vector<double> energies_resumed;
  std::optional<SettleLoop> saved;
  std::string saved_state;
  struct Stop {};
  int safe_points = 0;
  try {
    settle(b, settled_part, quiet, nullptr,
           [&](const SettleSample& s) { energies_resumed.push_back(s.kinetic_energy.total()); },
           [&](const SettleLoop& loop) {
             if (++safe_points < 5) return;
             saved = loop;
             saved_state = saved_state_of(b);
             throw Stop{};
           });
  } catch (const Stop&) {
  }
  ASSERT_TRUE(saved);
  ParticleStore settled_resumed = settled_part;
  DemSystem c(settled_resumed, box, model, settings);
  restore(c, saved_state);
  const SettleResult rest = settle(c, settled_resumed, quiet, nullptr, [&](const SettleSample& s) {
    energies_resumed.push_back(s.kinetic_energy.total());
  }, {}, &*saved);
  EXPECT_EQ(rest.end, all.end);
  EXPECT_EQ(rest.steps, all.steps);
  EXPECT_EQ(rest.simulated_time, all.simulated_time);
  EXPECT_EQ(energies_resumed, energies_whole);
  EXPECT_EQ(0, std::memcmp(settled_whole.position.data(), settled_resumed.position.data(),
                           settled_whole.size() * sizeof(Vec3)));
}

// A state damaged past the checkpoint's checksums (forged): restore_state() refuses it with
// InputError, or restores a system that runs; never an index out of range or a flag that is
// not one. Every single-byte change is tried (the sanitize preset would see any bad read);
// the user-index table, the neighbour list and the container's flag, each damaged, are refused.
TEST(DemSystem, ADamagedStateIsRefusedOrRunsNeverReadsOutOfRange) {
  const Container box = Container::square(0.03, 0.2, false);
  Rng sizes(10, 1);
  std::vector<double> radii(40);
  for (double& r : radii) r = sizes.uniform(0.002, 0.003);
  ParticleStore store;
  DropAndRoll deposition(store, box, radii, DepositionSettings{}, Rng(10, 2));
  deposition.deposit(radii, SphereMaterials::all_of(kDensity));
  DemSettings settings;
  settings.time_step = 1e-5;
  settings.threads = 1;
  const ContactModel model = make_contact_model(material(0.5, 0.3));
  std::vector<std::uint8_t> frozen(store.size(), 0);
  for (std::size_t i = 0; i < frozen.size(); i += 4) frozen[i] = 1;  // some, as below a settled layer
  DemSystem dem(store, box, model, settings, frozen);
  dem.run(50);
  const std::string state = saved_state_of(dem);
  const std::uint32_t n = static_cast<std::uint32_t>(store.size());
  const auto restore_and_run = [&](const std::string& bytes) {
    ParticleStore copy = store;
    DemSystem fresh(copy, box, model, settings, frozen);
    restore(fresh, bytes);
    fresh.run(3);
  };
  ASSERT_NO_THROW(restore_and_run(state));

  // Where a table of n (or n + 1) 4-byte values follows its count, as `fits` would have it.
  const auto table = [&](std::uint64_t count, auto fits) {
    for (std::size_t at = 0; at + 8 + 4 * count <= state.size(); ++at) {
      std::uint64_t c = 0;
      std::memcpy(&c, state.data() + at, 8);
      std::vector<std::uint32_t> v(count);
      std::memcpy(v.data(), state.data() + at + 8, 4 * count);
      if (c == count && fits(v)) return at + 8;
    }
    return std::string::npos;
  };
  const std::size_t user_index = table(n, [](const std::vector<std::uint32_t>& v) {
    std::vector<std::uint32_t> sorted = v;
    std::sort(sorted.begin(), sorted.end());
    for (std::uint32_t i = 0; i < sorted.size(); ++i)
      if (sorted[i] != i) return false;
    return true;
  });
  const std::size_t offsets = table(n + 1, [](const std::vector<std::uint32_t>& v) {
    return v.front() == 0 && std::is_sorted(v.begin(), v.end()) && v.back() > 0;
  });
  ASSERT_NE(user_index, std::string::npos);
  ASSERT_NE(offsets, std::string::npos);
  std::uint32_t entries = 0;
  std::memcpy(&entries, state.data() + offsets + 4 * n, 4);
  const std::size_t list = offsets + 4 * (n + 1) + 8;
  const auto with = [&](std::size_t at, std::uint32_t value) {
    std::string bytes = state;
    std::memcpy(bytes.data() + at, &value, 4);
    return bytes;
  };
  EXPECT_THROW(restore_and_run(with(user_index + 4 * 5, n)), InputError);             // out of range
  EXPECT_THROW(restore_and_run(with(user_index + 4 * 5, 0xFFFFFFFFu)), InputError);
  std::uint32_t first = 0;
  std::memcpy(&first, state.data() + user_index, 4);
  EXPECT_THROW(restore_and_run(with(user_index + 4 * 7, first)), InputError);          // a particle twice
  EXPECT_THROW(restore_and_run(with(list + 4 * (entries / 2), n + 9)), InputError);    // beyond the walls
  EXPECT_THROW(restore_and_run(with(list, 0)), InputError);                            // not a later slot
  EXPECT_THROW(restore_and_run(with(offsets + 4 * (n / 2), entries + 1)), InputError);  // a row past the list
  std::string flag = state;
  flag[4 + 8 + sizeof(Box)] = 2;  // the container's `periodic`, after the format, the count and its box
  EXPECT_THROW(restore_and_run(flag), InputError);

  // A state of a system with one more particle, its count in the header forged to this
  // store's: refused by its own count, before any record is read against the store.
  {
    std::vector<double> more = radii;
    more.push_back(radii.back());
    ParticleStore bigger;
    DropAndRoll more_deposition(bigger, box, more, DepositionSettings{}, Rng(10, 2));
    more_deposition.deposit(more, SphereMaterials::all_of(kDensity));
    std::vector<std::uint8_t> more_frozen = frozen;
    more_frozen.push_back(0);
    DemSystem larger(bigger, box, model, settings, more_frozen);
    std::string forged = saved_state_of(larger);
    const std::uint64_t count = n;
    std::memcpy(forged.data() + 4, &count, 8);  // after the format
    try {
      restore_and_run(forged);
      ADD_FAILURE() << "a state of " << n + 1 << " particles was restored into " << n;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("particle count"), std::string::npos) << e.what();
    }
  }

  std::size_t refused = 0;
  for (std::size_t at = 0; at < state.size(); ++at) {
    std::string bytes = state;
    bytes[at] = static_cast<char>(bytes[at] ^ 0x5a);
    try {
      restore_and_run(bytes);
    } catch (const InputError&) {
      ++refused;
    }
  }
  // Most bytes are records, indices and counts, each checked; a spring or a force may change.
  EXPECT_GT(refused, state.size() / 2);
}

// A system that has diverged (a sphere at 1e200 m/s, its kinetic energy infinite: an unstable
// time step does the like) is refused at its sample, before the density probe casts its
// positions to cells; one whose positions stop being finite, at the step.
TEST(Settle, ADivergedSystemIsRefusedAtItsSample) {
  ParticleStore store;
  store.add({0.01, 0.01, 0.01}, 0.005, kDensity);
  store.add({0.02, 0.01, 0.01}, 0.005, kDensity);
  store.velocity[1] = {1e200, 0.0, 0.0};
  DemSettings settings;
  settings.time_step = 1e-5;
  // Refused when the system is made (its first list build sees the sphere's step: DemBlowUp),
  // or else at its sample: never by the density probe.
  bool probed = false;
  EXPECT_THROW(
      {
        DemSystem dem(store, Container::square(0.05, 0.05, false), make_contact_model(material(0.5, 0.3)), settings);
        (void)sample_system(dem, store, 1.0, [&](const ParticleStore&) { return probed = true, 0.5; });
      },
      InputError);
  EXPECT_FALSE(probed);
  // Diverging within a step: a position no longer finite stops it, before a neighbour list
  // is built from it (the Morton sort and the grid cast positions to cells).
  store.velocity[1] = {std::numeric_limits<double>::infinity(), 0.0, 0.0};
  // (Here the first list build, when the system is made, already sees a sphere that moves
  // further than its radius in a step: a blow-up, DemBlowUp, an InputError.)
  EXPECT_THROW(
      {
        DemSystem lost(store, Container::square(0.05, 0.05, false), make_contact_model(material(0.5, 0.3)), settings);
        lost.run(1);
      },
      InputError);
}

// The progress line's time left for a settling run: an energy decaying as E0 (t / t0)^-a
// after its peak at t0 falls below the threshold at t0 (E0 / threshold)^(1/a), and the run
// ends one window later.
TEST(Settle, QuietForecastOfAPowerLawDecay) {
  QuietCriterion criterion;
  criterion.max_time = 10.0;
  criterion.sample_interval = 1e-3;
  criterion.window = 0.05;
  criterion.kinetic_fraction = 1e-5;
  const double e0 = 1e-2, t0 = 0.03, a = 3.5;
  const double expected = t0 * std::pow(e0 / criterion.kinetic_fraction, 1.0 / a) + criterion.window;  // 0.27 s
  const auto energy = [&](double t) { return t < t0 ? e0 * std::exp((t - t0) / 0.005) : e0 * std::pow(t / t0, -a); };
  const auto sample = [](double t, double e) {
    SettleSample s;
    s.time = t;
    s.translational_per_particle_mgd = e;
    return s;
  };
  QuietForecast forecast(criterion);
  // Rising energy (the bed collapsing): no forecast, the bound applies.
  for (int k = 0; k <= 25; ++k) forecast.add(sample(1e-3 * k, energy(1e-3 * k)));
  EXPECT_FALSE(forecast.expected_end());
  // A noisy decay, part of the way down: the forecast is within a few per cent.
  for (int k = 26; k <= 120; ++k) forecast.add(sample(1e-3 * k, energy(1e-3 * k) * (k % 2 ? 1.2 : 0.8)));
  ASSERT_TRUE(forecast.expected_end());
  EXPECT_NEAR(*forecast.expected_end(), expected, 0.03 * expected);
  // Below the threshold: the window from the last loud sample.
  for (int k = 121; k <= 250; ++k) forecast.add(sample(1e-3 * k, energy(1e-3 * k)));
  EXPECT_NEAR(*forecast.expected_end(), expected, 2e-3);
  // Never past max_time.
  criterion.max_time = 0.2;
  QuietForecast capped(criterion);
  for (int k = 0; k <= 100; ++k) capped.add(sample(1e-3 * k, energy(1e-3 * k)));
  EXPECT_DOUBLE_EQ(*capped.expected_end(), 0.2);
}

TEST(Settle, StopsWhenQuietOrAtTheMaximumTime) {
  const double r = 0.01;
  ParticleStore store = sphere_on_the_floor(r);
  DemSettings settings;
  settings.time_step = 1e-5;
  const Container box = Container::square(0.1, 0.1, false);
  const ContactModel model = make_contact_model(material(0.3, 0.5));
  QuietCriterion criterion;
  criterion.max_time = 1.0;
  std::size_t samples = 0;
  DemSystem dem(store, box, model, settings);
  const SettleResult quiet = settle(dem, store, criterion, [](const ParticleStore& s) { return s.position[0].z; },
                                    [&](const SettleSample&) { ++samples; });
  EXPECT_EQ(quiet.end, SettleEnd::Quiet);
  EXPECT_LT(quiet.simulated_time, 1.0);
  EXPECT_GE(quiet.simulated_time, criterion.window);
  EXPECT_EQ(samples, quiet.steps / 100 + 1);

  store.position[0].z = 0.05;  // falls for ~0.09 s, then bounces
  criterion.max_time = 0.02;
  DemSystem falling(store, box, model, settings);
  const SettleResult cut = settle(falling, store, criterion, nullptr, nullptr);
  EXPECT_EQ(cut.end, SettleEnd::MaxTime);
  EXPECT_NEAR(cut.simulated_time, 0.02, 1e-9);
}

}  // namespace
}  // namespace aggpack
