// The analysis of a packing with rigid grains: a grain counts with the volume of its spheres'
// union inside the box (each point once), whole, cut, or through the periodic sides; the
// profiles and the bed's measures take grains as they take spheres.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "aggpack/analysis/coordination.hpp"
#include "aggpack/analysis/density.hpp"
#include "aggpack/analysis/sphere_box_volume.hpp"
#include "aggpack/core/quaternion.hpp"
#include "aggpack/grains/union_mass_properties.hpp"

namespace aggpack {
namespace {

// Three overlapping spheres, their union's volume and principal moments computed once.
struct Grain {
  std::vector<Vec3> centres{{-0.004, 0.0, 0.0}, {0.002, 0.001, 0.0}, {0.005, -0.001, 0.001}};
  std::vector<double> radii{0.003, 0.0035, 0.002};
  MassProperties mass;
  Grain() {
    std::vector<MemberSphere> spheres;
    for (std::size_t k = 0; k < 3; ++k) spheres.push_back({centres[k], radii[k]});
    mass = union_mass_properties(spheres);
    // Into the frame of the centre of mass (the moments are not used by the analysis).
    for (Vec3& c : centres) c -= mass.centre_of_mass;
  }
  [[nodiscard]] RigidBodyShape shape() const { return {centres, radii, mass.volume, {1e-12, 1e-12, 1e-12}}; }
  [[nodiscard]] std::vector<MemberSphere> placed(const ParticleStore& p, std::size_t b) const {
    std::vector<MemberSphere> s;
    for (std::size_t k = 0; k < 3; ++k)
      s.push_back({p.bodies.position[b] + rotate(p.bodies.orientation[b], centres[k]), radii[k]});
    return s;
  }
};

TEST(GrainDensity, AGrainCountsItsUnionInsideTheBoxWholeOrCut) {
  const Grain grain;
  ParticleStore p;
  p.add({0.03, 0.03, 0.03}, 0.002, 2650.0);
  const Quaternion q = normalized(Quaternion{0.8, 0.1, -0.4, 0.3});
  p.add_body({0.05, 0.05, 0.05}, q, grain.shape(), 2650.0);
  p.add({0.07, 0.05, 0.05}, 0.002, 2650.0);
  const Container container = Container::square(0.1, 0.1, false);
  // Whole inside: its union's volume (not its spheres' summed, which count the overlaps twice).
  const Box all{{0.0, 0.0, 0.0}, {0.1, 0.1, 0.1}};
  const double ball = 4.0 / 3.0 * std::numbers::pi * 0.008e-6;
  EXPECT_NEAR(solid_volume_in_box(p, container, all), grain.mass.volume + 2.0 * ball, 1e-9 * grain.mass.volume);
  // Cut by one, two and three planes: the slicing of the union against the box.
  const std::vector<MemberSphere> placed = grain.placed(p, 0);
  for (const Box& cut : {Box{{0.0, 0.0, 0.0}, {0.051, 0.1, 0.1}}, Box{{0.0, 0.049, 0.0}, {0.051, 0.1, 0.1}},
                         Box{{0.0, 0.049, 0.0495}, {0.051, 0.1, 0.1}}}) {
    const double spheres = sphere_box_volume(p.position[0], 0.002, cut) + sphere_box_volume(p.position[4], 0.002, cut);
    EXPECT_NEAR(solid_volume_in_box(p, container, cut), union_volume_in_box(placed, cut) + spheres,
                2e-6 * grain.mass.volume);
  }
}

// In a periodic box a grain astride a side counts in full in a box of the whole footprint,
// its images' parts adding up.
TEST(GrainDensity, AGrainAstrideAPeriodicSideCountsWholeInTheFootprint) {
  const Grain grain;
  ParticleStore p;
  p.add_body({0.0005, 0.099, 0.05}, normalized(Quaternion{0.3, 0.6, 0.1, -0.7}), grain.shape(), 2650.0);
  const Container periodic = Container::square(0.1, 0.1, true);
  const Box footprint{{0.0, 0.0, 0.0}, {0.1, 0.1, 0.1}};
  EXPECT_NEAR(solid_volume_in_box(p, periodic, footprint), grain.mass.volume, 2e-6 * grain.mass.volume);
}

// Slices of the bed hold all of its solid between them, grains counted once; the bed's
// largest size is the grain's bounding diameter.
TEST(GrainDensity, ProfilesAddUpToTheSolidAndTheBedSizesItsGrains) {
  const Grain grain;
  ParticleStore p;
  const Container container = Container::square(0.03, 0.1, false);
  for (int k = 0; k < 9; ++k) {
    const Vec3 at{0.008 + 0.007 * (k % 3), 0.008 + 0.007 * ((k / 3) % 3), 0.01 + 0.003 * k};
    p.add_body(at, normalized(Quaternion{1.0, 0.1 * k, -0.05 * k, 0.2}), grain.shape(), 2650.0);
  }
  p.add({0.015, 0.015, 0.004}, 0.002, 2650.0);
  const double solid = 9.0 * grain.mass.volume + 4.0 / 3.0 * std::numbers::pi * 0.008e-6;
  const double thickness = 0.0025;
  const Profile slices = vertical_profile(p, container, thickness);
  double summed = 0.0;
  for (const double f : slices.solid_fraction) summed += f * 0.03 * 0.03 * thickness;
  EXPECT_NEAR(summed, solid, 2e-6 * solid);
  const BedGeometry bed = measure_bed(p, container);
  double reach = 0.0;
  for (std::size_t k = 0; k < 3; ++k) reach = std::max(reach, norm(grain.centres[k]) + grain.radii[k]);
  EXPECT_NEAR(bed.d_max, 2.0 * reach, 1e-15);
  // The wall profile's shells hold the solid between its heights.
  const Profile shells = wall_distance_profile(p, container, 0.003, 0.0, 0.1);
  double in_shells = 0.0;
  for (std::size_t k = 0; k < shells.solid_fraction.size(); ++k) {
    const double a = 0.003 * static_cast<double>(k), b = a + 0.003;
    in_shells += shells.solid_fraction[k] * ((0.03 - 2 * a) * (0.03 - 2 * a) - (0.03 - 2 * b) * (0.03 - 2 * b)) * 0.1;
  }
  EXPECT_NEAR(in_shells, solid, 2e-6 * solid);
}

// The spheres of a grain overlap and are not in contact; two grains whose spheres touch in two
// places are one contact each, by grain; a sphere touching a grain's two spheres, one.
TEST(GrainDensity, CoordinationCountsEachTouchingGrainOnce) {
  const std::vector<Vec3> centres{{-0.002, 0, 0}, {0.002, 0, 0}};
  const std::vector<double> radii{0.003, 0.003};
  const RigidBodyShape rod{centres, radii, 1e-7, {1e-12, 1e-12, 1e-12}};
  ParticleStore p;
  p.add_body({0.05, 0.05, 0.05}, {}, rod, 2650.0);   // spheres at x = 0.048 and 0.052
  p.add_body({0.05, 0.056, 0.05}, {}, rod, 2650.0);  // 6 mm along y: both pairs touch
  p.add({0.05, 0.05, 0.054}, 0.0015, 2650.0);         // above the first, touching both its spheres
  const Container container = Container::square(0.1, 0.1, false);
  const std::vector<int> per_sphere = contact_counts(p, container, 1e-6);
  EXPECT_EQ(per_sphere, (std::vector<int>{2, 2, 1, 1, 2}));
  const CoordinationResult c = measure_coordination(p, container, {{0, 0, 0}, {0.1, 0.1, 0.1}}, 1e-6);
  EXPECT_EQ(c.particles_counted, 3u);  // two grains and a sphere
  EXPECT_DOUBLE_EQ(c.mean, (2.0 + 1.0 + 1.0) / 3.0);
  // Per grain: the first touches the second grain and the sphere, the second the first only.
  EXPECT_EQ(grain_contact_counts(p, container, 1e-6), (std::vector<int>{2, 1}));
}

}  // namespace
}  // namespace aggpack
