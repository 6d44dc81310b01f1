#include "aggpack/analysis/coordination.hpp"

#include <gtest/gtest.h>

#include "lattices.hpp"

namespace aggpack {
namespace {

TEST(Coordination, SimpleCubicInteriorHasSixContacts) {
  const ParticleStore p = testing::simple_cubic(6, 1.0);
  const Container c = Container::square(6.0, 6.0, false);
  const auto r = measure_coordination(p, c, {{1, 1, 1}, {5, 5, 5}}, 1e-9);
  EXPECT_EQ(r.particles_counted, 64u);
  EXPECT_DOUBLE_EQ(r.mean, 6.0);
  ASSERT_EQ(r.histogram.size(), 7u);
  EXPECT_EQ(r.histogram[6], 64u);
}

TEST(Coordination, FaceCentredCubicInteriorHasTwelve) {
  const ParticleStore p = testing::face_centred_cubic(5, 1.0);
  const auto r = measure_coordination(p, Container::square(5.0, 5.0, false), {{1.2, 1.2, 1.2}, {3.8, 3.8, 3.8}}, 1e-9);
  EXPECT_GT(r.particles_counted, 0u);
  EXPECT_DOUBLE_EQ(r.mean, 12.0);
}

TEST(Coordination, PeriodicSidesWrapContacts) {
  const ParticleStore p = testing::simple_cubic(4, 1.0);
  const auto counts = contact_counts(p, Container::square(4.0, 4.0, true), 1e-9);
  // Every sphere has 4 horizontal neighbours through the wrap; 1 or 2 vertical ones.
  for (std::size_t i = 0; i < p.size(); ++i) {
    const bool end_layer = p.position[i].z < 1.0 || p.position[i].z > 3.0;
    EXPECT_EQ(counts[i], end_layer ? 5 : 6) << i;
  }
}

TEST(Coordination, GapsBeyondTheToleranceAreNotContacts) {
  ParticleStore p;
  p.add({0, 0, 0}, 1.0, 1.0);
  p.add({2.0 + 1e-7, 0, 0}, 1.0, 1.0);  // relative gap 5e-8
  p.add({0, 2.0 + 1e-3, 0}, 1.0, 1.0);  // relative gap 5e-4
  const Container c{{{-5, -5, -5}, {5, 5, 5}}, false};
  EXPECT_EQ(contact_counts(p, c, 1e-6)[0], 1);
  EXPECT_EQ(contact_counts(p, c, 1e-3)[0], 2);
  EXPECT_EQ(contact_counts(p, c, 0.0)[0], 0);
}

}  // namespace
}  // namespace aggpack
