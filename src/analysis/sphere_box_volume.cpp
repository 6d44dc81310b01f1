#include "aggpack/analysis/sphere_box_volume.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace aggpack {

namespace {
constexpr double kPi = std::numbers::pi;


// For one offset t > 0 of the corner region, t * S_t(z) + I_t(z), where
//   S_t(z) = ∫ w dz,  w = sqrt(K² - z²),  K² = R² - t²
//   I_t(z) = ∫ (R² - z²) asin(t / sqrt(R² - z²)) dz   (integrated by parts;
//            ∫ dz / ((R² - z²) w) = atan(t z / (R w)) / (R t)).
// The caller passes w: asin(z / K) near z = K would turn rounding into sqrt(eps) errors,
// atan2(z, w) with an accurate w does not.
double offset_antiderivative(double R, double t, double z, double w, double cubic) {
  const double K2 = z * z + w * w;
  // At the top of a wedge w = 0 exactly and every angle below is a right angle (z, t > 0).
  const bool pole = w == 0.0;
  const double half_pi = 0.5 * kPi;
  const double as = pole ? half_pi : std::atan2(z, w);                        // asin(z / K)
  const double at = pole ? half_pi : std::atan2(t * z, R * w);
  const double asin_t_rho = pole ? half_pi : std::atan2(t, w);                // asin(t / rho)
  const double S = 0.5 * (z * w + K2 * as);
  const double J = (2.0 / 3.0) * R * R * R * at - (2.0 / 3.0) * t * R * R * as + (t / 6.0) * (K2 * as - z * w);
  const double I = cubic * asin_t_rho - J;  // rho² = t² + w²
  return t * S + I;
}

// Antiderivative in z of A(z), the area of the disc of radius sqrt(R² - z²) with x > a, y > b
// (a, b >= 0, valid while a² + b² <= R² - z²):
//   A = ab + ½ρ²(π/2 - asin(a/ρ) - asin(b/ρ)) - ½ a sqrt(ρ² - a²) - ½ b sqrt(ρ² - b²).
// w_a = sqrt(R² - a² - z²) and w_b = sqrt(R² - b² - z²) are given by the caller.
double corner_antiderivative(double R, double a, double b, double z, double w_a, double w_b) {
  const double cubic = R * R * z - z * z * z / 3.0;  // ∫ (R² - z²) dz
  double f = a * b * z + 0.25 * kPi * cubic;
  if (a > 0.0) f -= 0.5 * offset_antiderivative(R, a, z, w_a, cubic);
  if (b > 0.0) f -= 0.5 * offset_antiderivative(R, b, z, w_b, cubic);
  return f;
}

// One axis's slab as a signed sum of half-spaces {u > offset}; offset < 0 means "no constraint".
struct SlabTerm {
  double sign;
  double offset;
};
struct SlabTerms {
  std::array<SlabTerm, 3> terms;
  int count = 0;
  void add(double sign, double offset) { terms[count++] = {sign, offset}; }
};
constexpr double kNone = -1.0;

// Returns false when the ball misses the slab [lo, hi] (coordinates relative to the centre).
bool decompose_slab(double lo, double hi, double R, SlabTerms& out) {
  if (hi <= -R || lo >= R || hi <= lo) return false;
  const bool cut_lo = lo > -R;
  const bool cut_hi = hi < R;
  if (!cut_lo && !cut_hi) {
    out.add(1.0, kNone);
  } else if (cut_lo && !cut_hi) {  // u > lo
    if (lo >= 0.0) {
      out.add(1.0, lo);
    } else {
      out.add(1.0, kNone);
      out.add(-1.0, -lo);
    }
  } else if (!cut_lo && cut_hi) {  // u < hi
    if (hi <= 0.0) {
      out.add(1.0, -hi);
    } else {
      out.add(1.0, kNone);
      out.add(-1.0, hi);
    }
  } else if (lo < 0.0 && hi > 0.0) {
    out.add(1.0, kNone);
    out.add(-1.0, -lo);
    out.add(-1.0, hi);
  } else if (lo >= 0.0) {
    out.add(1.0, lo);
    out.add(-1.0, hi);
  } else {
    out.add(1.0, -hi);
    out.add(-1.0, -lo);
  }
  return true;
}

// Volume of the ball beyond the given non-negative offsets (kNone: unconstrained axis).
double orthant_piece(double R, double a, double b, double c) {
  std::array<double, 3> t{};
  int n = 0;
  for (double o : {a, b, c})
    if (o >= 0.0) t[n++] = o;
  switch (n) {
    case 0:
      return 4.0 / 3.0 * kPi * R * R * R;
    case 1:
      return ball_cap_volume(R, t[0]);
    case 2:
      return ball_wedge_volume(R, t[0], t[1]);
    default:
      return ball_corner_volume(R, t[0], t[1], t[2]);
  }
}
}  // namespace

double ball_cap_volume(double R, double t) {
  if (t >= R) return 0.0;
  const double h = R - t;
  return kPi * h * h * (3.0 * R - h) / 3.0;
}

double ball_wedge_volume(double R, double b, double c) {
  // {x free, y > b, z > c} is twice the corner with a = 0.
  return 2.0 * ball_corner_volume(R, 0.0, b, c);
}

double ball_corner_volume(double R, double a, double b, double c) {
  // Beyond the corner (a, b, c) the ball has depth D = R² - a² - b² - c² > 0.
  const double D = R * R - a * a - b * b - c * c;
  if (D <= 0.0) return 0.0;
  // Integrate over z from c to z_top, where the disc shrinks to the corner (a, b).
  // There w_a = b and w_b = a exactly; at z = c they are sqrt(D + b²) and sqrt(D + a²).
  const double z_top = std::sqrt(D + c * c);
  const double upper = corner_antiderivative(R, a, b, z_top, b, a);
  const double lower = corner_antiderivative(R, a, b, c, std::sqrt(D + b * b), std::sqrt(D + a * a));
  return std::max(upper - lower, 0.0);
}

double sphere_box_volume(const Vec3& centre, double radius, const Box& box) {
  const double R = radius;
  SlabTerms x, y, z;
  if (!decompose_slab(box.lo.x - centre.x, box.hi.x - centre.x, R, x)) return 0.0;
  if (!decompose_slab(box.lo.y - centre.y, box.hi.y - centre.y, R, y)) return 0.0;
  if (!decompose_slab(box.lo.z - centre.z, box.hi.z - centre.z, R, z)) return 0.0;
  double volume = 0.0;
  for (int i = 0; i < x.count; ++i)
    for (int j = 0; j < y.count; ++j)
      for (int k = 0; k < z.count; ++k) {
        const double sign = x.terms[i].sign * y.terms[j].sign * z.terms[k].sign;
        volume += sign * orthant_piece(R, x.terms[i].offset, y.terms[j].offset, z.terms[k].offset);
      }
  return std::max(volume, 0.0);
}

}  // namespace aggpack
