#pragma once
// A material as CPM sees it: the residual packing density (beta) of each of its size classes,
// by one of two routes (README, "Blends of materials in seconds"):
//  - the lab route: the material's own C29 or C1252 number inverted through CPM (at the test's
//    compaction index, with the measure's wall effect), one beta for all of its classes, what
//    CPM's practitioners do;
//  - the simulation route: each sieve fraction of the material poured alone, its grains, its
//    contact values and its test's procedure, in a periodic bed; each class's beta from its
//    bed's packing through CPM's relation for one class (simulated_betas.hpp).
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "aggpack/core/enum_names.hpp"
#include "aggpack/io/material_file.hpp"
#include "aggpack/models/packing_models.hpp"

namespace aggpack {

enum class BetaRoute { LabTest, Simulation };
inline constexpr std::array kBetaRouteNames{EnumName<BetaRoute>{BetaRoute::LabTest, "lab_test"},
                                            EnumName<BetaRoute>{BetaRoute::Simulation, "simulation"}};

// One size class of a material: a sieve fraction, its share of the material's solid volume and
// its residual packing density.
struct ClassBeta {
  double d_lo = 0.0, d_hi = 0.0;  // m: the sieves
  double diameter = 0.0;          // m: the equivalent diameter, the geometric mean of the sieves
  double volume_fraction = 0.0;   // of the material's solid
  double beta = 0.0;
  double beta_sd = 0.0;         // over the seeds of its beds; 0 by the lab route
  std::vector<double> packing;  // simulation: the packing fraction of each seed's bed
};

struct MaterialBetas {
  std::filesystem::path file;
  std::string material;  // its name
  BetaRoute route = BetaRoute::LabTest;
  std::string source;                   // what the betas come from, in a sentence
  double particle_density_kg_m3 = 0.0;  // oven-dry (ASTM C127/C128)
  std::vector<ClassBeta> classes;       // coarse to fine
  std::vector<std::string> modelling;   // every modelling choice behind the betas
};

// --- The lab route ---
// CPM's wall effect of a container (de Larrard 1999, section 1.2.5, after Ben-Aim; recalled,
// not read): within d/2 of a wall a class of diameter d packs at k_w times its bulk density, so
// a cylinder of diameter D and height H packs it at beta (1 - (1 - k_w) V_p / V), with the
// perturbed volume V_p / V = 1 - (1 - d / D)^2 (1 - d / (2 H)) (the side and the floor; the
// struck-off top is a cut, not a wall). k_w = 0.88 (de Larrard's value for rounded aggregates,
// recalled; aggpack's own C29 beads lose about twice that, docs/validation.md).
inline constexpr double kContainerWallFactor = 0.88;
[[nodiscard]] double container_perturbed_fraction(double diameter, double measure_diameter, double measure_height);

// The compaction index of a lab test's procedure (de Larrard 1999, Table 1.2): C29 shovelling
// and C1252 (poured through a funnel) 4.1 "poured", C29 rodding 4.5 "rodded", C29 jigging 4.75
// (dropping the measure taken as de Larrard's "vibrated": a choice the output states).
struct TestProcess {
  std::string name;  // "poured", "rodded", "vibrated"
  double compaction_index = 0.0;
};
[[nodiscard]] TestProcess c29_process(C29Method method);
[[nodiscard]] TestProcess c1252_process();

// The material's lab number (C29 if it has one, else C1252) inverted through CPM: the one beta
// that, for every class of the test's sample, in the test's measure at the test's K, gives the
// lab's packing fraction; then that beta for every class of the material's whole grading.
// InputError naming the file when the material has no lab number, or when no beta below 1
// reaches it (a lab packing above CPM's reach at that K).
MaterialBetas lab_route_betas(const AggregateMaterial& material);

// The distribution and the betas of a material alone, for CPM.
ModelDistribution model_distribution(const MaterialBetas& betas);

nlohmann::json to_json(const MaterialBetas& betas);
// What to_json wrote, every field checked: std::exception (nlohmann's, or runtime_error for a
// value out of range or an unknown route) for anything else; its reader names the file.
MaterialBetas material_betas_from_json(const nlohmann::json& json);

}  // namespace aggpack
