#include "aggpack/dynamics/contact_batch.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <stdexcept>

#include "aggpack/core/rng.hpp"

namespace aggpack {
namespace {

using C = ContactBatch;

// `count` random touching pairs: sizes over a factor of four, overlaps up to 1 % of the
// reach, speeds of a collision, spins, and springs long enough that some contacts slide.
ContactBatch random_contacts(std::size_t count, std::uint64_t seed) {
  Rng rng(seed, 7);
  ContactBatch b;
  b.reserve_more(count);
  for (std::size_t k = 0; k < count; ++k) {
    const double ri = rng.uniform(0.002, 0.008), rj = rng.uniform(0.002, 0.008);
    Vec3 direction{rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)};
    direction = direction * (1.0 / norm(direction));
    const Vec3 d = direction * ((ri + rj) * (1.0 - rng.uniform(1e-6, 1e-2)));
    const auto put = [&](C::Column c, double v) { b.at(c, k) = v; };
    const auto put3 = [&](C::Column c, const Vec3& v) { C::put3(b.contact(k), c, v); };
    const auto random3 = [&](double scale) {
      return Vec3{rng.uniform(-scale, scale), rng.uniform(-scale, scale), rng.uniform(-scale, scale)};
    };
    put3(C::kDx, d);
    put(C::kDistance2, norm2(d));
    put(C::kRadiusI, ri);
    put(C::kRadiusJ, rj);
    put(C::kMassI, 2650.0 * 4.18879 * ri * ri * ri);
    put(C::kMassJ, 2650.0 * 4.18879 * rj * rj * rj);
    put3(C::kVx, random3(0.5));
    put3(C::kSx, random3(0.05));
    put3(C::kWx, random3(20.0));
    put3(C::kUx, random3(k % 2 ? 1e-4 : 1e-7));
    put3(C::kHx, random3(k % 3 ? 1e-4 : 1e-6));  // rolling history, tilted off the contact plane
    b.entry[k] = static_cast<std::uint32_t>(k);
  }
  b.size = count;
  return b;
}

ContactCoefficients coefficients(double rolling) {
  return {effective_youngs_modulus(50e9, 0.25, 50e9, 0.25), effective_shear_modulus(50e9, 0.25, 50e9, 0.25),
          damping_for_restitution(0.5), 0.3, rolling};
}
// The spring-dashpot rolling law, stiff enough that some histories reach the cap and some do not.
ContactCoefficients spring_dashpot(double rolling) {
  ContactCoefficients c = coefficients(rolling);
  c.rolling_model = RollingModel::SpringDashpot;
  c.rolling_stiffness = 1e6;
  c.rolling_damping = 10.0;
  return c;
}

// Every output column and the updated springs, for the batch's contacts.
std::vector<double> results(const ContactBatch& b) {
  std::vector<double> out;
  for (const C::Column c : {C::kUx, C::kUy, C::kUz, C::kHx, C::kHy, C::kHz, C::kFx, C::kFy, C::kFz, C::kTix, C::kTiy, C::kTiz, C::kTjx,
                            C::kTjy, C::kTjz})
    for (std::size_t k = 0; k < b.size; ++k) out.push_back(b.at(c, k));
  return out;
}

// The vector kernel gives the scalar law's bits, on every instruction set this machine
// runs, without rolling resistance, with the constant torque and with the spring-dashpot;
// sizes that are not a multiple of the vector length use the padding.
TEST(ContactBatch, VectorKernelGivesTheScalarLawsBitsOnEveryTarget) {
  const std::vector<std::string> targets = contact_kernel_targets();
  ASSERT_FALSE(targets.empty());
  EXPECT_EQ(contact_kernel_target(), targets.front());
  for (const ContactCoefficients& coefficient : {coefficients(0.0), coefficients(0.05), spring_dashpot(0.05)}) {
    const HertzMindlin law(coefficient);
    const double rolling = coefficient.rolling;
    for (const std::size_t count : {std::size_t{1}, std::size_t{7}, std::size_t{1003}}) {
      ContactBatch reference = random_contacts(count, 11 + count);
      const ContactBatch input = reference;
      evaluate_each(law, reference, 1e-6);
      const std::vector<double> expected = results(reference);
      // Some contacts slide (the tangential force is at the Coulomb limit mu F_n), some stick.
      std::size_t sliding = 0;
      for (std::size_t k = 0; k < count; ++k) {
        const auto at = [&](C::Column c) { return reference.at(c, k); };
        const Vec3 d{at(C::kDx), at(C::kDy), at(C::kDz)}, f{at(C::kFx), at(C::kFy), at(C::kFz)};
        const Vec3 n = d * (1.0 / norm(d));
        const double fn = -dot(f, n);
        if (std::abs(norm(f + fn * n) - law.c.friction * fn) < 1e-9 * fn) ++sliding;
      }
      if (count > 100) {
        EXPECT_GT(sliding, count / 10);
        EXPECT_LT(sliding, count - count / 10);
      }
      for (const std::string& target : targets) {
        ContactBatch vector = input;
        evaluate_with_target(target, law, vector, 1e-6);
        const std::vector<double> got = results(vector);
        ASSERT_EQ(got.size(), expected.size());
        EXPECT_EQ(0, std::memcmp(got.data(), expected.data(), got.size() * sizeof(double)))
            << target << ", rolling " << rolling << (law.c.rolling_history() ? " (spring-dashpot)" : "") << ", "
            << count << " contacts";
      }
      ContactBatch dispatched = input;
      evaluate(law, dispatched, 1e-6);
      EXPECT_EQ(results(dispatched), expected);
      if (!law.c.rolling_history() || count < 100) continue;
      // Some rolling torques are at the cap mu_r R* F_n, some below it.
      std::size_t capped = 0;
      for (std::size_t k = 0; k < count; ++k) {
        const auto at = [&](C::Column c) { return reference.at(c, k); };
        const Vec3 d{at(C::kDx), at(C::kDy), at(C::kDz)}, f{at(C::kFx), at(C::kFy), at(C::kFz)};
        const Vec3 n = d * (1.0 / norm(d));
        const double fn = -dot(f, n), ri = at(C::kRadiusI), rj = at(C::kRadiusJ);
        // Less the tangential force's torque, applied at the contact point (R_i - d/2 from i).
        const double arm = ri - 0.5 * (ri + rj - norm(d));
        const Vec3 torque = C::get3(reference.contact(k), C::kTix) - arm * cross(n, f + fn * n);
        capped += std::abs(norm(torque) - rolling * ri * rj / (ri + rj) * fn) < 1e-6 * norm(torque) ? 1 : 0;
      }
      EXPECT_GT(capped, count / 10);
      EXPECT_LT(capped, count - count / 10);
    }
  }
  ContactBatch batch = random_contacts(4, 5);
  EXPECT_THROW(evaluate_with_target("no such target", HertzMindlin(coefficients(0.0)), batch, 1e-6),
               std::invalid_argument);
}

// A run of three materials: the vector kernel with each lane's pair coefficients gives
// evaluate_pairs's bits (each contact with its own pair's law alone) on every target, with
// pairs of other moduli, friction and restitution, and pairs with and without rolling
// resistance side by side in one vector (their torque +0 and their history untouched).
TEST(ContactBatch, PairKernelGivesEachPairsScalarLawBitsOnEveryTarget) {
  const auto pair_laws = [](bool spring) {
    std::vector<ContactLaw> laws;
    for (std::size_t a = 0; a < 3; ++a)
      for (std::size_t b = 0; b < 3; ++b) {
        const double rolling = (a + b) % 3 == 0 ? 0.0 : 0.02 * static_cast<double>(a + b);
        ContactCoefficients c = spring ? spring_dashpot(rolling) : coefficients(rolling);
        if (spring && rolling == 0.0) c.rolling_stiffness = c.rolling_damping = 0.0;
        c.e_star = effective_youngs_modulus(50e9 / static_cast<double>(1 + a), 0.25, 70e9 / static_cast<double>(1 + b), 0.2);
        c.g_star = effective_shear_modulus(50e9 / static_cast<double>(1 + a), 0.25, 70e9 / static_cast<double>(1 + b), 0.2);
        c.friction = 0.2 + 0.1 * static_cast<double>(a * b);
        c.damping = damping_for_restitution(0.3 + 0.1 * static_cast<double>(a + b));
        laws.emplace_back(HertzMindlin(c));
      }
    return laws;
  };
  for (const bool spring : {false, true}) {
    const std::vector<ContactLaw> laws = pair_laws(spring);
    for (const std::size_t count : {std::size_t{1}, std::size_t{7}, std::size_t{1003}}) {
      ContactBatch reference = random_contacts(count, 23 + count);
      reference.pair.resize(count);
      Rng rng(count, 3);
      for (std::size_t k = 0; k < count; ++k) reference.pair[k] = static_cast<std::uint16_t>(rng.uniform(0.0, 9.0));
      const ContactBatch input = reference;
      evaluate_pairs<HertzMindlin>(laws, reference, 1e-6);
      const std::vector<double> expected = results(reference);
      for (const std::string& target : contact_kernel_targets()) {
        ContactBatch vector = input;
        evaluate_hertz_pairs_with_target(target, laws, vector, 1e-6);
        const std::vector<double> got = results(vector);
        ASSERT_EQ(got.size(), expected.size());
        EXPECT_EQ(0, std::memcmp(got.data(), expected.data(), got.size() * sizeof(double)))
            << target << (spring ? ", spring-dashpot" : ", constant torque") << ", " << count << " contacts";
      }
      // The pairs without rolling resistance kept their histories; the others moved theirs.
      std::size_t kept = 0, moved = 0;
      for (std::size_t k = 0; k < count; ++k) {
        const bool same = reference.at(C::kHx, k) == input.at(C::kHx, k);
        if (std::get<HertzMindlin>(laws[input.pair[k]]).c.rolling == 0.0) {
          EXPECT_TRUE(same) << k;
          kept += same ? 1 : 0;
        } else {
          moved += same ? 0 : 1;
        }
      }
      if (count > 100 && spring) {
        EXPECT_GT(kept, count / 10);
        EXPECT_GT(moved, count / 2);
      }
    }
  }
}

}  // namespace
}  // namespace aggpack
