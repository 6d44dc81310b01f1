// Rolling resistance against closed forms: the constant torque mu_r R* F_n and LAMMPS's
// spring-dashpot (`rolling sds`), on the law alone and on a sphere rolling on the floor.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <sstream>
#include <string>

#include "aggpack/core/rng.hpp"
#include "aggpack/deposition/drop_and_roll.hpp"
#include "aggpack/dynamics/dem_system.hpp"

namespace aggpack {
namespace {

constexpr double kDensity = 2650.0;
constexpr double kModulus = 1e8;  // soft, so that contacts last many steps
constexpr double kPoisson = 0.3;
constexpr double kRadius = 0.005;
constexpr double kG = 9.81;
constexpr double kMuR = 0.1;
constexpr double kKRoll = 100.0;  // N/m: the cap (about 1.4e-3 N) within a few micrometres

ContactParameters material(RollingModel model, double rolling_damping = 0.0) {
  ContactParameters p;
  p.youngs_modulus = p.wall_youngs_modulus = kModulus;
  p.poisson_ratio = p.wall_poisson_ratio = kPoisson;
  p.restitution = 0.5;
  p.friction_particle = p.friction_wall = 0.5;  // enough that nothing slides here
  p.rolling_friction = kMuR;
  p.rolling_model = model;
  if (model == RollingModel::SpringDashpot) {
    p.rolling_stiffness = kKRoll;
    p.rolling_damping = rolling_damping;
  }
  return p;
}

const double kEStar = effective_youngs_modulus(kModulus, kPoisson, kModulus, kPoisson);
double sphere_mass(double r) { return kDensity * 4.0 / 3.0 * std::numbers::pi * r * r * r; }

// One sphere resting on the floor under gravity g (tilted: an incline), rolling along x
// without slip at `speed`.
struct RollingSphere {
  ParticleStore store;
  DemSystem dem;
  RollingSphere(const ContactParameters& p, const Vec3& g, double speed)
      : store(one_sphere(g, speed)), dem(store, Container::square(2.0, 0.1, false), make_contact_model(p), settings(g)) {}
  static ParticleStore one_sphere(const Vec3& g, double speed) {
    ParticleStore s;
    const double overlap = hertz_static_overlap(sphere_mass(kRadius) * -g.z, kEStar, kRadius);
    s.add({0.2, 0.05, kRadius - overlap}, kRadius, kDensity);
    s.velocity[0] = {speed, 0.0, 0.0};
    s.angular_velocity[0] = {0.0, speed / kRadius, 0.0};
    return s;
  }
  static DemSettings settings(const Vec3& g) {
    DemSettings s;
    s.gravity = g;
    s.time_step = 1e-5;
    return s;
  }
  [[nodiscard]] double speed() const { return store.velocity[0].x; }
};

// A solid sphere rolling without slip under the torque M = mu_r R F_n about its contact:
// (I + m R^2) a = -M with I = (2/5) m R^2 and F_n = m g, so a = -(5/7) mu_r g.
TEST(RollingResistance, ConstantTorqueDeceleratesARollingSphereAtFiveSeventhsMuRG) {
  RollingSphere s(material(RollingModel::ConstantTorque), {0.0, 0.0, -kG}, 0.5);
  s.dem.run(30000);  // 0.3 s
  const double expected = 0.5 - 5.0 / 7.0 * kMuR * kG * s.dem.time();
  EXPECT_NEAR(s.speed(), expected, 0.01 * expected);
  EXPECT_NEAR(s.store.angular_velocity[0].y * kRadius, expected, 0.01 * expected);
}

// The spring-dashpot law reaches its cap within microseconds and then rolls plastically at
// the same torque: the same deceleration; then it stops, and stays stopped (the spring holds).
TEST(RollingResistance, SpringDashpotDeceleratesAtTheSameCapAndStopsTheSphere) {
  RollingSphere s(material(RollingModel::SpringDashpot, 0.3), {0.0, 0.0, -kG}, 0.5);
  s.dem.run(30000);
  const double expected = 0.5 - 5.0 / 7.0 * kMuR * kG * s.dem.time();
  EXPECT_NEAR(s.speed(), expected, 0.01 * expected);
  s.dem.run(60000);  // to 0.9 s, past the stop at 0.73 s
  const double stopped_at = s.store.position[0].x;
  EXPECT_LT(std::abs(s.speed()), 1e-4);
  s.dem.run(20000);
  EXPECT_LT(std::abs(s.speed()), 1e-5);
  EXPECT_NEAR(s.store.position[0].x, stopped_at, 1e-6);
  // The distance rolled: v0^2 / (2 a).
  EXPECT_NEAR(stopped_at - 0.2, 0.25 / (2.0 * 5.0 / 7.0 * kMuR * kG), 0.01 * 0.25 / (1.4 * kMuR * kG));
}

// Random contacts, many steps each (the spring's history builds up): the rolling torque is
// never above mu_r R* F_n, for either law.
TEST(RollingResistance, TheTorqueNeverExceedsMuRRStarFn) {
  Rng rng(17, 3);
  for (const RollingModel model : {RollingModel::ConstantTorque, RollingModel::SpringDashpot}) {
    const ContactModel laws = make_contact_model(material(model, 0.01));
    const HertzMindlin& law = std::get<HertzMindlin>(laws.particle);
    double largest = 0.0;
    for (int contact = 0; contact < 200; ++contact) {
      Vec3 spring{}, history{};
      for (int step = 0; step < 50; ++step) {
        ContactKinematics k;
        const Vec3 n{rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)};
        k.normal = n * (1.0 / norm(n));
        k.overlap = rng.uniform(1e-7, 1e-5);
        k.velocity = {rng.uniform(-0.1, 0.1), rng.uniform(-0.1, 0.1), rng.uniform(-0.1, 0.1)};
        k.spin = {rng.uniform(-50, 50), rng.uniform(-50, 50), rng.uniform(-50, 50)};
        k.r_eff = rng.uniform(0.001, 0.005);
        k.m_eff = sphere_mass(k.r_eff);
        const ContactForce f = law.evaluate(k, spring, history, 1e-5);
        const double cap = kMuR * k.r_eff * f.normal;
        ASSERT_LE(norm(f.rolling_torque), cap * (1.0 + 1e-12)) << name_of(kRollingModelNames, model);
        largest = std::max(largest, norm(f.rolling_torque) / cap);
      }
    }
    EXPECT_GT(largest, 0.999) << "the cap is reached";
  }
}

// The spring's torque is elastic below the cap: a small rolling twist theta (no damping)
// gives k_roll R*^2 theta, and the same twist back gives the history and torque back to 0.
TEST(RollingResistance, SpringDashpotIsElasticBelowTheCap) {
  const ContactModel laws = make_contact_model(material(RollingModel::SpringDashpot));
  const HertzMindlin& law = std::get<HertzMindlin>(laws.particle);
  ContactKinematics k;
  k.normal = {0.0, 0.0, -1.0};  // i rests on j below
  k.overlap = 1e-5;
  k.r_eff = kRadius;
  k.m_eff = sphere_mass(kRadius);
  const double dt = 1e-6, spin = 0.5;  // rad/s: 5e-5 rad in 100 steps
  Vec3 spring{}, history{};
  ContactForce f;
  for (const double sign : {1.0, -1.0}) {
    k.spin = {0.0, sign * spin, 0.0};
    for (int step = 0; step < 100; ++step) f = law.evaluate(k, spring, history, dt);
    if (sign > 0) {
      const double theta = spin * 100 * dt;
      ASSERT_LT(kKRoll * kRadius * theta, 0.5 * kMuR * f.normal) << "below the cap";
      EXPECT_NEAR(norm(f.rolling_torque), kKRoll * kRadius * kRadius * theta, 1e-9 * kKRoll * kRadius * kRadius * theta);
      EXPECT_LT(f.rolling_torque.y, 0.0) << "against the spin";
    }
  }
  EXPECT_LT(norm(history), 1e-18);
  EXPECT_LT(norm(f.rolling_torque), 1e-15);
}

// A sphere on an incline, friction high enough that it cannot slide: at rest, the friction
// force F_t = m g sin(theta) acts at the contact with a torque F_t R about the centre, which
// the rolling torque must balance: m g sin(theta) R <= mu_r R m g cos(theta), so the sphere
// holds while tan(theta) <= mu_r. Above, it rolls with (I + m R^2) a = m g R sin(theta) -
// mu_r R m g cos(theta): a = (5/7) g (sin(theta) - mu_r cos(theta)).
double incline_acceleration(RollingModel model, double tan_theta, double& creep) {
  const double theta = std::atan(tan_theta);
  RollingSphere s(material(model, 0.3), {kG * std::sin(theta), 0.0, -kG * std::cos(theta)}, 0.0);
  s.dem.run(10000);
  const double v1 = s.speed(), t1 = s.dem.time();
  s.dem.run(20000);
  creep = std::abs(s.speed());
  return (s.speed() - v1) / (s.dem.time() - t1);
}

TEST(RollingResistance, ASphereOnAnInclineHoldsBelowTanThetaEqualsMuRAndRollsAbove) {
  for (const RollingModel model : {RollingModel::ConstantTorque, RollingModel::SpringDashpot}) {
    const std::string name(name_of(kRollingModelNames, model));
    double creep = 0.0;
    incline_acceleration(model, 0.8 * kMuR, creep);
    // The spring holds the sphere still. The constant torque flips with the spin: its band of
    // regularisation (1e-6 m/s) is narrower than the spin one step of its torque gives (here
    // 2.4e-5 m/s), so it chatters about rest and creeps down at about 2e-5 m/s, a thousandth
    // of the speed it reaches above the angle.
    EXPECT_LT(creep, model == RollingModel::SpringDashpot ? 1e-7 : 5e-5) << name;
    const double theta = std::atan(1.25 * kMuR);
    const double expected = 5.0 / 7.0 * kG * (std::sin(theta) - kMuR * std::cos(theta));
    EXPECT_NEAR(incline_acceleration(model, 1.25 * kMuR, creep), expected, 0.02 * expected) << name;
  }
}

// A sphere held on an incline by the rolling spring holds through a list rebuild (forced by
// admitting a far sphere): the rebuild carries its wall contact's rolling history over.
TEST(RollingResistance, TheSpringHoldsASphereThroughAListRebuild) {
  const double theta = std::atan(0.8 * kMuR);
  RollingSphere s(material(RollingModel::SpringDashpot, 0.3), {kG * std::sin(theta), 0.0, -kG * std::cos(theta)}, 0.0);
  s.dem.run(20000);
  const Vec3 before = s.store.position[0];
  const std::size_t rebuilds = s.dem.rebuilds();
  s.store.add({1.5, 0.05, 0.05}, kRadius, kDensity);
  s.dem.admit_new_particles();
  EXPECT_GT(s.dem.rebuilds(), rebuilds);
  s.dem.run(2000);
  // Without its history the sphere would roll about 1e-5 m before the spring caught it again.
  EXPECT_LT(norm(s.store.position[0] - before), 1e-9);
}

// The rolling history is kept per list entry, carried through rebuilds and saved: a state
// restored into a fresh system goes on bit for bit; the state of the constant-torque law has
// no rolling history (its bytes are those it had before the spring-dashpot model).
std::string saved_state_of(const DemSystem& dem) {
  std::ostringstream out(std::ios::binary);
  dem.save_state(out);
  return std::move(out).str();
}

TEST(RollingResistance, TheRollingHistoryIsCarriedAndRestoredBitForBit) {
  const Container box = Container::square(0.06, 1.0, false);
  Rng sizes(4, 1);
  std::vector<double> radii(600);
  for (double& r : radii) r = sizes.uniform(0.002, 0.003);
  ParticleStore deposited;
  DropAndRoll deposition(deposited, box, radii, DepositionSettings{}, Rng(4, 2));
  deposition.deposit(radii, SphereMaterials::all_of(kDensity));
  DemSettings settings;
  settings.time_step = 1e-5;
  settings.skin = 5e-5;  // rebuilt during the run
  const ContactModel model = make_contact_model(material(RollingModel::SpringDashpot, 1e-3));

  ParticleStore whole = deposited;
  DemSystem uninterrupted(whole, box, model, settings);
  uninterrupted.run(400);
  ParticleStore half = deposited;
  DemSystem interrupted(half, box, model, settings);
  interrupted.run(200);
  const std::string state = saved_state_of(interrupted);
  ParticleStore resumed_store = half;
  DemSystem resumed(resumed_store, box, model, settings);
  resumed.restore_state(state);
  resumed.run(200);
  EXPECT_GE(resumed.rebuilds(), 2u);
  EXPECT_EQ(0, std::memcmp(whole.position.data(), resumed_store.position.data(), whole.size() * sizeof(Vec3)));
  EXPECT_EQ(0, std::memcmp(whole.angular_velocity.data(), resumed_store.angular_velocity.data(),
                           whole.size() * sizeof(Vec3)));

  ParticleStore a = deposited, b = deposited;
  const DemSystem with(a, box, model, settings);
  DemSystem without(b, box, make_contact_model(material(RollingModel::ConstantTorque)), settings);
  // 24 bytes more per list entry (and the array's length) than the constant-torque law's
  // state of the same bed.
  EXPECT_EQ(saved_state_of(with).size(),
            saved_state_of(without).size() + sizeof(std::uint64_t) + 3 * sizeof(double) * with.list_entries());
  // A constant-torque system refuses the spring-dashpot's state: it has bytes after its end.
  EXPECT_THROW(without.restore_state(state), InputError);
}

}  // namespace
}  // namespace aggpack
