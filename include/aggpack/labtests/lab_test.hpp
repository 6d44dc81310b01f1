#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "aggpack/io/material_file.hpp"
#include "aggpack/labtests/standards.hpp"
#include "aggpack/studies/campaign.hpp"

namespace aggpack {

// `aggpack test c29|c1252 MATERIAL --method M` (README, "The lab's tests, simulated"): the
// standard's test of one aggregate, simulated in the standard's measure by its procedure, over
// seeds. A test is a scenario aggpack writes (scenario.toml in the output folder: the user can
// read it, change it and run it with `aggpack run`), made of the material's file and the
// standard's numbers, run by the run engine like any other.
enum class LabTestKind { C29, C1252 };
inline constexpr std::array kLabTestNames{EnumName<LabTestKind>{LabTestKind::C29, "c29"},
                                          EnumName<LabTestKind>{LabTestKind::C1252, "c1252"}};

struct LabTestOptions {
  std::filesystem::path material;
  LabTestKind test = LabTestKind::C29;
  std::string method;                 // C29: shovelling, rodding, jigging; C1252: A, B, C
  int seeds = 3;
  int threads = 0;
  bool quiet = false;
  std::vector<std::string> set;       // --set assignments applied to the test's scenario
  double finest_size_m = 0.0;         // cut-off of fines (m); 0: the test's default
  // C1252: the most particles a simulated measure holds: a cylinder that would hold more is
  // simulated as a representative one, smaller in the same proportions (LabTestPart::scale).
  // C29's measure is always the standard's (a smaller one would change what the rod does).
  double max_particles = kDefaultMaxParticles;
  static constexpr double kDefaultMaxParticles = 50000;
};

// One simulated test (C29, C1252 A or C) or one of C1252 B's three fractions.
struct LabTestPart {
  std::string label;          // "ASTM C29 rodding", "ASTM C1252 B, 1.18-2.36 mm"
  std::string scenario_text;  // what is run, seed by seed
  double measure_diameter_m = 0.0, measure_height_m = 0.0;  // the standard's measure
  // The measure simulated: the standard's (scale 1), or a representative one, the standard's
  // scaled by `scale` < 1 in diameter and height, whose content is read as the full measure's
  // (LabTestPartResult::packing).
  double simulated_diameter_m = 0.0, simulated_height_m = 0.0;
  double scale = 1.0;
  double full_size_particles = 0.0;  // expected in the standard's measure
  double largest_size_m = 0.0;       // of the particles simulated
  double cut_off_m = 0.0;           // finer material left out (0: none)
  double cut_off_percent = 0.0;     // of the mass
};

// What a test will simulate, known before any run: `plan_lab_test` checks the material, the
// method and the sizes against the standard and refuses (InputError) what it does not define.
struct LabTestPlan {
  AggregateMaterial material;
  LabTestKind test = LabTestKind::C29;
  std::string method;               // the standard's name of it
  std::string standard;             // "ASTM C29/C29M-17a", ...
  double nominal_maximum_size_m = 0.0;
  std::string measure_name;         // "1/3 ft3 (9.3 L)", "C1252 cylinder (100 mL)"
  std::vector<LabTestPart> parts;   // C1252 B: three; else one
  // The grains' own solid over the spheres of their sizes (1 for spheres): the amount of grains
  // generated is divided by it, the generator counting each grain as the sphere of its size.
  double grain_volume_ratio = 1.0;
  std::vector<std::string> modelling;  // every modelling choice, said in the outputs
};
LabTestPlan plan_lab_test(const LabTestOptions& options);

// Where a part's time went, summed over its seeds (wall clock, s): BENCHMARKS.md's breakdown.
struct LabTestTiming {
  double sizes_s = 0.0, grains_s = 0.0;  // drawing the sizes; the grains' templates
  double pour_s = 0.0;                   // the DEM of the pours and their settling
  double rodding_s = 0.0, jigging_s = 0.0;
  double analysis_s = 0.0;
  std::size_t dem_steps = 0;  // of every DEM stage
  std::size_t spheres = 0;    // of the last seed's bed (a grain's members each one)
  double simulated_s = 0.0;   // of every DEM stage
};

// A part's result over the seeds: the packing fraction of the struck-off measure's content.
struct LabTestPartResult {
  std::string label;
  // Per seed, the standard measure's content struck off by an exact cut at the rim. A
  // representative measure's reads as the full measure's: the walls' loss of density is a layer
  // of the same loss per unit area at any size, so in measures of the same proportions it falls
  // as 1 / size: packing = core - (core - simulated) x scale.
  std::vector<double> packing;
  std::vector<double> packing_whole;      // the same, the particles whose centre is below the rim counted whole
  std::vector<double> packing_simulated;  // per seed, the simulated measure's own content (exact cut)
  std::vector<double> packing_core;       // per seed, its core: farther than one largest particle from the wall
  std::vector<std::size_t> particles;
  SeedStatistics packing_stats, packing_whole_stats;
  double wall_clock_s = 0.0;
  LabTestTiming timing;
};

// The test's answer, in the lab's units.
struct LabTestResult {
  LabTestPlan plan;
  std::vector<std::uint64_t> seeds;
  std::vector<LabTestPartResult> parts;
  SeedStatistics packing;                 // of the test (C1252 B: the mean of the parts, per seed)
  double bulk_density_kg_m3 = 0.0;        // C29: packing x oven-dry particle density
  double bulk_density_sd_kg_m3 = 0.0;
  double voids_percent = 0.0, voids_sd_percent = 0.0;  // C29's voids, C1252's U
  std::optional<double> lab_value;        // the material file's measurement of this test and method
  double wall_clock_s = 0.0;
};

// Runs the plan's parts over seeds 1..N through `campaign` (numbered, timed, in memory).
LabTestResult run_lab_test(const LabTestOptions& options, std::ostream& log);
LabTestResult run_lab_test(const LabTestPlan& plan, const LabTestOptions& options, Campaign& campaign);

nlohmann::json to_json(const LabTestResult& result);
// The console's lines: the test, the measure, the answer with its spread, the lab's value.
std::string describe(const LabTestResult& result);

}  // namespace aggpack
