#pragma once
#include <cmath>

#include "aggpack/core/particle_store.hpp"

namespace aggpack::testing {

// n^3 cells of a simple cubic lattice of touching spheres, period a, from the origin.
inline ParticleStore simple_cubic(int n, double a) {
  ParticleStore p;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) p.add({(i + 0.5) * a, (j + 0.5) * a, (k + 0.5) * a}, 0.5 * a, 1.0);
  return p;
}

// n^3 conventional cells of a face-centred cubic lattice of touching spheres, cell side a.
inline ParticleStore face_centred_cubic(int n, double a) {
  ParticleStore p;
  const double r = a * std::sqrt(2.0) / 4.0;
  const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        for (const auto& b : basis)
          p.add({(i + b[0] + 0.25) * a, (j + b[1] + 0.25) * a, (k + b[2] + 0.25) * a}, r, 1.0);
  return p;
}

}  // namespace aggpack::testing
