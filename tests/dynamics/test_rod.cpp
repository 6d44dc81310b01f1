// The rod (a kinematic capsule in the DEM), rodding, the lift-and-drop container motion and
// jigging (README, "Rodding" and "Jigging").
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "aggpack/core/rng.hpp"
#include "aggpack/deposition/drop_and_roll.hpp"
#include "aggpack/dynamics/dem_system.hpp"
#include "aggpack/dynamics/jig.hpp"
#include "aggpack/dynamics/rod.hpp"
#include "aggpack/dynamics/settle.hpp"

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

RodTool rod_along(double radius, std::vector<RodWaypoint> path) {
  RodTool tool;
  tool.radius = radius;
  tool.length = 0.5;
  tool.path = std::move(path);
  return tool;
}

// The capsule's distance and normal against the nearest of many points of its surface.
TEST(RodTool, DistanceAndNormalMatchTheNearestPointOfItsSurface) {
  RodTool rod = rod_along(0.008, {{0.0, {0.0, 0.0, 0.0}}});
  rod.length = 0.04;
  const Vec3 tip{0.01, -0.02, 0.03};
  std::vector<Vec3> surface;
  const int around = 360, along = 200, cap = 90;
  for (int a = 0; a < around; ++a) {
    const double phi = 2.0 * std::numbers::pi * a / around;
    for (int k = 0; k <= along; ++k)  // the shaft
      surface.push_back(tip + Vec3{rod.radius * std::cos(phi), rod.radius * std::sin(phi), rod.length * k / along});
    for (int k = 1; k <= cap; ++k) {  // the hemispheres, below the tip and above the top
      const double theta = 0.5 * std::numbers::pi * k / cap, ring = rod.radius * std::cos(theta);
      const Vec3 around_axis{ring * std::cos(phi), ring * std::sin(phi), 0.0};
      surface.push_back(tip + around_axis + Vec3{0.0, 0.0, -rod.radius * std::sin(theta)});
      surface.push_back(tip + around_axis + Vec3{0.0, 0.0, rod.length + rod.radius * std::sin(theta)});
    }
  }
  // The largest gap between neighbouring samples, around the axis or along it.
  const double spacing = std::max(2.0 * std::numbers::pi * rod.radius / around, rod.length / along);
  Rng rng(5, 1);
  for (int n = 0; n < 60; ++n) {
    const Vec3 x = tip + Vec3{rng.uniform(-0.03, 0.03), rng.uniform(-0.03, 0.03), rng.uniform(-0.02, 0.06)};
    double nearest = std::numeric_limits<double>::infinity();
    for (const Vec3& s : surface) nearest = std::min(nearest, norm(s - x));
    Vec3 towards;
    const double d = rod.distance(tip, x, towards);
    if (d > 0.0) EXPECT_NEAR(d, nearest, spacing) << n;
    else EXPECT_NEAR(-d, nearest, spacing) << n;  // inside: the depth
    EXPECT_NEAR(norm(towards), 1.0, 1e-12);
    // The point d along the normal lies on the surface, and no surface point is nearer.
    const Vec3 foot = x + towards * d;
    Vec3 unused;
    EXPECT_NEAR(rod.distance(tip, foot, unused), 0.0, 1e-12) << n;
  }
}

TEST(RodTool, FollowsItsPathPiecewiseLinearly) {
  const RodTool rod = rod_along(0.008, {{1.0, {0, 0, 1.0}}, {2.0, {0, 0, 0.0}}, {4.0, {1.0, 0, 0.0}}});
  EXPECT_EQ(rod.tip_at(0.5), (Vec3{0, 0, 1.0}));
  EXPECT_EQ(rod.velocity_at(0.5), Vec3{});
  EXPECT_NEAR(rod.tip_at(1.25).z, 0.75, 1e-15);
  EXPECT_EQ(rod.velocity_at(1.25), (Vec3{0, 0, -1.0}));
  EXPECT_NEAR(rod.tip_at(3.0).x, 0.5, 1e-15);
  EXPECT_EQ(rod.velocity_at(3.0), (Vec3{0.5, 0, 0}));
  EXPECT_EQ(rod.tip_at(9.0), (Vec3{1.0, 0, 0.0}));
  EXPECT_EQ(rod.velocity_at(9.0), Vec3{});
}

// A sphere on the floor, struck from above by the descending tip (no damping: e = 1): at every
// step the rod's force is Hertz's for the overlap of a sphere with a sphere of the rod's radius,
// along the line of centres (vertical), and it is what the sphere feels from the rod (its net
// force less its weight and the floor's Hertz force).
TEST(DemRod, TheTipPushesASphereOnTheFloorWithTheContactLawsForceAndFeelsItsOpposite) {
  const double r = 0.005, rod_r = 0.008, speed = 0.05;
  ParticleStore store;
  store.add({0.05, 0.05, r}, r, kDensity);
  DemSettings settings;
  settings.time_step = 1e-6;
  DemSystem dem(store, Container::square(0.1, 0.1, false), make_contact_model(material(1.0, 0.5)), settings);
  dem.run(20000);  // at rest on the floor
  const double t0 = dem.time(), top = store.position[0].z + r + rod_r + 1e-4;
  const double bottom = top - 3e-4;  // 0.2 mm into the sphere
  dem.set_tool(rod_along(rod_r, {{t0, {0.05, 0.05, top}}, {t0 + (top - bottom) / speed, {0.05, 0.05, bottom}}}));
  const double m = store.mass[0], r_star = r * rod_r / (r + rod_r);
  int touching = 0;
  for (int s = 0; s < 8000; ++s) {
    dem.run(1);
    const Vec3 tip = dem.tool()->tip_at(dem.time());
    const double overlap = r + rod_r - norm(tip - store.position[0]);
    const Vec3 on_rod = dem.tool_force();
    if (overlap <= 0.0) {
      EXPECT_EQ(on_rod, Vec3{});
      continue;
    }
    ++touching;
    const double law = hertz_normal_force(kEStar, r_star, overlap);
    EXPECT_NEAR(on_rod.z, law, 1e-9 * law + 1e-12) << s;
    EXPECT_NEAR(std::hypot(on_rod.x, on_rod.y), 0.0, 1e-12 * law) << s;
    const double floor = hertz_normal_force(kEStar, r, r - store.position[0].z);
    const Vec3 from_rod = dem.force(0) - Vec3{0.0, 0.0, floor - m * 9.81};
    EXPECT_NEAR(from_rod.z, -on_rod.z, 1e-9 * law) << s;
  }
  EXPECT_GT(touching, 1000);
  EXPECT_GT(dem.tool_peak_force(), hertz_normal_force(kEStar, r_star, 1e-4));
  EXPECT_LT(store.position[0].z, r);  // pressed into the floor, not through it
}

// Newton's third law exactly: a free sphere (no gravity) struck off-centre; its force is
// minus the rod's, whatever the friction and damping.
TEST(DemRod, TheRodsForceIsMinusTheSpheres) {
  const double r = 0.005, rod_r = 0.008;
  ParticleStore store;
  store.add({0.05, 0.05, 0.05}, r, kDensity);
  DemSettings settings;
  settings.gravity = {};
  settings.time_step = 1e-6;
  DemSystem dem(store, Container::square(0.1, 0.1, false), make_contact_model(material(0.5, 0.5)), settings);
  const Vec3 start{0.052, 0.051, 0.07};
  dem.set_tool(rod_along(rod_r, {{0.0, start}, {0.02, start + Vec3{0.0, 0.0, -0.02}}}));
  int touching = 0;
  for (int s = 0; s < 20000; ++s) {
    dem.run(1);
    if (dem.tool_force() == Vec3{}) continue;
    ++touching;
    EXPECT_EQ(dem.force(0), -dem.tool_force()) << s;
  }
  EXPECT_GT(touching, 100);
  EXPECT_LT(norm(store.velocity[0]), 2.0);
}

// A rod through empty space touches nothing; a sphere beside its path is pushed away from
// its axis, horizontally.
TEST(DemRod, ARodThroughFreeSpaceTouchesNothingAndPushesASphereBesideItsPathAway) {
  const double r = 0.005, rod_r = 0.008;
  ParticleStore store;
  store.add({0.02, 0.02, r}, r, kDensity);            // far from the path
  store.add({0.05 + rod_r + 0.6 * r, 0.05, 0.02}, r, kDensity);  // beside it, reached by the shaft
  DemSettings settings;
  settings.gravity = {};
  settings.time_step = 2e-6;
  DemSystem dem(store, Container::square(0.1, 0.1, false), make_contact_model(material(0.5, 0.0)), settings);
  const std::size_t rebuilds = dem.rebuilds();
  dem.set_tool(rod_along(rod_r, {{0.0, {0.08, 0.08, 0.09}}, {0.08, {0.08, 0.08, 0.01}}}));
  dem.run(40000);
  EXPECT_EQ(dem.tool_peak_force(), 0.0);
  EXPECT_EQ(store.velocity[0], Vec3{});
  EXPECT_EQ(store.velocity[1], Vec3{});
  EXPECT_GT(dem.rebuilds(), rebuilds + 50);  // the moving rod rebuilt the list as it went

  dem.set_tool(rod_along(rod_r, {{dem.time(), {0.05, 0.05, 0.06}}, {dem.time() + 0.05, {0.05, 0.05, 0.01}}}));
  dem.run(25000);
  EXPECT_GT(dem.tool_peak_force(), 0.0);
  const Vec3 v = store.velocity[1];
  EXPECT_GT(v.x, 0.1);                      // away from the axis (along +x, where it sat)
  EXPECT_LT(std::abs(v.y), 1e-9 * v.x);     // and nowhere else around
  // Out of the rod's way: its centre now further from the axis than the two radii.
  EXPECT_GT(store.position[1].x - 0.05, rod_r + r);
  EXPECT_EQ(store.velocity[0], Vec3{});
}

// The lift-and-drop profile against its closed form: lifted by h at a < g in 2 sqrt(h / a),
// at rest at the top, then a free fall that meets the base at sqrt(2 g h) and stops dead.
TEST(ContainerMotion, LiftAndDropFollowsItsClosedForm) {
  const double h = 0.05, a = 4.9, g = 9.81, t0 = 0.3;
  const ContainerMotion m = ContainerMotion::lift_and_drop(t0, h, a, g);
  const double lift = 2.0 * std::sqrt(h / a), fall = std::sqrt(2.0 * h / g);
  EXPECT_NEAR(m.end(), t0 + lift + fall, 1e-15);
  EXPECT_EQ(m.offset(t0 - 0.1), 0.0);
  EXPECT_NEAR(m.offset(t0 + 0.25 * lift), 0.5 * a * std::pow(0.25 * lift, 2), 1e-15);
  EXPECT_NEAR(m.offset(t0 + 0.5 * lift), 0.5 * h, 1e-15);
  EXPECT_NEAR(m.velocity(t0 + 0.5 * lift), a * 0.5 * lift, 1e-12);  // the peak speed of the lift
  EXPECT_NEAR(m.offset(t0 + lift), h, 1e-15);
  EXPECT_NEAR(m.velocity(t0 + lift), 0.0, 1e-12);
  const double falling = 0.6 * fall;
  EXPECT_NEAR(m.offset(t0 + lift + falling), h - 0.5 * g * falling * falling, 1e-15);
  EXPECT_NEAR(m.velocity(t0 + lift + falling), -g * falling, 1e-12);
  EXPECT_NEAR(m.velocity(m.end() - 1e-12), -std::sqrt(2.0 * g * h), 1e-9);  // the impact speed
  EXPECT_EQ(m.offset(m.end() + 1e-9), 0.0);
  EXPECT_EQ(m.velocity(m.end() + 1e-9), 0.0);
  // The tap's sine is the default profile, unchanged.
  const ContainerMotion tap{0.0, 1e-3, 100.0, 0.5};
  EXPECT_EQ(tap.offset(0.01), 1e-3 * std::sin(1.0));
}

// In the DEM: a sphere on the floor rides the lift (a < g) and falls with the container; it
// meets the stopped floor at about sqrt(2 g h).
TEST(ContainerMotion, ASphereRidesTheLiftAndHitsTheBaseAtTheFreeFallSpeed) {
  const double r = 0.005, h = 0.01;
  ParticleStore store;
  store.add({0.05, 0.05, r}, r, kDensity);
  DemSettings settings;
  settings.time_step = 1e-6;
  DemSystem dem(store, Container::square(0.1, 0.1, false), make_contact_model(material(0.5, 0.5)), settings);
  dem.run(20000);
  const double rest = store.position[0].z;
  const ContainerMotion m = ContainerMotion::lift_and_drop(dem.time(), h, 4.9, 9.81);
  dem.set_container_motion(m);
  double largest_gap = 0.0, fastest_down = 0.0;
  while (dem.time() < m.end() + 0.01) {
    dem.run(10);
    if (dem.time() < m.start + m.lift_time())
      largest_gap = std::max(largest_gap, store.position[0].z - dem.container_offset() - rest);
    fastest_down = std::max(fastest_down, -store.velocity[0].z);
  }
  EXPECT_LT(largest_gap, 1e-5);  // rode the lift
  EXPECT_NEAR(fastest_down, std::sqrt(2.0 * 9.81 * h), 0.02 * std::sqrt(2.0 * 9.81 * h));
  EXPECT_EQ(dem.container_offset(), 0.0);
  EXPECT_LT(store.position[0].z, 2.0 * r);  // back on the floor
}

// ---- A small bed rodded and jigged ----------------------------------------------------

ParticleStore deposited_bed(std::size_t count, double r_lo, double r_hi, const Container& box) {
  Rng sizes(11, 1);
  std::vector<double> radii(count);
  for (double& r : radii) r = sizes.uniform(r_lo, r_hi);
  ParticleStore bed;
  DropAndRoll deposition(bed, box, radii, DepositionSettings{}, Rng(11, 2));
  deposition.deposit(radii, SphereMaterials::all_of(kDensity));
  return bed;
}

double mean_height(const ParticleStore& p) {
  double sum = 0.0;
  for (const Vec3& x : p.position) sum += x.z;
  return sum / static_cast<double>(p.size());
}

TapHooks quiet_hooks() {
  TapHooks hooks;
  hooks.on_sample = [](const SettleSample&, std::string_view) {};
  hooks.at_safe_point = [](std::string_view) {};
  hooks.density = [](const ParticleStore& p) { return 1.0 / mean_height(p); };  // rises as the bed sinks
  return hooks;
}

bool all_inside(const ParticleStore& p, const Container& box) {
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec3& x = p.position[i];
    if (!(x.z > box.bounds.lo.z && x.x > box.bounds.lo.x && x.x < box.bounds.hi.x && x.y > box.bounds.lo.y &&
          x.y < box.bounds.hi.y))
      return false;
  }
  return true;
}

TEST(Rodding, StrokePositionsSpreadOverTheSectionInsideItsMargin) {
  const Container box = Container::square(0.1, 0.1, false);
  const std::vector<Vec3> points = rod_stroke_positions(box, 25, 0.013);
  ASSERT_EQ(points.size(), 25u);
  double nearest_pair = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < points.size(); ++i) {
    EXPECT_GE(points[i].x, 0.013 - 1e-12);
    EXPECT_LE(points[i].x, 0.087 + 1e-12);
    EXPECT_GE(points[i].y, 0.013 - 1e-12);
    EXPECT_LE(points[i].y, 0.087 + 1e-12);
    for (std::size_t j = 0; j < i; ++j) nearest_pair = std::min(nearest_pair, norm(points[i] - points[j]));
  }
  // Evenly: no two closer than half the spacing of a 5 x 5 grid over the inset square.
  EXPECT_GT(nearest_pair, 0.5 * 0.074 / 5.0);
  EXPECT_EQ(points, rod_stroke_positions(box, 25, 0.013));  // deterministic
}

struct BedRun {
  ParticleStore bed;
  RoddingReport rodded;
  JigReport jigged;
};

// Rods then jigs a bed on `threads` threads; stops at the `stop_at`-th safe point of the
// rodding (0: never) and resumes from the state saved there.
BedRun rod_and_jig(const ParticleStore& start, const Container& box, int threads, std::size_t stop_at,
                   std::size_t drops, std::size_t strokes = 3, double max_force = 1e9) {
  DemSettings settings;
  settings.time_step = 2e-5;
  settings.threads = threads;
  settings.adapt_threads = false;
  const ContactModel model = make_contact_model(material(0.5, 0.5));
  QuietCriterion quiet;
  BedRun out{start, {}, {}};
  RoddingSettings rodding;
  rodding.strokes = strokes;
  rodding.max_force = max_force;  // by default, driven to the target whatever the force
  rodding.speed = 2.0;
  rodding.depth = RodDepth::Floor;
  rodding.rest_time = 0.02;
  rodding.rest_until_quiet = false;
  DemSystem dem(out.bed, box, model, settings);
  dem.run(1000);  // the deposited bed settles under its weight
  const double before = 1.0 / mean_height(out.bed);
  RodLoop loop = begin_rodding(dem, box, rodding, {box.bounds.lo.z, std::nullopt}, before);
  TapHooks hooks = quiet_hooks();
  std::size_t safe_points = 0;
  std::string saved_state;
  RodLoop saved_loop;
  ParticleStore saved_store;
  struct Stop {};
  if (stop_at > 0)
    hooks.at_safe_point = [&](std::string_view) {
      if (++safe_points < stop_at) return;
      std::ostringstream state;
      dem.save_state(state);
      saved_state = state.str();
      saved_loop = loop;
      saved_store = out.bed;
      throw Stop{};
    };
  try {
    rod(dem, out.bed, rodding, quiet, loop, hooks);
  } catch (const Stop&) {
    out.bed = saved_store;
    DemSystem resumed(out.bed, box, model, settings);
    resumed.restore_state(saved_state);
    EXPECT_TRUE(fits(saved_loop, rodding, resumed));
    loop = saved_loop;
    rod(resumed, out.bed, rodding, quiet, loop, quiet_hooks());
    out.rodded = loop.report;
    return out;
  }
  out.rodded = loop.report;
  JiggingSettings jigging;
  jigging.drops = drops;
  jigging.height = 0.01;
  jigging.rest_time = 0.03;
  JigLoop jig_loop = begin_jigging(dem, jigging, 1.0 / mean_height(out.bed));
  jig(dem, out.bed, jigging, quiet, jig_loop, false, quiet_hooks());
  out.jigged = jig_loop.report;
  return out;
}

TEST(Rodding, RodsASmallBedToItsFloorAndJiggingCompactsIt) {
  const Container box = Container::square(0.07, 0.2, false);
  const ParticleStore start = deposited_bed(250, 0.003, 0.004, box);
  const BedRun run = rod_and_jig(start, box, 1, 0, 3);
  const RoddingReport& r = run.rodded;
  ASSERT_EQ(r.stroke_records.size(), 3u);
  EXPECT_EQ(r.depth_mode, RodDepth::Floor);
  for (const RodStroke& s : r.stroke_records) {
    EXPECT_DOUBLE_EQ(s.tip_lowest, 0.005);        // the floor less the clearance
    EXPECT_GT(s.depth, 0.02);                     // through the bed's depth
    EXPECT_GT(s.peak_force, 0.0);                 // it met the bed
    EXPECT_LT(s.peak_force, 1e4);                 // and no blow-up
  }
  EXPECT_TRUE(all_inside(run.bed, box));
  EXPECT_GT(r.steps, 0u);
  // A hand's push of 2 N stops every stroke short of the floor, where the bed pushed back so.
  const BedRun gentle = rod_and_jig(start, box, 1, 0, 0, 3, 2.0);
  for (const RodStroke& s : gentle.rodded.stroke_records) {
    EXPECT_TRUE(s.stopped_by_force);
    EXPECT_GT(s.tip_lowest, 0.005 + 1e-3);
    EXPECT_GT(s.peak_force, 2.0);
  }
  // Jigging: the bed sinks (its mean height falls) with the drops.
  const JigReport& j = run.jigged;
  ASSERT_EQ(j.samples.size(), 3u);
  EXPECT_NEAR(j.impact_speed, std::sqrt(2.0 * 9.81 * 0.01), 1e-12);
  EXPECT_GT(j.samples.back().density, j.density_before);
  EXPECT_TRUE(all_inside(run.bed, box));
}

TEST(Rodding, AResumedRoddingGivesTheSameBytes) {
  const Container box = Container::square(0.07, 0.2, false);
  const ParticleStore start = deposited_bed(250, 0.003, 0.004, box);
  const BedRun whole = rod_and_jig(start, box, 1, 0, 0);
  for (const std::size_t stop_at : {2u, 5u, 9u}) {
    const BedRun resumed = rod_and_jig(start, box, 1, stop_at, 0);
    ASSERT_EQ(whole.bed.size(), resumed.bed.size());
    EXPECT_EQ(0, std::memcmp(whole.bed.position.data(), resumed.bed.position.data(), whole.bed.size() * sizeof(Vec3)))
        << stop_at;
    ASSERT_EQ(resumed.rodded.stroke_records.size(), 3u);
    for (std::size_t k = 0; k < 3; ++k)
      EXPECT_EQ(whole.rodded.stroke_records[k].peak_force, resumed.rodded.stroke_records[k].peak_force) << stop_at;
  }
}

// Over kThreadedFrom spheres the DEM's loops run on the threads: the same bytes on 1 and 2.
TEST(Rodding, OneAndTwoThreadsGiveTheSameBytes) {
  const Container box = Container::square(0.06, 0.2, false);
  const ParticleStore start = deposited_bed(1100, 0.002, 0.0025, box);
  const BedRun one = rod_and_jig(start, box, 1, 0, 0, 1);
  const BedRun two = rod_and_jig(start, box, 2, 0, 0, 1);
  ASSERT_EQ(one.rodded.stroke_records.size(), 1u);
  ASSERT_EQ(two.rodded.stroke_records.size(), 1u);
  EXPECT_GT(one.rodded.stroke_records[0].peak_force, 0.0);
  EXPECT_EQ(0, std::memcmp(one.bed.position.data(), two.bed.position.data(), one.bed.size() * sizeof(Vec3)));
  EXPECT_EQ(0, std::memcmp(one.bed.velocity.data(), two.bed.velocity.data(), one.bed.size() * sizeof(Vec3)));
  EXPECT_EQ(one.rodded.stroke_records[0].peak_force, two.rodded.stroke_records[0].peak_force);
}

}  // namespace
}  // namespace aggpack

namespace aggpack {
namespace {

// In a cylinder (the measure of ASTM C29): the strokes spread over the disc less the margin,
// and a bed in it is rodded to its floor without a sphere leaving it.
TEST(Rodding, InACylinderTheStrokesSpreadOverTheDiscAndReachTheFloor) {
  const Container measure = Container::cylinder(0.08, 0.2);
  const double margin = 0.013;
  const std::vector<Vec3> points = rod_stroke_positions(measure, 25, margin);
  ASSERT_EQ(points.size(), 25u);
  double farthest = 0.0;
  for (const Vec3& p : points) {
    const double from_axis = std::hypot(p.x - 0.04, p.y - 0.04);
    EXPECT_LE(from_axis, 0.04 - margin + 1e-12);
    farthest = std::max(farthest, from_axis);
  }
  EXPECT_GT(farthest, 0.8 * (0.04 - margin));  // out to the rim, not bunched at the axis

  // Drop and roll needs a box: the bed is made in a square inscribed in the disc, moved into it.
  ParticleStore start = deposited_bed(200, 0.003, 0.004, Container::square(0.05, 0.2, false));
  for (Vec3& x : start.position) x = x + Vec3{0.015, 0.015, 0.0};
  const BedRun run = rod_and_jig(start, measure, 1, 0, 1);
  ASSERT_EQ(run.rodded.stroke_records.size(), 3u);
  for (const RodStroke& s : run.rodded.stroke_records) {
    EXPECT_DOUBLE_EQ(s.tip_lowest, 0.005);
    EXPECT_GT(s.peak_force, 0.0);
  }
  for (std::size_t i = 0; i < run.bed.size(); ++i) {
    const Vec3& x = run.bed.position[i];
    EXPECT_LT(std::hypot(x.x - 0.04, x.y - 0.04), 0.04) << i;
    EXPECT_GT(x.z, 0.0) << i;
  }
  EXPECT_GT(run.jigged.samples.back().density, run.jigged.density_before);
}

}  // namespace
}  // namespace aggpack
