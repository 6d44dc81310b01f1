#pragma once
// One sieve fraction of a material alone, in a periodic bed (no wall), filled by the procedure
// of a lab test: the bed whose packing gives the class's residual packing density
// (blends/simulated_betas.hpp). Its scenario is written like a test's, every choice said.
#include <string>
#include <vector>

#include "aggpack/io/material_file.hpp"
#include "aggpack/labtests/lab_test.hpp"

namespace aggpack {

struct ClassBedSetup {
  const AggregateMaterial* material = nullptr;
  double d_lo = 0.0, d_hi = 0.0;  // m: the fraction's sieves
  LabTestKind test = LabTestKind::C29;
  std::string method;       // C29: shovelling, rodding, jigging; C1252: A, B, C (all poured alike)
  double particles = 3000;  // about, in the bed
  double max_time_s = 2.0;  // each DEM step's budget of simulated time
};

struct ClassBed {
  std::string scenario_text;
  std::string procedure;       // "poured", "rodded", "jigged": what was done to this bed
  double side_m = 0.0;         // of the periodic square
  double fill_height_m = 0.0;  // expected
  std::vector<std::string> modelling;
};

// InputError for a fraction with d_lo >= d_hi or not positive, or a method the test does not
// define. Rodding a bed narrower than three rods (16 mm) is not the lab's rodding: such a bed is
// poured (said in `procedure` and `modelling`).
ClassBed class_bed(const ClassBedSetup& setup);

// A blend of two materials in a periodic bed by the same procedure: the DEM check of a blend's
// prediction (blends/blend_check.hpp). Each material's whole grading, its grains and its contact
// values; the fine one's cut at `fine_d_min` (0: none).
struct BlendBedSetup {
  const AggregateMaterial* coarse = nullptr;
  const AggregateMaterial* fine = nullptr;
  double fine_volume_fraction = 0.4;  // of the solid, the fine's share after its cut
  double fine_d_min = 0.0;            // m
  LabTestKind test = LabTestKind::C29;
  std::string method;
  double coarse_particles = 400;  // about, in the bed: the bed's side from them
  double max_time_s = 2.0;
};
ClassBed blend_bed(const BlendBedSetup& setup);

}  // namespace aggpack
