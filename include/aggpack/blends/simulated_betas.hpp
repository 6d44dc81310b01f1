#pragma once
// The simulation route to a material's betas: each of its sieve fractions poured alone, with
// its grains, its (calibrated) contact values and its lab test's procedure, in a periodic bed
// (labtests/class_bed.hpp); each class's beta from its beds' packing through CPM's relation for
// one class, beta = phi (1 + 1/K), at the procedure's K. Kept in a cache beside the material
// file, keyed by aggpack's build, the material and the settings: with it warm, nothing is
// simulated again.
#include <filesystem>
#include <optional>
#include <ostream>
#include <string>

#include "aggpack/blends/material_betas.hpp"
#include "aggpack/labtests/lab_test.hpp"

namespace aggpack {

struct SimulatedBetaOptions {
  std::filesystem::path material;
  int seeds = 3;
  int threads = 0;
  double particles = 3000;  // about, in each bed
  // Classes finer than this (m) are not simulated: they take the finest simulated class's beta
  // (a bed of 0.1 mm grains costs as many steps as ten of 10 mm ones; they are a few % of a sand).
  double finest_simulated_m = 0.3e-3;
  // The beds' procedure for every material ("c29:shovelling", "c1252:A"); empty: each
  // material's own (bed_procedure).
  std::string procedure;
  // The cache's folder (default: the material file's): the cache is <folder>/<stem>.betas.json.
  std::optional<std::filesystem::path> cache_folder;
  bool quiet = false;
};

// The test and method the beds follow: the material's calibration's, else its lab number's, else
// C29 shovelling (the loose procedure; said in the betas' modelling).
struct BedProcedure {
  LabTestKind test = LabTestKind::C29;
  std::string method = "shovelling";
  std::string why;  // "calibrated on it", "its lab number's", "no test named: the loose procedure"
};
BedProcedure bed_procedure(const AggregateMaterial& material);
// The options' procedure when they name one (InputError for a test or method that is not one),
// else the material's own.
BedProcedure bed_procedure(const AggregateMaterial& material, const SimulatedBetaOptions& options);

// What the cache is keyed by: the build (kVersion), the material as read (every value, the
// calibrated contact values included, but not its path or comments) and the settings.
nlohmann::json beta_cache_key(const AggregateMaterial& material, const SimulatedBetaOptions& options);
[[nodiscard]] std::filesystem::path beta_cache_file(const SimulatedBetaOptions& options);

// The cache (<stem>.betas.json) holds entries, each betas and the key they were made with: one
// for each of this build's settings of the material (a --check's cut of it beside its whole).
// The cache's betas when it holds this key; none (and why, in `stale`) when it holds none of
// this key or does not exist. InputError naming the file when it exists but cannot be read as a cache
// (damaged): never a silently different curve.
std::optional<MaterialBetas> read_beta_cache(const std::filesystem::path& file, const nlohmann::json& key,
                                             std::string& stale);

// Writes the cache (atomically): this entry, the key, the betas and what the beds cost, beside
// the entries of this build and material with other settings (the others are dropped).
void write_beta_cache(const std::filesystem::path& file, const nlohmann::json& key, const MaterialBetas& betas,
                      double wall_clock_s);

// The betas: from the cache when it is warm; else simulated (the beds, through the campaign
// runner, progress on `log`) and the cache written (atomically). `log` says which, and why a
// cache was rebuilt.
MaterialBetas simulated_betas(const SimulatedBetaOptions& options, std::ostream& log);

}  // namespace aggpack
