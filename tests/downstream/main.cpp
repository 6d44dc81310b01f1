// Measures a simple cubic lattice with the installed library: the density of any box whose
// faces lie between lattice planes is pi/6.
#include <cstdio>

#include "aggpack/core/version.hpp"
#include "aggpack/run/analyze.hpp"

int main() {
  aggpack::ParticleStore lattice;
  for (int k = 0; k < 6; ++k)
    for (int j = 0; j < 6; ++j)
      for (int i = 0; i < 6; ++i) lattice.add({i + 0.5, j + 0.5, k + 0.5}, 0.5, 1000.0);
  aggpack::AnalysisRequest request;
  request.boxes.push_back({{1, 1, 1}, {5, 5, 5}});
  const auto report = aggpack::analyze_packing(lattice, aggpack::bounding_container(lattice), request);
  std::printf("aggpack %s: density %.12f\n", aggpack::kVersion, report.density.mean);
  return 0;
}
