// A run from the caller's bed (particles.from = "-", RunControls::starting_bed) against the same
// run reading that bed from its file, and what a starting bed may not be.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>

#include "aggpack/core/error.hpp"
#include "aggpack/io/particle_file.hpp"
#include "aggpack/io/scenario.hpp"
#include "aggpack/run/run.hpp"

namespace aggpack {
namespace {

const std::filesystem::path kLattice = std::filesystem::path(AGGPACK_EXAMPLES) / "cubic_lattice.csv";

// The shipped lattice's container, its particles from `from`; `more` appended.
Scenario lattice_scenario(const std::string& from, const std::string& more = "") {
  return parse_scenario("seed = 1\n[container]\nside = \"10 in\"\nheight = \"10 in\"\n[particles]\nfrom = \"" + from +
                            "\"\n" + more + "[analysis]\nbox_sides = [\"4 in\", \"6 in\"]\n",
                        "lattice.toml");
}

RunReport run_from(const Scenario& sc, const ParticleStore* bed) {
  RunControls controls;
  controls.starting_bed = bed;
  Progress silent;
  return run(sc, controls, silent);
}

std::string error_of(const Scenario& sc, const ParticleStore* bed) {
  try {
    (void)run_from(sc, bed);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(StartingBed, IsMeasuredAsTheFileItCameFrom) {
  const ParticleStore lattice = read_particle_file(kLattice, 1.0, 1.0);
  const RunReport given = run_from(lattice_scenario("-"), &lattice);
  const RunReport read = run_from(lattice_scenario(kLattice.string()), nullptr);
  ASSERT_EQ(given.particles.size(), 1000u);
  EXPECT_EQ(given.particles.position, read.particles.position);
  EXPECT_EQ(given.final.density.mean, read.final.density.mean);
  EXPECT_NEAR(given.final.density.mean, std::numbers::pi / 6.0, 1e-9);  // touching spheres on a cubic lattice
  // Its masses are the scenario's material's, not the caller's density of 1 kg/m^3.
  EXPECT_NEAR(given.particles.mass[0], 2650.0 * std::numbers::pi / 6.0 * std::pow(0.0254, 3), 1e-12);
  EXPECT_EQ(given.input_format, "given by the caller (1000 spheres)");
  EXPECT_EQ(given.summary_json(0.0, 0.0)["input"]["format"], "given by the caller (1000 spheres)");
}

TEST(StartingBed, IsRefusedWhenAbsentUnwantedOrUnfit) {
  ParticleStore lattice = read_particle_file(kLattice, 1.0, 1.0);
  EXPECT_NE(error_of(lattice_scenario("-"), nullptr).find("particles.from = \"-\" takes the starting bed from the "
                                                          "library's caller"),
            std::string::npos);
  EXPECT_NE(error_of(lattice_scenario(kLattice.string()), &lattice).find("a starting bed was given, and the "
                                                                         "scenario's particles are read from"),
            std::string::npos);
  lattice.material[3] = 2;  // the scenario has one material
  EXPECT_NE(error_of(lattice_scenario("-"), &lattice).find("sphere 3 of the starting bed given"), std::string::npos);
  lattice.material[3] = 0;
  lattice.position[7].x = 1.0;  // far outside the 10 in container
  EXPECT_NE(error_of(lattice_scenario("-"), &lattice).find("the starting bed given"), std::string::npos);
  EXPECT_THROW((void)lattice_scenario("-", "length_unit = \"mm\"\n"), InputError);
}

}  // namespace
}  // namespace aggpack
