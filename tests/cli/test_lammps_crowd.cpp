// The spring-dashpot rolling law in a crowd of contacts, step by step in aggpack and in LAMMPS
// (`lmp`, Debian's lammps): a sphere in a pocket of three of unequal sizes on the floor, all
// spinning, so that every contact carries a rolling history while its normal turns and its
// normal force changes. Both codes start from the same state with the same law and the
// same time step; a few hundred steps are far too few for chaos to part them.
#include <cmath>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <gtest/gtest.h>

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

// The pour's law (tests/cli/test_lammps_bridge.cpp, kRollingPour) with friction `mu` between
// spheres and none at the walls, and no normal damping (restitution 1, see undamped()).
ContactParameters crowd_material(double rolling_friction, double mu) {
  ContactParameters p;
  p.youngs_modulus = p.wall_youngs_modulus = 1e8;
  p.friction_particle = mu;
  p.friction_wall = 0.0;
  p.restitution = 1.0;
  p.rolling_friction = rolling_friction;
  p.rolling_model = RollingModel::SpringDashpot;
  p.rolling_stiffness = 1000.0;
  p.rolling_damping = 0.1;
  return p;
}

// Three spheres of 4, 5 and 6.5 mm on the floor touching each other, a fourth of 5 mm resting in
// their pocket, each overlapping its neighbours a little, each moving and spinning its own way.
ParticleStore crowd() {
  ParticleStore s;
  const double r[4] = {0.004, 0.005, 0.0065, 0.005};
  const Vec3 at[4] = {{0.02, 0.02, 0.004002},
                      {0.0289472906, 0.02, 0.005002},
                      {0.02302035619, 0.0297437394, 0.006502},
                      {0.0225012713, 0.02003676883, 0.01264840335}};
  const Vec3 v[4] = {{0.01, 0.005, 0.0}, {-0.01, 0.004, 0.0}, {0.0, -0.01, 0.0}, {0.005, -0.003, -0.05}};
  const Vec3 w[4] = {{3.0, -5.0, 2.0}, {-4.0, 1.0, 6.0}, {2.0, 3.0, -1.0}, {-6.0, 8.0, 4.0}};
  for (int i = 0; i < 4; ++i) {
    s.add(at[i], r[i], kDensity);
    s.velocity[i] = v[i];
    s.angular_velocity[i] = w[i];
  }
  return s;
}

struct State {
  Vec3 x, v, w;
};

// aggpack's states after each of `steps` steps.
std::vector<std::vector<State>> aggpack_states(const ContactParameters& p, const Container& box, int steps) {
  ParticleStore s = crowd();
  DemSettings settings;
  settings.time_step = kStep;
  settings.skin = kSkin;
  settings.threads = 1;
  DemSystem dem(s, box, make_contact_model(p), settings);
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
  words.at(2) = std::string("0");  // not = "0": GCC 12 warns falsely (-Wrestrict, PR 105329)
  words.at(5) = std::string("velocity");
  return fmt::format("{}", fmt::join(words, " "));
}

// LAMMPS's states after each of `steps` steps, the deck written as the bridge writes its own.
std::vector<std::vector<State>> lammps_states(const ContactParameters& p, const Container& box, int steps,
                                              const fs::path& dir) {
  fs::create_directories(dir);
  const ParticleStore s = crowd();
  const double density[1] = {kDensity};
  std::ofstream(dir / "bed.data") << lammps_data(s, box, density, box.bounds.hi.z, {});
  const ContactLawEntry& law = contact_law("mindlin");
  std::string deck = fmt::format(
      "units si\natom_style sphere\nboundary f f fm\nnewton off\ncomm_modify vel yes\nread_data bed.data\n"
      "group mobile type 1\npair_style granular\npair_coeff * * {0}\n"
      "fix wall_x mobile wall/gran granular {1} xplane 0 {2:.17g}\n"
      "fix wall_y mobile wall/gran granular {1} yplane 0 {2:.17g}\n"
      "fix floor mobile wall/gran granular {1} zplane 0 NULL\n"
      "fix integrate mobile nve/sphere\nfix gravity mobile gravity 9.81 vector 0 0 -1\n"
      "neighbor {3:.17g} bin\nneigh_modify delay 0 every 1 check yes\ntimestep {4:.17g}\n"
      "dump states all custom 1 states.dump id x y z vx vy vz omegax omegay omegaz\n"
      "dump_modify states format float %.17g sort id\nrun {5}\n",
      undamped(law.lammps_keywords(p, false)), undamped(law.lammps_keywords(p, true)), box.bounds.hi.x, kSkin, kStep, steps);
  std::ofstream(dir / "crowd.in") << deck;
  const auto result = testing::run_command("cd '" + dir.string() + "' && lmp -in crowd.in -log log.lammps -screen none");
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

// The largest difference of spin (rad/s) and of place (m) between the two codes over the steps.
struct Apart {
  double spin = 0.0, place = 0.0;
};
Apart apart(const std::vector<std::vector<State>>& a, const std::vector<std::vector<State>>& b) {
  Apart most;
  for (std::size_t k = 0; k < a.size(); ++k)
    for (std::size_t i = 0; i < a[k].size(); ++i) {
      most.spin = std::max(most.spin, std::sqrt(norm2(a[k][i].w - b[k][i].w)));
      most.place = std::max(most.place, std::sqrt(norm2(a[k][i].x - b[k][i].x)));
    }
  return most;
}

// Issue 55: LAMMPS's poured beds were denser than aggpack's with the spring-dashpot rolling law
// (+0.0066 over forty seeds, +0.0018 without it). Step by step in this crowd the rolling law
// itself is the same in both codes to the last digits (frictionless spheres: spins within
// 1e-8 rad/s over 3000 steps, the contacts rolling at or below their caps, normals turning).
// What differed was the lever arm of the tangential force between spheres: LAMMPS's pair
// granular applies it at the contact point, R - d/2 from each centre (dist_to_contact), aggpack
// applied it at R. With friction the spins parted from the first contact on, by 0.07 rad/s over
// these steps, and by 3.2 rad/s with rolling resistance; with the arm R - d/2 they agree to
// the last bits and their growth. (The walls take no friction here: fix wall/gran's arm is R,
// as aggpack's, but a wall's friction parts the two codes at first touch by something else,
// not found yet: docs/validation.md.)
TEST(LammpsCrowd, ASpinningCrowdWithRollingResistanceMovesAsInLammpsStepByStep) {
  testing::ScratchDir scratch("aggpack_lammps_crowd_");
  const Container box = Container::square(0.05, 0.05, false);
  constexpr int kSteps = 3000;  // 0.03 s: the top sphere lands, bounces and rolls in the pocket
  for (const double mu : {0.0, 0.5})
    for (const double mu_r : {0.0, 0.1}) {
      const ContactParameters p = crowd_material(mu_r, mu);
      const auto own = aggpack_states(p, box, kSteps);
      const auto theirs = lammps_states(p, box, kSteps, scratch.path() / fmt::format("mu{}_mur{}", mu, mu_r));
      ASSERT_EQ(theirs.size(), own.size());
      // A torque acts (so a law left out would show): the top sphere's spin changes by rad/s.
      if (mu > 0.0 || mu_r > 0.0) {
        EXPECT_GT(std::sqrt(norm2(own.back()[3].w - crowd().angular_velocity[3])), 1.0);
      }
      const Apart most = apart(own, theirs);
      // Measured: 1e-8 rad/s and 1e-12 m at most; with friction and rolling resistance 1.5e-5
      // rad/s and 4e-11 m (the last bits, grown where contacts stick or slip).
      EXPECT_LT(most.spin, 1e-4) << "friction " << mu << ", rolling friction " << mu_r;
      EXPECT_LT(most.place, 1e-9) << "friction " << mu << ", rolling friction " << mu_r;
      std::cout << "friction " << mu << ", rolling friction " << mu_r << ": spins within " << most.spin
                << " rad/s, places within " << most.place << " m\n";
    }
}

}  // namespace
}  // namespace aggpack
