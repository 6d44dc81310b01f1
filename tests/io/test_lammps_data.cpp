#include "aggpack/io/lammps_data.hpp"

#include <gtest/gtest.h>

#include <sstream>
#include <vector>

#include "aggpack/core/error.hpp"
#include <stdexcept>

namespace aggpack {
namespace {

// Read back as LAMMPS's read_data would: the counts, the box and every atom, bit for bit.
TEST(LammpsData, RoundTripsTheBedExactly) {
  ParticleStore bed;
  bed.add({0.1, 1.0 / 3.0, 0.0127}, 0.0127, 1.0);
  bed.add({2.0 / 7.0, 0.2, 0.05}, 0.00635, 1.0);
  const Container container{{{0, 0, 0}, {0.3, 0.4, 1.0}}, false};
  const std::string text = lammps_data(bed, container, std::vector<double>{2650.0}, 0.5);
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);  // title
  std::size_t atoms = 0, types = 0;
  double xlo, xhi, ylo, yhi, zlo, zhi;
  std::string word;
  in >> atoms >> word;
  EXPECT_EQ(word, "atoms");
  in >> types >> word >> word;
  EXPECT_EQ(atoms, 2u);
  EXPECT_EQ(types, 1u);
  in >> xlo >> xhi >> word >> word >> ylo >> yhi >> word >> word >> zlo >> zhi >> word >> word;
  EXPECT_EQ(xhi, 0.3);
  EXPECT_EQ(yhi, 0.4);
  EXPECT_EQ(zlo, 0.0);
  EXPECT_EQ(zhi, 0.5);
  in >> word >> word >> word;  // Atoms # sphere
  EXPECT_EQ(word, "sphere");
  for (std::size_t i = 0; i < 2; ++i) {
    std::size_t id, type;
    double diameter, density, x, y, z;
    in >> id >> type >> diameter >> density >> x >> y >> z;
    EXPECT_EQ(id, i + 1);
    EXPECT_EQ(type, 1u);
    EXPECT_EQ(diameter, 2.0 * bed.radius[i]);
    EXPECT_EQ(density, 2650.0);
    EXPECT_EQ(x, bed.position[i].x);
    EXPECT_EQ(y, bed.position[i].y);
    EXPECT_EQ(z, bed.position[i].z);
  }
  EXPECT_THROW(lammps_data(bed, container, std::vector<double>{2650.0}, 0.05), std::invalid_argument);  // below a sphere's top
}

// What aggpack writes, its reader takes back bit for bit: ids, types and velocities included.
TEST(LammpsData, TheReaderTakesBackWhatTheWriterWrote) {
  ParticleStore bed;
  bed.add({0.1, 1.0 / 3.0, 0.0127}, 0.0127, 2650.0, 0);
  bed.add({2.0 / 7.0, 0.2, 0.05}, 0.00635, 2650.0, 1);
  bed.velocity[1] = {0.1, -0.2, 1.0 / 3.0};
  const Container container{{{0, 0, 0}, {0.3, 0.4, 1.0}}, false};
  const std::vector<std::uint8_t> frozen{1, 0};
  const std::string text = lammps_data(bed, container, std::vector<double>{2650.0}, 0.5, frozen);
  EXPECT_NE(text.find("2 atom types"), std::string::npos);
  EXPECT_NE(text.find("\nVelocities\n"), std::string::npos);
  ASSERT_TRUE(is_lammps_data(text));
  EXPECT_FALSE(is_lammps_dump(text));
  const LammpsBed back = parse_lammps_data(text, "bed.data", 1.0, 2650.0);
  ASSERT_EQ(back.particles.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(back.particles.position[i], bed.position[i]);
    EXPECT_EQ(back.particles.radius[i], bed.radius[i]);
  }
  EXPECT_EQ(back.box.hi.z, 0.5);
  EXPECT_FALSE(back.timestep);
}

// The Atoms rows of a data file: (type, density) per atom, in id order.
std::vector<std::pair<std::size_t, double>> atom_types(const std::string& text) {
  std::istringstream in(text.substr(text.find("Atoms # sphere\n\n") + 16));
  std::vector<std::pair<std::size_t, double>> rows;
  std::size_t id = 0, type = 0;
  double diameter, density, x, y, z;
  while (in >> id >> type >> diameter >> density >> x >> y >> z) rows.emplace_back(type, density);
  return rows;
}

// M materials: atom type m + 1 for material m, M + m + 1 for a frozen sphere of it; 2M types
// in the header when M > 1, frozen or not; each atom carries its material's density.
TEST(LammpsData, EachMaterialIsAnAtomTypeWithItsDensity) {
  ParticleStore bed;
  const std::vector<double> densities{2650.0, 2000.0, 3100.0};
  const std::vector<std::uint8_t> material{2, 0, 1, 1, 2, 0};
  for (std::size_t i = 0; i < material.size(); ++i)
    bed.add({0.05 + 0.04 * double(i), 0.1, 0.02}, 0.01, densities[material[i]], 0, material[i]);
  const Container container{{{0, 0, 0}, {0.3, 0.4, 1.0}}, false};
  const std::string free_text = lammps_data(bed, container, densities, 0.5);
  EXPECT_NE(free_text.find("\n6 atom types\n"), std::string::npos) << free_text;
  const auto free_rows = atom_types(free_text);
  ASSERT_EQ(free_rows.size(), material.size());
  for (std::size_t i = 0; i < material.size(); ++i) {
    EXPECT_EQ(free_rows[i].first, material[i] + 1u) << i;
    EXPECT_EQ(free_rows[i].second, densities[material[i]]) << i;
  }
  const std::vector<std::uint8_t> frozen{1, 1, 0, 1, 0, 0};
  const auto frozen_rows = atom_types(lammps_data(bed, container, densities, 0.5, frozen));
  ASSERT_EQ(frozen_rows.size(), material.size());
  for (std::size_t i = 0; i < material.size(); ++i) {
    EXPECT_EQ(frozen_rows[i].first, material[i] + 1u + (frozen[i] ? densities.size() : 0u)) << i;
    EXPECT_EQ(frozen_rows[i].second, densities[material[i]]) << i;
  }
  // Two materials: 4 types; one material and nothing frozen: 1.
  const std::vector<double> two{2650.0, 2000.0};
  ParticleStore pair;
  pair.add({0.1, 0.1, 0.02}, 0.01, 2650.0, 0, 0);
  pair.add({0.2, 0.1, 0.02}, 0.01, 2000.0, 0, 1);
  EXPECT_NE(lammps_data(pair, container, two, 0.5).find("\n4 atom types\n"), std::string::npos);
  ParticleStore plain;
  plain.add({0.1, 0.1, 0.02}, 0.01, 2650.0);
  EXPECT_NE(lammps_data(plain, container, std::vector<double>{2650.0}, 0.5).find("\n1 atom types\n"),
            std::string::npos);
  // A sphere of a material beyond the list is refused.
  EXPECT_THROW(lammps_data(pair, container, std::vector<double>{2650.0}, 0.5), std::invalid_argument);
}

// A dump as LAMMPS writes it: several snapshots, columns in any order, rows out of id order.
constexpr const char* kDump =
    "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS ff ff fm\n0 0.3\n0 0.3\n0 1\n"
    "ITEM: ATOMS id type x y z radius\n2 1 0.2 0.2 0.9 0.01\n1 1 0.1 0.1 0.8 0.02\n"
    "ITEM: TIMESTEP\n5000\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS ff ff fm\n0 0.3\n0 0.3\n0 0.5\n"
    "ITEM: ATOMS radius z y x type id vx\n0.01 0.01 0.2 0.2 1 2 0\n0.02 0.02 0.1 0.1 1 1 0\n";

// A bed with a grain: the hybrid rows (its spheres of molecule 1 at its pose, the sphere of
// its own of molecule 0) and bodies.txt's record, whose inertia tensor in space turns each of
// the grain's principal axes into its moment times that axis, and whose angular momentum is
// that tensor times the angular velocity.
TEST(LammpsData, AGrainIsAMoleculeWithItsUnionsMassPropertiesInTheBodiesFile) {
  ParticleStore bed;
  const std::vector<Vec3> centres{{-0.002, 0.0, 0.0}, {0.003, 0.0, 0.0}};
  const std::vector<double> radii{0.002, 0.0015};
  RigidBodyShape shape{centres, radii, 5e-8, {1e-10, 3e-10, 3.5e-10}, 1.0, 0};
  const Quaternion q = normalized(Quaternion{0.9, 0.1, -0.3, 0.2});
  bed.add({0.02, 0.02, 0.005}, 0.003, 2000.0);
  const std::size_t b = bed.add_body({0.01, 0.012, 0.004}, q, shape, 2000.0);
  bed.bodies.velocity[b] = {0.0, 0.0, -1.0};
  bed.bodies.angular_velocity[b] = {3.0, -2.0, 1.0};
  const Container box = Container::square(0.03, 0.1, false);
  const double densities[] = {2000.0};
  std::istringstream data(lammps_data(bed, box, densities, 0.1));
  std::vector<std::vector<double>> rows;
  for (std::string line; std::getline(data, line);) {
    std::istringstream in(line);
    std::vector<double> v;
    for (double x; in >> x;) v.push_back(x);
    if (v.size() == 8) rows.push_back(v);
  }
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0][7], 0.0);  // the sphere of its own
  for (std::size_t k = 1; k < 3; ++k) {
    EXPECT_EQ(rows[k][7], 1.0);
    EXPECT_NEAR(rows[k][2], bed.position[k].x, 1e-17);
    EXPECT_NEAR(rows[k][4], bed.position[k].z, 1e-17);
    EXPECT_EQ(rows[k][5], 2.0 * radii[k - 1]);
  }
  std::istringstream bodies(lammps_rigid_bodies(bed, box));
  std::string line;
  std::vector<double> v;
  while (std::getline(bodies, line))
    if (!line.empty() && line[0] != '#' && v.empty()) {
      EXPECT_EQ(line, "1");  // the count
      std::getline(bodies, line);
      std::istringstream in(line);
      for (double x; in >> x;) v.push_back(x);
    }
  ASSERT_EQ(v.size(), 20u);
  EXPECT_EQ(v[0], 1.0);
  EXPECT_EQ(v[1], bed.bodies.mass[b]);
  EXPECT_EQ(v[2], 0.01);
  const double i[3][3] = {{v[5], v[8], v[9]}, {v[8], v[6], v[10]}, {v[9], v[10], v[7]}};
  const auto times = [&](const Vec3& a) {
    return Vec3{i[0][0] * a.x + i[0][1] * a.y + i[0][2] * a.z, i[1][0] * a.x + i[1][1] * a.y + i[1][2] * a.z,
                i[2][0] * a.x + i[2][1] * a.y + i[2][2] * a.z};
  };
  const Vec3& moments = bed.bodies.principal_inertia[b];
  const Vec3 axes[] = {rotate(q, {1, 0, 0}), rotate(q, {0, 1, 0}), rotate(q, {0, 0, 1})};
  const double m[] = {moments.x, moments.y, moments.z};
  for (int k = 0; k < 3; ++k) EXPECT_LT(norm(times(axes[k]) - m[k] * axes[k]), 1e-12 * moments.z) << k;
  EXPECT_EQ(v[13], -1.0);
  const Vec3 l = times(bed.bodies.angular_velocity[b]);
  EXPECT_NEAR(v[14], l.x, 1e-12 * norm(l));
  EXPECT_NEAR(v[15], l.y, 1e-12 * norm(l));
  EXPECT_NEAR(v[16], l.z, 1e-12 * norm(l));
}

TEST(LammpsDump, ReadsTheLastSnapshotOrTheOneAskedForInIdOrder) {
  ASSERT_TRUE(is_lammps_dump(kDump));
  const LammpsBed last = parse_lammps_dump(kDump, "bed.dump", 1.0, 2650.0);
  EXPECT_EQ(last.timestep, 5000);
  EXPECT_EQ(last.snapshots, 2u);
  ASSERT_EQ(last.particles.size(), 2u);
  EXPECT_EQ(last.particles.position[0], (Vec3{0.1, 0.1, 0.02}));  // id 1 first
  EXPECT_EQ(last.particles.radius[0], 0.02);
  EXPECT_EQ(last.particles.position[1], (Vec3{0.2, 0.2, 0.01}));
  const LammpsBed first = parse_lammps_dump(kDump, "bed.dump", 1000.0, 2650.0, 0);  // in mm: x 1000
  EXPECT_EQ(first.particles.position[0], (Vec3{100.0, 100.0, 800.0}));
  EXPECT_EQ(first.particles.radius[1], 10.0);
  // Scaled positions and diameters.
  const std::string scaled = "ITEM: TIMESTEP\n7\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS pp pp fm\n-1 1\n0 2\n0 4\n"
                             "ITEM: ATOMS id xs ys zs diameter\n1 0.5 0.25 0.125 0.2\n";
  const LammpsBed s = parse_lammps_dump(scaled, "s.dump", 1.0, 2650.0);
  EXPECT_EQ(s.particles.position[0], (Vec3{0.0, 0.5, 0.5}));
  EXPECT_EQ(s.particles.radius[0], 0.1);
}

TEST(LammpsDump, RefusesWhatItCannotReadWithTheLineAndWhatIsExpected) {
  const auto refused = [](const std::string& text, const std::string& words, std::optional<std::int64_t> step = {}) {
    try {
      parse_lammps_dump(text, "bed.dump", 1.0, 2650.0, step);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("bed.dump"), std::string::npos) << e.what();
    }
  };
  const std::string head = "ITEM: TIMESTEP\n1\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS ff ff ff\n0 1\n0 1\n0 1\n";
  refused(head + "ITEM: ATOMS id type x y z\n1 1 0.5 0.5 0.5\n", "radius or diameter");
  refused(head + "ITEM: ATOMS id x y z radius\n1 0.5 0.5 0.5\n", "expected 5 fields");
  refused(head + "ITEM: ATOMS id x y z radius\n1 0.5 0.5 0.5 -1\n", "must be positive");
  refused(head + "ITEM: ATOMS id x y z radius\n", "ends where atom row 1 of 1");
  refused(std::string(kDump), "no snapshot of timestep 17", 17);
  refused("ITEM: TIMESTEP\n1\nITEM: NUMBER OF ATOMS\n99999999999\n", "cannot fit");
  refused("ITEM: TIMESTEP\n1\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS xy xz yz ff ff ff\n", "triclinic");
  refused(head + "ITEM: ATOMS id x y z radius\n1 0.5 0.5 0.5 0.1\n1 0.5 0.5 0.5 0.1\n", "expected \"ITEM: TIMESTEP\"");
  try {
    parse_lammps_data("title\n\n1 atoms\n0 1 xlo xhi\n0 1 ylo yhi\n0 1 zlo zhi\n\nAtoms # atomic\n\n1 1 0.5 0.5 0.5\n",
                      "bed.data", 1.0, 2650.0);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("atom_style atomic"), std::string::npos) << e.what();
  }
}

// A position is read by its columns' kind (x y z, xu yu zu: lengths; xs ys zs: fractions of
// the box): columns of two kinds are refused, naming them, not read all as one kind.
TEST(LammpsDump, PositionColumnsOfMixedKindsAreRefused) {
  const std::string head = "ITEM: TIMESTEP\n7\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS pp pp fm\n0 1\n0 2\n0 4\n";
  for (const std::string columns : {"x ys z", "xs ys z", "xu y zs"}) {
    SCOPED_TRACE(columns);
    try {
      parse_lammps_dump(head + "ITEM: ATOMS id " + columns + " radius\n1 0.5 0.25 0.125 0.1\n", "mixed.dump", 1.0,
                        2650.0);
      ADD_FAILURE() << "read with every axis of one kind";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("mixed.dump:9:"), std::string::npos) << what;
      EXPECT_NE(what.find("\"" + columns + "\""), std::string::npos) << what;
      EXPECT_NE(what.find("x y z, xu yu zu or xs ys zs"), std::string::npos) << what;
    }
  }
}

// A triclinic data file's header has a tilt line ("xy xz yz" its last words): aggpack's
// containers are rectangular, so the file is refused, not read as a rectangular box.
TEST(LammpsData, ATriclinicBoxIsRefusedAtItsTiltLine) {
  const std::string text =
      "title\n\n1 atoms\n0 1 xlo xhi\n0 1 ylo yhi\n0 1 zlo zhi\n0.1 0 0 xy xz yz\n\nAtoms # sphere\n\n"
      "1 1 0.2 2650 0.5 0.5 0.5\n";
  ASSERT_TRUE(is_lammps_data(text));
  try {
    parse_lammps_data(text, "tilted.data", 1.0, 2650.0);
    ADD_FAILURE() << "a triclinic box was read as a rectangular one";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("tilted.data:7:"), std::string::npos) << what;
    EXPECT_NE(what.find("triclinic"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace aggpack
