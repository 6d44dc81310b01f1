#include "aggpack/io/lammps_data.hpp"

#include <gtest/gtest.h>

#include <sstream>
#include <stdexcept>

namespace aggpack {
namespace {

// Read back as LAMMPS's read_data would: the counts, the box and every atom, bit for bit.
TEST(LammpsData, RoundTripsTheBedExactly) {
  ParticleStore bed;
  bed.add({0.1, 1.0 / 3.0, 0.0127}, 0.0127, 1.0);
  bed.add({2.0 / 7.0, 0.2, 0.05}, 0.00635, 1.0);
  const Container container{{{0, 0, 0}, {0.3, 0.4, 1.0}}, false};
  const std::string text = lammps_data(bed, container, 2650.0, 0.5);
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
  EXPECT_THROW(lammps_data(bed, container, 2650.0, 0.05), std::invalid_argument);  // below a sphere's top
}

}  // namespace
}  // namespace aggpack
