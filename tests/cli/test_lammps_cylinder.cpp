// A cylindrical measure in aggpack and in LAMMPS (`lmp`): spheres bouncing and rolling on its
// curved wall step by step, the deck's wall as the bridge writes it (a region cylinder's side,
// fix wall/gran/region); and poured beds of both engines, as dense within the seeds' scatter.
#include <cmath>
#include <fstream>
#include <iostream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "aggpack/core/particle_store.hpp"
#include "aggpack/dynamics/contact_law_registry.hpp"
#include "aggpack/dynamics/dem_system.hpp"
#include "aggpack/io/lammps_data.hpp"
#include "run_cli.hpp"

namespace aggpack {
namespace {

namespace fs = std::filesystem;

constexpr double kDensity = 2650.0;
constexpr double kStep = 1e-5;
constexpr double kSkin = 0.001;

// Hertz-Mindlin with friction `mu` between spheres, none at the walls (a wall's friction
// parts the two codes at first touch even on flat walls: tests/cli/test_lammps_crowd.cpp),
// and no normal damping (restitution 1, see undamped()).
ContactParameters wall_material(double mu) {
  ContactParameters p;
  p.youngs_modulus = p.wall_youngs_modulus = 1e8;
  p.friction_particle = mu;
  p.friction_wall = 0.0;
  p.restitution = 1.0;
  return p;
}

// Three spheres on the floor of a 50 mm measure, thrown at its wall at three angles, spinning;
// the first two meet after their bounces (their friction then acts).
ParticleStore throws() {
  ParticleStore s;
  const double r[3] = {0.004, 0.005, 0.0035};
  const Vec3 at[3] = {{0.025, 0.012, 0.004002}, {0.027, 0.038, 0.005002}, {0.015, 0.035, 0.0035}};
  const Vec3 v[3] = {{0.0, -0.5, 0.0}, {0.0, 0.4, 0.0}, {-0.2, 0.1, 0.1}};
  const Vec3 w[3] = {{3.0, -5.0, 2.0}, {-4.0, 1.0, 6.0}, {2.0, 3.0, -1.0}};
  for (int i = 0; i < 3; ++i) {
    s.add(at[i], r[i], kDensity);
    s.velocity[i] = v[i];
    s.angular_velocity[i] = w[i];
  }
  return s;
}

struct State {
  Vec3 x, v, w;
};

std::vector<std::vector<State>> aggpack_states(const ContactParameters& p, const Container& measure, int steps) {
  ParticleStore s = throws();
  DemSettings settings;
  settings.time_step = kStep;
  settings.skin = kSkin;
  settings.threads = 1;
  DemSystem dem(s, measure, make_contact_model(p), settings);
  std::vector<std::vector<State>> out;
  for (int k = 0; k < steps; ++k) {
    dem.run(1);
    std::vector<State>& now = out.emplace_back();
    for (std::size_t i = 0; i < s.size(); ++i) now.push_back({s.position[i], s.velocity[i], s.angular_velocity[i]});
  }
  return out;
}

// The bridge's keywords without normal damping: aggpack's restitution 1 is no damping at all,
// where LAMMPS's tsuji polynomial leaves a little.
std::string undamped(std::string keywords) {
  std::istringstream in(keywords);
  std::vector<std::string> words{std::istream_iterator<std::string>(in), std::istream_iterator<std::string>()};
  words.at(2) = std::string("0");
  words.at(5) = std::string("velocity");
  return fmt::format("{}", fmt::join(words, " "));
}

std::vector<std::vector<State>> lammps_states(const ContactParameters& p, const Container& measure, int steps,
                                              const fs::path& dir) {
  fs::create_directories(dir);
  const ParticleStore s = throws();
  const double density[1] = {kDensity};
  std::ofstream(dir / "bed.data") << lammps_data(s, measure, density, measure.bounds.hi.z, {});
  const ContactLawEntry& law = contact_law("mindlin");
  std::string deck = fmt::format(
      "units si\natom_style sphere\nboundary f f fm\nnewton off\ncomm_modify vel yes\nread_data bed.data\n"
      "group mobile type 1\npair_style granular\npair_coeff * * {0}\n"
      "region measure cylinder z {2:.17g} {2:.17g} {2:.17g} 0 INF side in open 1 open 2 units box\n"
      "fix wall_side mobile wall/gran/region granular {1} region measure\n"
      "fix floor mobile wall/gran granular {1} zplane 0 NULL\n"
      "fix integrate mobile nve/sphere\nfix gravity mobile gravity 9.81 vector 0 0 -1\n"
      "neighbor {3:.17g} bin\nneigh_modify delay 0 every 1 check yes\ntimestep {4:.17g}\n"
      "dump states all custom 1 states.dump id x y z vx vy vz omegax omegay omegaz\n"
      "dump_modify states format float %.17g sort id\nrun {5}\n",
      undamped(law.lammps_keywords(p, false)), undamped(law.lammps_keywords(p, true)), measure.radius(), kSkin,
      kStep, steps);
  std::ofstream(dir / "throws.in") << deck;
  const auto result = testing::run_command("cd '" + dir.string() + "' && lmp -in throws.in -log log.lammps -screen none");
  EXPECT_EQ(result.exit_code, 0) << result.output;
  std::ifstream in(dir / "states.dump");
  std::vector<std::vector<State>> out;
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("ITEM: ATOMS", 0) != 0) continue;
    std::vector<State>& now = out.emplace_back(s.size());
    for (std::size_t k = 0; k < s.size() && std::getline(in, line); ++k) {
      std::istringstream row(line);
      std::size_t id;
      State st;
      row >> id >> st.x.x >> st.x.y >> st.x.z >> st.v.x >> st.v.y >> st.v.z >> st.w.x >> st.w.y >> st.w.z;
      now[id - 1] = st;
    }
  }
  if (!out.empty()) out.erase(out.begin());  // the dump at step 0
  return out;
}

// Each sphere hits the curved wall (its centre within r of it at some step) and comes back:
// the two codes' places and speeds step by step, the same wall law at the same effective
// radius (a concave cylinder's, 2 R r / (2 R - r)).
TEST(LammpsCylinder, SpheresBouncingOnTheCurvedWallMoveAsInLammpsStepByStep) {
  testing::ScratchDir scratch("aggpack_lammps_cylinder_");
  const Container measure = Container::cylinder(0.05, 0.05);
  constexpr int kSteps = 6000;  // 0.06 s: each sphere reaches the wall and comes back
  for (const double mu : {0.0, 0.5}) {
    const ContactParameters p = wall_material(mu);
    const auto own = aggpack_states(p, measure, kSteps);
    const auto theirs = lammps_states(p, measure, kSteps, scratch.path() / fmt::format("mu{}", mu));
    ASSERT_EQ(theirs.size(), own.size());
    const ParticleStore start = throws();
    for (std::size_t i = 0; i < start.size(); ++i) {
      double nearest = 1.0;
      for (const auto& now : own) {
        Vec3 towards;
        nearest = std::min(nearest, measure.plane_distance(Container::kCylinderWall, now[i].x, towards));
      }
      EXPECT_LT(nearest, start.radius[i]) << "sphere " << i << " never reached the wall";
    }
    double closest = 1.0;  // of the first two spheres' surfaces
    for (const auto& now : own) closest = std::min(closest, norm(now[0].x - now[1].x) - 0.009);
    EXPECT_LT(closest, 0.0) << "the first two spheres never met";
    double place = 0.0, speed = 0.0;
    for (std::size_t k = 0; k < own.size(); ++k)
      for (std::size_t i = 0; i < own[k].size(); ++i) {
        place = std::max(place, std::sqrt(norm2(own[k][i].x - theirs[k][i].x)));
        speed = std::max(speed, std::sqrt(norm2(own[k][i].v - theirs[k][i].v)));
      }
    EXPECT_LT(place, 1e-9) << "friction " << mu;
    EXPECT_LT(speed, 1e-6) << "friction " << mu;
    std::cout << "friction " << mu << ": places within " << place << " m, speeds within " << speed << " m/s\n";
  }
}

// 1200 spheres of 6 mm poured into an 80 mm measure, struck off at 40 mm, by both engines over
// three seeds each: the two means of the measure's packing density within the seeds' scatter.
// (Measured, 80 s on two cores: aggpack 0.5735, 0.5658, 0.5645, mean 0.5679; LAMMPS 0.5697,
// 0.5679, 0.5691, mean 0.5689; the seeds' sd 0.0035.)
TEST(LammpsCylinderLong, APourIntoAMeasureIsAsDenseInLammps) {
  testing::ScratchDir scratch("aggpack_lammps_cylinder_pour_");
  const fs::path scenario = scratch.path() / "measure.toml";
  std::ofstream(scenario)
      << "[container]\nshape = \"cylinder\"\ndiameter = 0.08\nheight = 0.3\nrim = 0.04\n[particles]\n"
         "diameter = 0.006\ncount = 1200\n[material]\nyoungs_modulus = 1e8\nwall_youngs_modulus = 1e8\n"
         "friction_particle = 0.3\nfriction_wall = 0.3\n[pour]\nbatches = 2\n[dynamics]\nmax_time = 1.0\n"
         "[analysis]\nbox_sides = [0.03]\n";
  std::vector<double> own, theirs;
  for (const int seed : {1, 2, 3})
    for (const bool lammps : {false, true}) {
      const fs::path out = scratch.path() / fmt::format("{}_{}", lammps ? "lammps" : "aggpack", seed);
      const auto r = testing::run_cli(fmt::format("run {} --quiet --threads 2 --seed {} --out {}{}", scenario.string(),
                                                  seed, out.string(),
                                                  lammps ? " --set dynamics.engine='\"lammps\"'" : ""));
      ASSERT_EQ(r.exit_code, 0) << r.output;
      const auto summary = nlohmann::json::parse(std::ifstream(out / "summary.json"));
      EXPECT_EQ(summary.at("particle_count"), 1200);
      (lammps ? theirs : own).push_back(summary.at("measure").at("packing_density").get<double>());
    }
  const auto mean = [](const std::vector<double>& v) { return (v[0] + v[1] + v[2]) / 3.0; };
  double scatter = 0.0;  // the seeds' standard deviation, both engines pooled
  for (const auto* v : {&own, &theirs})
    for (const double d : *v) scatter += (d - mean(*v)) * (d - mean(*v)) / 4.0;
  scatter = std::sqrt(scatter);
  std::cout << fmt::format("aggpack {:.4f} ({}), LAMMPS {:.4f} ({}), seeds' sd {:.4f}\n", mean(own),
                           fmt::join(own, ", "), mean(theirs), fmt::join(theirs, ", "), scatter);
  EXPECT_GT(mean(own), 0.5);
  // Two means of three: their difference's sd is sqrt(2/3) of one bed's; within three of those
  // (and no tighter than 0.005, should three seeds happen to agree closely).
  EXPECT_NEAR(mean(theirs), mean(own), std::max(3.0 * std::sqrt(2.0 / 3.0) * scatter, 0.005));
}

}  // namespace
}  // namespace aggpack
