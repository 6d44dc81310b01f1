// Rigid bodies of several spheres in the DEM: the free rotor against its closed form and
// its conservation laws, a grain at rest on the floor, Newton's third law between bodies,
// and the same bytes for any thread count or a restored state.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "aggpack/core/error.hpp"
#include "aggpack/core/quaternion.hpp"
#include "aggpack/core/rng.hpp"
#include "aggpack/dynamics/dem_system.hpp"
#include "aggpack/dynamics/pour.hpp"
#include "aggpack/dynamics/rigid_rotation.hpp"

namespace aggpack {
namespace {

constexpr double kDensity = 2650.0;
constexpr double kModulus = 1e8;  // soft, so that contacts last many steps
constexpr double kPoisson = 0.3;
const double kEStar = effective_youngs_modulus(kModulus, kPoisson, kModulus, kPoisson);

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

double ball_volume(double r) { return 4.0 / 3.0 * std::numbers::pi * r * r * r; }

// A shape of equal spheres that do not overlap: its union's volume and principal moments are
// the closed forms (each ball's own 2/5 V r^2 plus V d^2 by the parallel axes).
struct BallsShape {
  std::vector<Vec3> centres;
  std::vector<double> radii;
  Vec3 moments;  // per unit density
  double volume = 0.0;
  [[nodiscard]] RigidBodyShape view() const { return {centres, radii, volume, moments}; }
};

BallsShape balls(const std::vector<Vec3>& centres, double r) {
  BallsShape shape{centres, std::vector<double>(centres.size(), r), {}, 0.0};
  const double v = ball_volume(r), own = 0.4 * v * r * r;
  for (const Vec3& c : centres) {
    shape.volume += v;
    shape.moments += Vec3{own + v * (c.y * c.y + c.z * c.z), own + v * (c.x * c.x + c.z * c.z),
                          own + v * (c.x * c.x + c.y * c.y)};
  }
  return shape;
}

// Four balls on the x and y axes at ±a and ±b (a > b): I_x < I_y < I_z, y the intermediate axis.
BallsShape cross_shape(double r, double a, double b) { return balls({{a, 0, 0}, {-a, 0, 0}, {0, b, 0}, {0, -b, 0}}, r); }

// Three balls at the corners of an equilateral triangle of side s in the plane z = 0.
BallsShape triangle_shape(double r, double s) {
  const double rho = s / std::sqrt(3.0);
  std::vector<Vec3> centres;
  for (int k = 0; k < 3; ++k) {
    const double angle = 2.0 * std::numbers::pi * k / 3.0;
    centres.push_back({rho * std::cos(angle), rho * std::sin(angle), 0.0});
  }
  return balls(centres, r);
}

double distance(const Quaternion& a, const Quaternion& b) {
  const auto length = [](double w, double x, double y, double z) { return std::sqrt(w * w + x * x + y * y + z * z); };
  // q and -q are one orientation.
  return std::min(length(a.w - b.w, a.x - b.x, a.y - b.y, a.z - b.z), length(a.w + b.w, a.x + b.x, a.y + b.y, a.z + b.z));
}

// The symmetric top (I_x = I_y): its exact motion turns the body about its axis at
// L_z (1/I_z - 1/I_x) and the whole about L at |L| / I_x. The scheme is of second order: half
// the step, a quarter of the error.
// The matrix of a quaternion turns vectors as the quaternion does.
TEST(RigidRotation, AQuaternionsMatrixTurnsAsItDoes) {
  const Quaternion q = normalized(Quaternion{0.3, -0.5, 0.7, 0.2});
  const RotationMatrix m = rotation_matrix(q);
  for (const Vec3& v : {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0.3, -2, 5}}) {
    EXPECT_LT(norm(m(v) - rotate(q, v)), 1e-15 * norm(v));
    EXPECT_LT(norm(m.transposed(v) - rotate_back(q, v)), 1e-15 * norm(v));
  }
  // A quarter turn about z takes x to y.
  EXPECT_LT(norm(rotate(axis_angle({0, 0, 1}, std::numbers::pi / 2), {1, 0, 0}) - Vec3{0, 1, 0}), 1e-15);
}

TEST(RigidRotation, ASymmetricTopPrecessesAsTheClosedFormToSecondOrder) {
  const Vec3 inverse_inertia{1.0, 1.0, 1.0 / 2.5};
  const Quaternion start = normalized(Quaternion{0.9, 0.2, -0.3, 0.25});
  const Vec3 momentum{0.3, -0.8, 1.1};
  const double duration = 3.0;
  const Vec3 body_momentum = rotate_back(start, momentum);
  const double precession = norm(momentum) * inverse_inertia.x;
  const double spin = body_momentum.z * (inverse_inertia.z - inverse_inertia.x);
  const Quaternion exact = axis_angle(normalized(momentum), precession * duration) * start *
                           axis_angle({0, 0, 1}, spin * duration);
  const auto error_with = [&](int steps) {
    Quaternion q = start;
    for (int s = 0; s < steps; ++s) rotate_freely(q, momentum, inverse_inertia, duration / steps);
    return distance(q, exact);
  };
  const double coarse = error_with(300), fine = error_with(600), finer = error_with(1200);
  EXPECT_LT(coarse, 1e-3);
  EXPECT_NEAR(coarse / fine, 4.0, 0.3);
  EXPECT_NEAR(fine / finer, 4.0, 0.3);
  // The angular velocity of the closed form: L / I_x + spin along the body's axis.
  Quaternion q = start;
  const Vec3 w = angular_velocity_of(rotation_matrix(q), momentum, inverse_inertia);
  const Vec3 expected = precession / norm(momentum) * momentum + spin * rotate(q, {0, 0, 1});
  EXPECT_NEAR(norm(w - expected), 0.0, 1e-14 * norm(expected));
}

// One body alone (no gravity, far from every wall): its energy, by the scheme's second
// order, stays within (ω dt)^2 I_max / I_min of its start over 1e5 steps without drifting,
// and its angular momentum in space is kept to the bit (no torque acts: no part of the
// scheme changes it). Spun nearly about its intermediate axis, it flips over and back
// (the Dzhanibekov effect), which an integrator that damps or pumps energy would not show.
TEST(RigidBodies, ATorqueFreeAsymmetricGrainKeepsEnergyAndMomentumAndFlipsAboutItsIntermediateAxis) {
  const double r = 0.004;
  const BallsShape shape = cross_shape(r, 0.012, 0.0075);
  ParticleStore store;
  const Quaternion tilt = normalized(Quaternion{0.8, 0.3, 0.4, -0.2});
  store.add_body({0.05, 0.05, 0.05}, tilt, shape.view(), kDensity);
  const double omega = 20.0;  // rad/s, about the body's y, with a thousandth about x and z
  store.bodies.angular_velocity[0] = rotate(tilt, {1e-3 * omega, omega, 1e-3 * omega});
  DemSettings settings;
  settings.gravity = {};
  settings.time_step = 5e-4;  // ω dt = 0.01
  DemSystem dem(store, Container::square(0.1, 0.1, false), make_contact_model(material(0.5, 0.5)), settings);
  ASSERT_EQ(dem.body_count(), 1u);
  const double start_energy = dem.kinetic_energy().total();
  const Vec3 moments = shape.moments * kDensity;
  const Vec3 start_momentum = rotate(tilt, {moments.x * 1e-3 * omega, moments.y * omega, moments.z * 1e-3 * omega});
  const double bound = std::pow(omega * settings.time_step, 2) * moments.z / moments.x;
  double worst = 0.0;
  int flips = 0;
  double last_sign = 1.0;
  for (int sample = 0; sample < 10000; ++sample) {
    dem.run(10);
    worst = std::max(worst, std::abs(dem.kinetic_energy().total() / start_energy - 1.0));
    const Vec3 body_spin = rotate_back(store.bodies.orientation[0], store.bodies.angular_velocity[0]);
    if (body_spin.y * last_sign < 0.0) {
      ++flips;
      last_sign = -last_sign;
    }
  }
  EXPECT_LT(worst, bound);
  const double end_drift = std::abs(dem.kinetic_energy().total() / start_energy - 1.0);
  EXPECT_LT(end_drift, bound);
  // The momentum: the store's angular velocity back through the inertia.
  const Quaternion& q = store.bodies.orientation[0];
  const Vec3 w = rotate_back(q, store.bodies.angular_velocity[0]);
  const Vec3 momentum = rotate(q, {moments.x * w.x, moments.y * w.y, moments.z * w.z});
  EXPECT_LT(norm(momentum - start_momentum), 1e-12 * norm(start_momentum));
  EXPECT_GE(flips, 10);
  // The centre did not move, the members kept their places in the body.
  EXPECT_EQ(store.bodies.position[0], (Vec3{0.05, 0.05, 0.05}));
  for (std::uint32_t i = 0; i < 4; ++i) {
    const Vec3 place = store.bodies.position[0] + rotate(q, shape.centres[i]);
    EXPECT_LT(norm(store.position[i] - place), 1e-15);
  }
  std::printf("worst relative energy error %.3g (bound %.3g), flips %d\n", worst, bound, flips);
}

// A dumbbell of two balls at ±a: its rotational energy spun about y is ½ (2 (2/5 m r² + m a²)) ω².
TEST(RigidBodies, ADumbbellSpinsWithItsClosedFormInertia) {
  const double r = 0.003, a = 0.005;
  ParticleStore store;
  store.add_body({0.05, 0.05, 0.05}, {}, balls({{a, 0, 0}, {-a, 0, 0}}, r).view(), kDensity);
  const double m = kDensity * ball_volume(r), omega = 7.0;
  store.bodies.angular_velocity[0] = {0, omega, 0};
  DemSettings settings;
  settings.gravity = {};
  DemSystem dem(store, Container::square(0.1, 0.1, false), make_contact_model(material(0.5, 0.5)), settings);
  const double inertia = 2.0 * (0.4 * m * r * r + m * a * a);
  EXPECT_NEAR(dem.kinetic_energy().rotational, 0.5 * inertia * omega * omega, 1e-12);
  dem.run(1000);
  // Spun about a principal axis it turns about it steadily: after t, by ω t.
  const double angle = omega * dem.time();
  const Vec3 end = rotate(store.bodies.orientation[0], {1, 0, 0});
  EXPECT_NEAR(end.x, std::cos(angle), 1e-9);
  EXPECT_NEAR(end.z, -std::sin(angle), 1e-9);
  EXPECT_NEAR(store.velocity[0].z, -omega * a * std::cos(angle), 1e-9);
}

// A flat grain of three balls dropped tilted onto the floor rocks, lands flat, and comes to
// rest with each ball at the Hertz static overlap of a third of the weight; then it stays.
TEST(RigidBodies, ATiltedGrainLandsFlatAndRestsAtItsMembersHertzOverlap) {
  const double r = 0.005;
  const BallsShape shape = triangle_shape(r, 2.4 * r);
  ParticleStore store;
  const Quaternion tilt = axis_angle({1, 0, 0}, 0.2);
  double lowest = 1.0;
  for (const Vec3& c : shape.centres) lowest = std::min(lowest, rotate(tilt, c).z);
  store.add_body({0.05, 0.05, r - lowest + 1e-4}, tilt, shape.view(), kDensity);
  DemSettings settings;
  settings.time_step = 1e-5;
  DemSystem dem(store, Container::square(0.1, 0.1, false), make_contact_model(material(0.3, 0.5)), settings);
  dem.run(60000);
  const double weight = store.bodies.mass[0] * 9.81;
  const double expected = hertz_static_overlap(weight / 3.0, kEStar, r);
  for (std::uint32_t i = 0; i < 3; ++i) EXPECT_NEAR(r - store.position[i].z, expected, 0.02 * expected) << i;
  EXPECT_LT(norm(dem.body_force(0)), 1e-4 * weight);
  const Vec3 rested = store.bodies.position[0];
  const Quaternion turned = store.bodies.orientation[0];
  dem.run(20000);
  EXPECT_LT(norm(store.bodies.position[0] - rested), 1e-9);
  EXPECT_LT(distance(store.bodies.orientation[0], turned), 1e-7);
  EXPECT_LT(norm(store.bodies.velocity[0]), 1e-6);
  EXPECT_LT(norm(store.bodies.angular_velocity[0]), 1e-4);
}

// Two grains thrown at each other, spinning: what one's members push on the other's comes
// back equal and opposite, so the net forces on the two bodies cancel to rounding at every
// step and the momentum is kept; without friction every contact force is central, and the
// angular momentum about any point is kept as well (velocity Verlet and the splitting are
// both exact for it).
TEST(RigidBodies, TwoGrainsCollidingKeepMomentumByNewtonsThirdLaw) {
  for (const double friction : {0.5, 0.0}) {
    const double r = 0.004;
    const BallsShape shape = cross_shape(r, 0.012, 0.0075);
    ParticleStore store;
    store.add_body({0.03, 0.05, 0.05}, normalized(Quaternion{1, 0.2, 0.1, 0}), shape.view(), kDensity);
    store.add_body({0.062, 0.053, 0.052}, normalized(Quaternion{0.7, 0, 0.3, 0.5}), shape.view(), kDensity);
    store.bodies.velocity = {{0.4, 0, 0}, {-0.3, 0.05, 0}};
    store.bodies.angular_velocity = {{0, 0, 15}, {5, -3, 0}};
    DemSettings settings;
    settings.gravity = {};
    settings.time_step = 1e-6;
    DemSystem dem(store, Container::square(0.1, 0.1, false), make_contact_model(material(0.8, friction)), settings);
    const auto momentum = [&] {
      Vec3 p{}, l{};
      for (std::size_t b = 0; b < 2; ++b) {
        const Vec3 moments = shape.moments * kDensity;
        const Quaternion& q = store.bodies.orientation[b];
        const Vec3 w = rotate_back(q, store.bodies.angular_velocity[b]);
        p += store.bodies.mass[b] * store.bodies.velocity[b];
        l += cross(store.bodies.position[b], store.bodies.mass[b] * store.bodies.velocity[b]) +
             rotate(q, {moments.x * w.x, moments.y * w.y, moments.z * w.z});
      }
      return std::array<Vec3, 2>{p, l};
    };
    const auto [p0, l0] = momentum();
    double largest = 0.0;
    int touching = 0;
    for (int s = 0; s < 40000; ++s) {
      dem.run(1);
      const Vec3 f0 = dem.body_force(0), f1 = dem.body_force(1);
      largest = std::max(largest, norm(f0));
      if (norm(f0) > 0.0) ++touching;
      EXPECT_LE(norm(f0 + f1), 1e-12 * norm(f0)) << s;
      if (HasFailure()) break;
    }
    EXPECT_GT(touching, 100) << "the grains never met";
    const auto [p1, l1] = momentum();
    EXPECT_LT(norm(p1 - p0), 1e-12 * norm(p0)) << friction;
    if (friction == 0.0) {
      EXPECT_LT(norm(l1 - l0), 1e-10 * norm(l0));
    }
    // They bounced: each one's velocity along the line of centres turned round.
    EXPECT_LT(store.bodies.velocity[0].x, 0.3);
  }
}

// A grain admitted into a running system (a pour's next batch) falls freely under its own
// weight: velocity Verlet is exact under a constant force, z = z0 - g t²/2 to rounding, and
// it does not turn. A second grain admitted in a system of spheres, the same.
TEST(RigidBodies, AGrainAdmittedIntoARunningSystemFallsFreely) {
  ParticleStore store;
  store.add({0.02, 0.02, 0.002}, 0.002, kDensity);
  DemSettings settings;
  settings.time_step = 1e-5;
  DemSystem dem(store, Container::square(0.1, 0.3, false), make_contact_model(material(0.5, 0.5)), settings);
  dem.run(100);
  const BallsShape shape = cross_shape(0.004, 0.012, 0.0075);
  const Quaternion q = normalized(Quaternion{0.6, 0.1, 0.5, 0.2});
  for (int body = 0; body < 2; ++body) {
    const Vec3 start{0.06, 0.05, 0.2 - 0.05 * body};
    store.add_body(start, q, shape.view(), kDensity);
    dem.admit_new_particles();
    EXPECT_EQ(dem.body_count(), static_cast<std::size_t>(body + 1));
    dem.run(2000);
    const double t = 2000 * settings.time_step;
    EXPECT_NEAR(store.bodies.position[body].z, start.z - 0.5 * 9.81 * t * t, 1e-12);
    EXPECT_NEAR(store.bodies.velocity[body].z, -9.81 * t, 1e-12);
    EXPECT_EQ(store.bodies.orientation[body], q);
  }
}

// A pour of grains and spheres, in turns, into a walled box: the grains come in at random
// orientations, touching nothing, fall and settle with the spheres into a bed inside the box,
// every member where its body's pose has it, no contact overlapping more than 1 %.
TEST(RigidBodies, APourOfGrainsAndSpheresSettlesIntoABed) {
  const BallsShape unit = cross_shape(0.25, 0.75, 0.5);  // reach 1
  ASSERT_DOUBLE_EQ(unit.view().reach(), 1.0);
  std::vector<double> radii;
  std::vector<const RigidBodyShape*> shapes;
  const RigidBodyShape shape = unit.view();
  for (int k = 0; k < 80; ++k) {
    const bool grain = k % 2 == 0;
    radii.push_back(grain ? 0.004 : 0.002);
    shapes.push_back(grain ? &shape : nullptr);
  }
  ParticleStore store;
  const Container box = Container::square(0.04, 0.3, false);
  DemSettings settings;
  settings.time_step = 1e-5;
  settings.skin = 2e-4;
  DemSystem dem(store, box, make_contact_model(material(0.3, 0.5)), settings);
  PourSettings pouring;
  pouring.solid_fraction = 0.1;
  pouring.batches = 2;
  QuietCriterion quiet;
  quiet.max_time = 1.5;
  PourLoop loop = begin_pour(dem, pouring, radii, Rng(38, 5));
  PourHooks hooks;
  hooks.on_sample = [](const SettleSample&, std::string_view) {};
  hooks.at_safe_point = [](std::string_view) {};
  const SettleResult result = pour(dem, store, box, radii, pouring, 0, SphereMaterials::all_of(kDensity),
                                   PouredShapes{shapes}, quiet, loop, false, hooks);
  EXPECT_EQ(result.end, SettleEnd::Quiet);
  ASSERT_EQ(store.bodies.size(), 40u);
  EXPECT_EQ(store.size(), 40u * 4 + 40u);
  EXPECT_LT(dem.contact_statistics().max_overlap, 0.01);
  double top = 0.0;
  for (std::size_t i = 0; i < store.size(); ++i) {
    const Vec3& x = store.position[i];
    const double r = store.radius[i];
    EXPECT_TRUE(x.x > r * 0.9 && x.x < 0.04 - 0.9 * r && x.y > 0.9 * r && x.y < 0.04 - 0.9 * r && x.z > 0.9 * r) << i;
    top = std::max(top, x.z + r);
  }
  // Loose or dense, a bed of some 19 cm^3 of solid over 16 cm^2 is a few centimetres deep.
  EXPECT_LT(top, 0.05);
  for (std::size_t b = 0; b < 40; ++b) {
    EXPECT_NEAR(store.bodies.mass[b], kDensity * unit.volume * std::pow(0.004, 3), 1e-12);
    for (std::uint32_t k = 0; k < 4; ++k) {
      const std::uint32_t i = store.bodies.first_member[b] + k;
      EXPECT_NEAR(store.radius[i], 0.001, 1e-15);
      const Vec3 place = store.bodies.position[b] + rotate(store.bodies.orientation[b], store.body_offset[i]);
      EXPECT_LT(norm(store.position[i] - place), 1e-12);
    }
  }
  EXPECT_NE(store.bodies.orientation[0], store.bodies.orientation[1]);
}

// A bed of grains and spheres in a periodic box, settling: the same bytes for one thread or
// two, and from a state saved halfway and restored into a fresh system (with the other count).
ParticleStore mixed_bed() {
  ParticleStore store;
  const double r = 0.0015;
  const BallsShape shape = cross_shape(r, 0.003, 0.0022);
  Rng rng(38, 7);
  // On a lattice of 9 mm cells: a grain in each (its reach is 4.5 mm), a sphere between; the
  // first column and row of grains astride the periodic sides.
  for (int k = 0; k < 420; ++k) {
    const Vec3 cell{0.009 * (k % 6), 0.009 * ((k / 6) % 6), 0.006 + 0.009 * (k / 36)};
    const Quaternion q = normalized(Quaternion{rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1),
                                               rng.uniform(-1, 1)});
    const std::size_t b = store.add_body(cell, q, shape.view(), kDensity);
    store.bodies.velocity[b] = {rng.uniform(-0.1, 0.1), rng.uniform(-0.1, 0.1), rng.uniform(-0.1, 0.1)};
    store.bodies.angular_velocity[b] = {rng.uniform(-20, 20), rng.uniform(-20, 20), rng.uniform(-20, 20)};
    if (k % 2 == 0) store.add(cell + Vec3{0.0045, 0.0045, 0.0045}, 0.001, kDensity);
  }
  return store;
}

void expect_same_bytes(const ParticleStore& a, const ParticleStore& b) {
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(0, std::memcmp(a.position.data(), b.position.data(), a.size() * sizeof(Vec3)));
  EXPECT_EQ(0, std::memcmp(a.velocity.data(), b.velocity.data(), a.size() * sizeof(Vec3)));
  EXPECT_EQ(0, std::memcmp(a.angular_velocity.data(), b.angular_velocity.data(), a.size() * sizeof(Vec3)));
  ASSERT_EQ(a.bodies.size(), b.bodies.size());
  const std::size_t n = a.bodies.size();
  EXPECT_EQ(0, std::memcmp(a.bodies.position.data(), b.bodies.position.data(), n * sizeof(Vec3)));
  EXPECT_EQ(0, std::memcmp(a.bodies.orientation.data(), b.bodies.orientation.data(), n * sizeof(Quaternion)));
  EXPECT_EQ(0, std::memcmp(a.bodies.angular_velocity.data(), b.bodies.angular_velocity.data(), n * sizeof(Vec3)));
}

DemSettings bed_settings(int threads) {
  DemSettings settings;
  settings.time_step = 2e-6;
  settings.skin = 5e-5;  // small, so that the list is rebuilt during the run
  settings.threads = threads;
  settings.adapt_threads = false;
  return settings;
}

TEST(RigidBodies, ABedOfGrainsGivesTheSameBytesForOneAndTwoThreadsAndFromARestoredState) {
  const ParticleStore start = mixed_bed();
  ASSERT_GE(start.size(), 1024u);  // threaded loops
  const Container box = Container::square(0.054, 0.2, true);
  const ContactModel model = make_contact_model(material(0.5, 0.4));
  const auto run = [&](int threads, std::size_t steps, ParticleStore store) {
    DemSystem dem(store, box, model, bed_settings(threads));
    dem.run(steps);
    EXPECT_GE(dem.rebuilds(), 2u);
    dem.finish();
    return store;
  };
  const ParticleStore one = run(1, 1000, start), two = run(2, 1000, start);
  expect_same_bytes(one, two);

  ParticleStore first_half = start;
  DemSystem interrupted(first_half, box, model, bed_settings(1));
  interrupted.run(500);
  std::ostringstream saved(std::ios::binary);
  interrupted.save_state(saved);
  ParticleStore resumed_store = first_half;
  DemSystem resumed(resumed_store, box, model, bed_settings(2));
  resumed.restore_state(saved.str());
  resumed.run(500);
  resumed.finish();
  expect_same_bytes(one, resumed_store);

  // The grains moved and collided, and kept their shapes: each member at its body's centre
  // plus its turned offset, to a period (some members lie a period away from that place:
  // their grains are astride a periodic side).
  int astride = 0;
  double moved = 0.0;
  for (std::size_t b = 0; b < one.bodies.size(); ++b) {
    moved = std::max(moved, norm(one.bodies.position[b] - start.bodies.position[b]));
    for (std::uint32_t k = 0; k < one.bodies.member_count[b]; ++k) {
      const std::uint32_t i = one.bodies.first_member[b] + k;
      const Vec3 place = one.bodies.position[b] + rotate(one.bodies.orientation[b], one.body_offset[i]);
      EXPECT_LT(norm(box.minimum_image(one.position[i] - place)), 1e-12) << b;
      if (norm(one.position[i] - place) > 0.027) ++astride;
    }
  }
  EXPECT_GT(moved, 1e-4);
  EXPECT_GT(astride, 0);
}

// A member may not be frozen, and a damaged body record in a state is refused.
// A frozen grain (a layer below the one that settles) hangs where it is, in the air, and
// bears a grain of its shape dropped onto it, member above member: it does not move by a bit,
// and the one on it comes to rest with each of the four member contacts at the Hertz static
// overlap of a quarter of its weight. The same grain free falls. A saved state continues the
// same bytes in a system of the same frozen grains and is refused by one where they are free.
TEST(RigidBodies, AFrozenGrainHoldsStillUnderTheGrainThatLandsOnIt) {
  const double r = 0.004;
  const BallsShape shape = cross_shape(r, 0.012, 0.0075);
  ParticleStore start;
  start.add_body({0.05, 0.05, 0.03}, {}, shape.view(), kDensity);
  start.add_body({0.05, 0.05, 0.03 + 2.0 * r + 1e-3}, {}, shape.view(), kDensity);
  std::vector<std::uint8_t> frozen(start.size(), 0);
  std::fill(frozen.begin(), frozen.begin() + 4, 1);  // the lower grain's four members
  // Handed over moving (a pour's last state): frozen, it stops where it is.
  start.bodies.velocity[0] = {0.1, 0, -0.2};
  start.bodies.angular_velocity[0] = {0, 3, 0};
  DemSettings settings;
  settings.time_step = 1e-5;
  const ContactModel model = make_contact_model(material(0.3, 0.5));
  const Container box = Container::square(0.1, 0.1, false);

  ParticleStore store = start;
  DemSystem dem(store, box, model, settings, frozen);
  EXPECT_EQ(dem.free_count(), 4u);
  dem.run(30000);
  EXPECT_EQ(store.bodies.position[0], start.bodies.position[0]);
  EXPECT_EQ(store.bodies.orientation[0], start.bodies.orientation[0]);
  EXPECT_EQ(store.bodies.velocity[0], Vec3{});
  EXPECT_EQ(store.bodies.angular_velocity[0], Vec3{});
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(store.position[i], start.position[i]) << i;
    EXPECT_EQ(store.velocity[i], Vec3{}) << i;
  }
  const double weight = store.bodies.mass[1] * 9.81;
  const double expected = hertz_static_overlap(0.25 * weight, kEStar, 0.5 * r);
  for (std::size_t i = 0; i < 4; ++i)
    EXPECT_NEAR(2.0 * r - (store.position[i + 4].z - store.position[i].z), expected, 0.02 * expected) << i;
  EXPECT_LT(norm(dem.body_force(1)), 1e-4 * weight);
  EXPECT_EQ(dem.body_force(0), Vec3{});
  EXPECT_LT(dem.kinetic_energy().translational, 1e-12 * weight * r);

  // Saved, restored into a system of the same frozen grain, run on: the bytes of the first.
  std::ostringstream saved(std::ios::binary);
  dem.save_state(saved);
  ParticleStore copy = store;
  DemSystem restored(copy, box, model, settings, frozen);
  restored.restore_state(saved.str());
  dem.run(500);
  restored.run(500);
  EXPECT_EQ(copy.position, store.position);
  EXPECT_EQ(copy.bodies.position, store.bodies.position);
  ParticleStore free_copy = store;
  DemSystem all_free(free_copy, box, model, settings);
  EXPECT_THROW(all_free.restore_state(saved.str()), InputError);

  // Unfrozen, the lower grain falls as soon as it is let go.
  ParticleStore falling = start;
  falling.bodies.velocity[0] = falling.bodies.angular_velocity[0] = {};
  DemSystem unfrozen(falling, box, model, settings);
  unfrozen.run(100);
  EXPECT_LT(falling.bodies.position[0].z, start.bodies.position[0].z - 1e-7);
}

TEST(RigidBodies, APartlyFrozenBodyOrADamagedBodyStateIsRefused) {
  const BallsShape shape = cross_shape(0.004, 0.012, 0.0075);
  ParticleStore store;
  store.add_body({0.05, 0.05, 0.05}, {}, shape.view(), kDensity);
  std::vector<std::uint8_t> frozen(store.size(), 0);
  frozen[1] = 1;  // one member of four: a body is frozen whole or not at all
  const ContactModel model = make_contact_model(material(0.5, 0.5));
  EXPECT_THROW(DemSystem(store, Container::square(0.1, 0.1, false), model, DemSettings{}, frozen),
               std::invalid_argument);
  DemSystem dem(store, Container::square(0.1, 0.1, false), model, DemSettings{});
  dem.run(10);
  std::ostringstream saved(std::ios::binary);
  dem.save_state(saved);
  const std::string state = saved.str();
  ParticleStore other = store;
  DemSystem fresh(other, Container::square(0.1, 0.1, false), model, DemSettings{});
  EXPECT_NO_THROW(fresh.restore_state(state));
  // The state ends with the members' periodic images: the last one's z made NaN.
  std::string damaged = state;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::memcpy(damaged.data() + damaged.size() - sizeof(double), &nan, sizeof(double));
  EXPECT_THROW(fresh.restore_state(damaged), InputError);
  // Before them the arms (4), the members' body ids (4), the body's load and its record (240
  // bytes), each list with its 8-byte length: the body's centre moved by 1 mm is refused too
  // (finite, but not where the store has it, nor where its members are).
  std::string moved = state;
  const std::size_t record = moved.size() - (8 + 4 * sizeof(Vec3)) * 2 - (8 + 4 * sizeof(std::uint32_t)) -
                             (8 + 2 * sizeof(Vec3)) - 240;
  double x = 0.0;
  std::memcpy(&x, moved.data() + record, sizeof x);
  ASSERT_DOUBLE_EQ(x, 0.05);  // the body's centre, x
  x += 1e-3;
  std::memcpy(moved.data() + record, &x, sizeof x);
  EXPECT_THROW(fresh.restore_state(moved), InputError);
}

}  // namespace
}  // namespace aggpack
