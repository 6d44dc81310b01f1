// The blends asked of material files: the routes, the betas, the curves and their modelling.
#include "aggpack/blends/blend_request.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <optional>
#include <sstream>

#include "aggpack/core/error.hpp"

namespace aggpack {

namespace {

// The route a material takes: auto's choice, or the one asked.
BetaRoute route_of(const std::string& asked, const AggregateMaterial& m) {
  if (asked == "lab") return BetaRoute::LabTest;
  if (asked == "simulation") return BetaRoute::Simulation;
  return m.calibration.is_null() ? BetaRoute::LabTest : BetaRoute::Simulation;
}

SimulatedBetaOptions beds_of(const BlendRequest& r, const std::filesystem::path& file) {
  SimulatedBetaOptions o = r.beds;
  o.material = file;
  return o;
}

// The simulation route's betas from the cache alone; none when it is cold.
std::optional<MaterialBetas> cached_betas(const BlendRequest& r, const std::filesystem::path& file,
                                          const AggregateMaterial& m) {
  const SimulatedBetaOptions o = beds_of(r, file);
  std::string stale;
  return read_beta_cache(beta_cache_file(o), beta_cache_key(m, o), stale);
}

// A material's betas by `route`; without simulation, a cold cache falls back to the lab route
// (auto) with `note` saying so.
MaterialBetas betas_of(const BlendRequest& r, const std::filesystem::path& file, BetaRoute route,
                       std::vector<std::string>& notes, std::ostream& log) {
  const AggregateMaterial m = load_material_file(file);
  if (route == BetaRoute::LabTest) return lab_route_betas(m);
  if (r.may_simulate) return simulated_betas(beds_of(r, file), log);
  if (auto cached = cached_betas(r, file, m)) return *cached;
  if (r.route == "simulation" || !(m.c29 || m.c1252))
    throw InputError(fmt::format(
        "{}: its betas by simulation are not in the cache ({}), and a prediction simulates nothing: run aggpack "
        "blend on it once (minutes) with the same settings{}",
        file.string(), beta_cache_file(beds_of(r, file)).string(),
        m.c29 || m.c1252 ? ", or ask for the lab route" : ", or give it a lab number ([c29] or [c1252])"));
  notes.push_back(
      fmt::format("{}: calibrated, but its simulated betas are not in the cache for these bed settings ({} seeds, "
                  "{:g} particles a bed): its lab number's betas instead (aggpack blend simulates them once)",
                  m.name, r.beds.seeds, r.beds.particles));
  return lab_route_betas(m);
}

BlendCurve curve(const BlendRequest& r, const std::vector<BetaRoute>& routes, std::vector<std::string>& notes,
                 std::ostream& log) {
  BlendCurve c;
  for (std::size_t i = 0; i < r.materials.size(); ++i)
    c.materials.push_back(betas_of(r, r.materials[i], routes[i], notes, log));
  const auto taken = [&](BetaRoute route) {
    return std::all_of(c.materials.begin(), c.materials.end(),
                       [&](const MaterialBetas& m) { return m.route == route; });
  };
  c.route = taken(BetaRoute::LabTest) ? "lab_test" : taken(BetaRoute::Simulation) ? "simulation" : "mixed";
  if (!r.sweep_percents.empty()) {
    c.points = sweep_binary(c.materials, r.sweep_percents, r.process.compaction_index, r.interaction);
    c.densest = densest(c.points);
  }
  for (const std::vector<double>& f : r.fractions)
    c.points.push_back(predict_blend(c.materials, f, r.process.compaction_index, r.interaction));
  return c;
}

std::string interaction_words(const CpmInteraction& e) {
  const CpmInteraction published;
  if (e.loosening_exponent == published.loosening_exponent && e.wall_exponent == published.wall_exponent)
    return fmt::format("at their published exponents ({:g}, {:g})", e.loosening_exponent, e.wall_exponent);
  return fmt::format("at exponents {:g} and {:g} (asked for, not de Larrard's)", e.loosening_exponent, e.wall_exponent);
}

}  // namespace

TestProcess blend_process(const std::string& name, const std::string& option) {
  const std::string model = name == "loose" ? "poured" : name;
  const auto k = compaction_index_of(model);
  if (!k || model == "vibrated_compressed")
    throw InputError(fmt::format("{} {}: expected loose, rodded or vibrated", option, name));
  return {model, *k};
}

void check_blend_request(const BlendRequest& r) {
  if (r.materials.empty()) throw InputError("no material: expected one material file or more");
  if (!r.sweep_percents.empty() && r.materials.size() != 2)
    throw InputError(fmt::format("a sweep takes two materials, {} given", r.materials.size()));
  if (r.route != "auto" && r.route != "lab" && r.route != "simulation")
    throw InputError(fmt::format("route {}: expected auto, lab or simulation", r.route));
  for (const std::filesystem::path& file : r.materials) {
    const AggregateMaterial m = load_material_file(file);
    if (route_of(r.route, m) == BetaRoute::LabTest) lab_route_betas(m);  // refuses a material without a number
  }
  for (const std::vector<double>& f : r.fractions) check_volume_fractions(r.materials.size(), f);
  for (const double pc : r.sweep_percents)
    if (!(pc >= 0.0 && pc <= 100.0)) throw InputError(fmt::format("a sweep's {} % is not between 0 and 100", pc));
}

BlendResult predict_blends(const BlendRequest& r, std::ostream& log) {
  const auto start = std::chrono::steady_clock::now();
  check_blend_request(r);
  BlendResult out;
  out.process = r.process;
  out.sweep = !r.sweep_percents.empty();
  std::vector<BetaRoute> routes;
  bool all_have_lab = true;
  for (const std::filesystem::path& file : r.materials) {
    const AggregateMaterial m = load_material_file(file);
    routes.push_back(route_of(r.route, m));
    all_have_lab = all_have_lab && (m.c29 || m.c1252);
  }
  out.curves.push_back(curve(r, routes, out.modelling, log));
  const bool simulated = out.curves.front().route != "lab_test";
  if (simulated && all_have_lab)  // the lab route beside it: what the simulation adds
    out.curves.push_back(curve(r, std::vector<BetaRoute>(routes.size(), BetaRoute::LabTest), out.modelling, log));
  out.modelling.push_back(fmt::format(
      "CPM (de Larrard 1999): every class of every material at its own beta, its loosening and wall effects {}; the "
      "packing of a bulk bed (no container wall) at K {:g} ({})",
      interaction_words(r.interaction), r.process.compaction_index, r.process.name));
  out.modelling.push_back(
      "volume percent: of the blend's solid (absolute volumes); mass percent from the oven-dry "
      "particle densities; bulk density oven-dry");
  out.wall_clock_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

MaterialsCurve lab_route_curve(const std::filesystem::path& coarse, const std::filesystem::path& fine,
                               const std::string& process, double from, double to) {
  BlendRequest r;
  r.materials = {coarse, fine};
  for (double pc = from; pc <= to + 1e-9; pc += 1.0) r.sweep_percents.push_back(pc);
  r.process = blend_process(process, "process");
  r.route = "lab";
  std::ostringstream quiet;
  const BlendCurve c = predict_blends(r, quiet).curves.front();
  MaterialsCurve out{c.materials.at(0).material,
                     c.materials.at(1).material,
                     r.process.name,
                     r.process.compaction_index,
                     {},
                     r.sweep_percents,
                     {}};
  for (const MaterialBetas& m : c.materials) out.betas.push_back(fmt::format("{}: {}", m.material, m.source));
  for (const BlendPoint& p : c.points) out.packing.push_back(p.packing);
  return out;
}

}  // namespace aggpack
