// The simulation route: a material's sieve fractions in periodic beds, their betas, the cache.
#include "aggpack/blends/simulated_betas.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <sstream>

#include "aggpack/core/error.hpp"
#include "aggpack/core/version.hpp"
#include "aggpack/io/atomic_file.hpp"
#include "aggpack/labtests/class_bed.hpp"
#include "aggpack/studies/campaign.hpp"

namespace aggpack {

namespace {

constexpr double kMm = 1e-3;
constexpr const char* kCacheKind = "aggpack betas";

TestProcess process_of(const BedProcedure& p) {
  if (p.test == LabTestKind::C1252) return c1252_process();
  return c29_process(*value_of(kC29MethodNames, p.method));
}

nlohmann::json settings_json(const SimulatedBetaOptions& o, const BedProcedure& p) {
  return {{"seeds", o.seeds},
          {"particles_per_bed", o.particles},
          {"finest_simulated_m", o.finest_simulated_m},
          {"test", name_of(kLabTestNames, p.test)},
          {"method", p.method}};
}

}  // namespace

BedProcedure bed_procedure(const AggregateMaterial& m) {
  if (m.calibration.is_object() && m.calibration.contains("test") && m.calibration.contains("method")) {
    const std::string test = m.calibration["test"].get<std::string>();
    if (const auto kind = value_of(kLabTestNames, test))
      return {*kind, m.calibration["method"].get<std::string>(), "the test it was calibrated on"};
  }
  if (m.c29) return {LabTestKind::C29, std::string(name_of(kC29MethodNames, m.c29->method)), "its lab number's test"};
  if (m.c1252)
    return {LabTestKind::C1252, std::string(name_of(kC1252MethodNames, m.c1252->method)), "its lab number's test"};
  return {LabTestKind::C29, "shovelling",
          "no test named, the material having no calibration and no lab number: C29's loose procedure"};
}

BedProcedure bed_procedure(const AggregateMaterial& m, const SimulatedBetaOptions& o) {
  if (o.procedure.empty()) return bed_procedure(m);
  const std::size_t colon = o.procedure.find(':');
  const std::string test = o.procedure.substr(0, colon),
                    method = colon == std::string::npos ? "" : o.procedure.substr(colon + 1);
  const auto kind = value_of(kLabTestNames, test);
  const bool known = kind && (*kind == LabTestKind::C29 ? value_of(kC29MethodNames, method).has_value()
                                                        : value_of(kC1252MethodNames, method).has_value());
  if (!known)
    throw InputError(
        fmt::format("--beds {}: expected c29:shovelling, c29:rodding, c29:jigging, c1252:A, c1252:B or "
                    "c1252:C",
                    o.procedure));
  return {*kind, method, "asked for (--beds)"};
}

nlohmann::json beta_cache_key(const AggregateMaterial& m, const SimulatedBetaOptions& o) {
  nlohmann::json material = to_json(m);
  for (const char* k : {"file", "notes", "lab", "name"}) material.erase(k);
  if (material["grading"].is_object()) material["grading"].erase("file");
  return {{"aggpack_version", kVersion}, {"material", material}, {"settings", settings_json(o, bed_procedure(m, o))}};
}

std::filesystem::path beta_cache_file(const SimulatedBetaOptions& o) {
  const std::filesystem::path name = o.material.stem().string() + ".betas.json";
  return o.cache_folder ? *o.cache_folder / name : o.material.parent_path() / name;
}

namespace {

// The cache's entries, every one's key checked for its three parts: std::exception otherwise.
nlohmann::json cache_entries(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  const nlohmann::json j = nlohmann::json::parse(text.str());
  if (j.at("kind").get<std::string>() != kCacheKind) throw std::runtime_error("not a betas cache");
  const nlohmann::json& entries = j.at("entries");
  if (!entries.is_array() || entries.empty()) throw std::runtime_error("no entries");
  for (const nlohmann::json& e : entries)
    for (const char* part : {"aggpack_version", "material", "settings"}) (void)e.at("key").at(part);
  return entries;
}

InputError damaged(const std::filesystem::path& file, const std::exception& e) {
  return InputError(
      fmt::format("{}: a damaged betas cache ({}); expected what aggpack blend writes: remove it to "
                  "simulate the betas again",
                  file.string(), e.what()));
}

}  // namespace

std::optional<MaterialBetas> read_beta_cache(const std::filesystem::path& file, const nlohmann::json& key,
                                             std::string& stale) {
  if (!std::filesystem::exists(file)) {
    stale = "no cache yet";
    return std::nullopt;
  }
  try {
    const nlohmann::json entries = cache_entries(file);
    for (const nlohmann::json& e : entries)
      if (e.at("key") == key) return material_betas_from_json(e.at("betas"));
    // Why not: against the newest entry.
    const nlohmann::json& had = entries.back().at("key");
    for (const char* part : {"aggpack_version", "material", "settings"})
      if (had.at(part) != key.at(part)) {
        stale = std::string(part) == "aggpack_version"
                    ? fmt::format("made by aggpack {}, this is {}", had.at(part).get<std::string>(),
                                  key.at(part).get<std::string>())
                    : fmt::format("its {} changed", part);
        break;
      }
    return std::nullopt;
  } catch (const std::exception& e) {
    throw damaged(file, e);
  }
}

void write_beta_cache(const std::filesystem::path& file, const nlohmann::json& key, const MaterialBetas& betas,
                      double wall_clock_s) {
  // Kept beside the new entry: those of this build and material with other settings (a check's
  // cut, other seeds); an older build's or another material's are rebuilt, never reused.
  nlohmann::json entries = nlohmann::json::array();
  if (std::filesystem::exists(file)) {
    try {
      for (const nlohmann::json& e : cache_entries(file))
        if (e.at("key").at("aggpack_version") == key.at("aggpack_version") &&
            e.at("key").at("material") == key.at("material") && e.at("key") != key)
          entries.push_back(e);
    } catch (const std::exception& e) {
      throw damaged(file, e);
    }
  }
  entries.push_back({{"key", key}, {"betas", to_json(betas)}, {"wall_clock_s", wall_clock_s}});
  const nlohmann::json cache{{"kind", kCacheKind}, {"entries", entries}};
  write_file_atomically(file, cache.dump(1) + "\n");
}

namespace {

// A size class of the material, and its bed when it is simulated.
struct PlannedClass {
  ModelClass size;
  std::optional<ClassBed> bed;
};

Scenario bed_scenario(const PlannedClass& p, const SimulatedBetaOptions& o) {
  return parse_scenario(p.bed->scenario_text,
                        o.material.parent_path() / fmt::format("{} ({:g}-{:g} mm bed)", o.material.filename().string(),
                                                               p.size.d_lo / kMm, p.size.d_hi / kMm));
}

// Every class's bed, its scenario read: all checked before any runs.
std::vector<PlannedClass> plan_class_beds(const AggregateMaterial& m, const SimulatedBetaOptions& o,
                                          const BedProcedure& procedure) {
  std::vector<PlannedClass> planned;
  for (const ModelClass& c : grading_classes(m.grading.grading).classes) {
    PlannedClass p{c, std::nullopt};
    if (c.d_hi > o.finest_simulated_m * (1.0 + 1e-9)) {  // a class ending at the cut is not simulated
      p.bed = class_bed({&m, c.d_lo, c.d_hi, procedure.test, procedure.method, o.particles});
      bed_scenario(p, o);
    }
    planned.push_back(std::move(p));
  }
  if (std::none_of(planned.begin(), planned.end(), [](const PlannedClass& p) { return p.bed.has_value(); }))
    throw InputError(fmt::format("{}: no size class above the finest simulated size {:g} mm", o.material.string(),
                                 o.finest_simulated_m / kMm));
  return planned;
}

// One class's beds over the seeds: its packings and its beta.
ClassBeta run_class_beds(const PlannedClass& p, const SimulatedBetaOptions& o, const TestProcess& process,
                         Campaign& campaign) {
  ClassBeta k{p.size.d_lo, p.size.d_hi, p.size.diameter, p.size.volume_fraction, 0.0, 0.0, {}};
  if (!p.bed) return k;
  std::vector<double> betas;
  for (int seed = 1; seed <= o.seeds; ++seed) {
    const CaseRun run = campaign.run(fmt::format("{:g}-{:g} mm", p.size.d_lo / kMm, p.size.d_hi / kMm),
                                     bed_scenario(p, o), static_cast<std::uint64_t>(seed));
    k.packing.push_back(run.final_density());
    betas.push_back(cpm_beta_from_monosized(run.final_density(), process.compaction_index));
  }
  const SeedStatistics s = seed_statistics(betas);
  k.beta = s.mean;
  k.beta_sd = s.sd;
  return k;
}

// What the betas rest on, said once each.
void add_modelling(MaterialBetas& out, const std::vector<PlannedClass>& planned, const SimulatedBetaOptions& o,
                   const AggregateMaterial& m) {
  std::vector<std::string> procedures;
  for (const PlannedClass& p : planned) {
    if (!p.bed) continue;
    for (const std::string& note : p.bed->modelling)
      if (std::find(out.modelling.begin(), out.modelling.end(), note) == out.modelling.end() &&
          note.rfind("the bed:", 0) != 0)
        out.modelling.push_back(note);
    procedures.push_back(fmt::format("{:g}-{:g} mm {}", p.size.d_lo / kMm, p.size.d_hi / kMm, p.bed->procedure));
  }
  out.modelling.push_back(fmt::format("the beds: {}", fmt::join(procedures, "; ")));
  out.modelling.push_back(
      fmt::format("each bed periodic (no wall), about {:.0f} particles, its packing read in the "
                  "largest cube clear of the floor and the surface",
                  o.particles));
  if (procedures.size() < planned.size())
    out.modelling.push_back(
        fmt::format("classes finer than {:g} mm not simulated: they take the finest simulated "
                    "class's beta",
                    o.finest_simulated_m / kMm));
  if (m.calibration.is_null())
    out.modelling.push_back("the material is not calibrated: its contact values are the file's own");
}

}  // namespace

namespace {
// InputError naming the folder when the cache could not be written there.
void check_cache_writable(const std::filesystem::path& cache) {
  const std::filesystem::path folder = cache.parent_path().empty() ? "." : cache.parent_path();
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  const std::filesystem::path probe = cache.string() + ".aggpack-probe";
  if (!error && std::ofstream(probe).good()) {
    std::filesystem::remove(probe, error);
    return;
  }
  throw InputError(
      fmt::format("{}: the betas' cache cannot be written in {}; expected a folder aggpack may write "
                  "(--betas-cache DIR)",
                  cache.string(), folder.string()));
}
}  // namespace

MaterialBetas simulated_betas(const SimulatedBetaOptions& o, std::ostream& log) {
  if (o.seeds < 2 || o.seeds > 100) throw InputError(fmt::format("--seeds {}: expected 2 to 100", o.seeds));
  if (!(o.particles >= 200.0 && o.particles <= 1e7))
    throw InputError(fmt::format("--bed-particles {}: expected 200 to 1e7", o.particles));
  const AggregateMaterial m = load_material_file(o.material);
  const nlohmann::json key = beta_cache_key(m, o);
  const std::filesystem::path cache = beta_cache_file(o);
  std::string stale;
  if (std::optional<MaterialBetas> warm = read_beta_cache(cache, key, stale)) {
    if (!o.quiet) log << fmt::format("aggpack: {}: betas from the cache {}\n", m.name, cache.string());
    warm->file = o.material;
    return *warm;
  }
  if (!o.quiet) log << fmt::format("aggpack: {}: simulating the betas ({}: {})\n", m.name, cache.string(), stale);
  check_cache_writable(cache);  // before hours of beds, not after

  const BedProcedure procedure = bed_procedure(m, o);
  const TestProcess process = process_of(procedure);
  const std::vector<PlannedClass> planned = plan_class_beds(m, o, procedure);
  const auto beds = static_cast<std::size_t>(
      std::count_if(planned.begin(), planned.end(), [](const PlannedClass& p) { return p.bed.has_value(); }));
  MaterialBetas out;
  out.file = o.material;
  out.material = m.name;
  out.route = BetaRoute::Simulation;
  out.particle_density_kg_m3 = oven_dry_particle_density(m);
  Campaign campaign(o.threads, o.quiet, log, beds * static_cast<std::size_t>(o.seeds));
  for (const PlannedClass& p : planned) out.classes.push_back(run_class_beds(p, o, process, campaign));
  // The classes not simulated take the nearest coarser simulated class's beta (and spread).
  for (std::size_t i = out.classes.size(); i-- > 0;)
    if (!planned[i].bed)
      for (std::size_t j = i; j-- > 0;)
        if (planned[j].bed) {
          out.classes[i].beta = out.classes[j].beta;
          out.classes[i].beta_sd = out.classes[j].beta_sd;
          break;
        }
  out.source = fmt::format(
      "simulated: each sieve fraction alone in a periodic bed, {} seeds, by ASTM {} {} ({}); "
      "beta = phi (1 + 1/K) at K {:g} ({})",
      o.seeds, procedure.test == LabTestKind::C29 ? "C29" : "C1252", procedure.method, procedure.why,
      process.compaction_index, process.name);
  add_modelling(out, planned, o, m);
  write_beta_cache(cache, key, out, campaign.seconds());
  if (!o.quiet) log << fmt::format("aggpack: {}: betas written to {}\n", m.name, cache.string());
  return out;
}

}  // namespace aggpack
