// calibrate --dem: one contact parameter fitted to one measured density by running the
// scenario's own protocol through the DEM, and the checks that refuse, before any run, what one
// measurement cannot fix.
#include "aggpack/studies/dem_calibration.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <set>

#include "aggpack/core/error.hpp"
#include "aggpack/core/version.hpp"
#include "aggpack/run/protocol.hpp"
#include "aggpack/studies/campaign.hpp"

namespace aggpack {

std::string material_key(const std::string& parameter) {
  return parameter == "friction" ? "friction_particle" : parameter;
}

namespace {

struct Bracket {
  double value, mean, standard_error;
};

// Where the line through the bracket's two ends meets `target`.
double crossing(const Bracket& a, const Bracket& b, double target) {
  if (a.mean == b.mean) return 0.5 * (a.value + b.value);
  return a.value + (target - a.mean) * (b.value - a.value) / (b.mean - a.mean);
}

std::string format_value(double v) {
  return fmt::format("{:.6g}", v);
}

}  // namespace

CrossingSearch find_crossing(const std::function<SimulatedDensities(double)>& density, double low, double high,
                             double target, int max_evaluations, const std::string& parameter) {
  CrossingSearch search;
  const auto evaluate = [&](double value) {
    search.evaluations.push_back({value, density(value)});
    const SimulatedDensities& d = search.evaluations.back().density;
    return Bracket{value, d.mean, d.standard_error};
  };
  Bracket a = evaluate(low), b = evaluate(high);  // a: the denser end, b: the looser
  // Beyond an end by more than its noise: no value of the range reaches the measurement.
  if (target > a.mean + a.standard_error)
    throw InputError(
        fmt::format("the measured density {:.4f} is above the simulated {:.4f} (+- {:.4f}) at {} = {:g}, "
                    "the densest end of the range: {}",
                    target, a.mean, a.standard_error, parameter, low,
                    low > 0.0 ? "lower the range's low end (--range), or the protocol packs looser than "
                                "the lab's (a denser fill, taps)"
                              : "no value of this lever reaches it; the protocol packs looser than the "
                                "lab's (a denser fill, taps), or another lever is too high"));
  if (target < b.mean - b.standard_error)
    throw InputError(
        fmt::format("the measured density {:.4f} is below the simulated {:.4f} (+- {:.4f}) at {} = {:g}, "
                    "the loosest end of the range: raise the range's high end (--range), or the "
                    "grains pack denser than this lever can loosen them",
                    target, b.mean, b.standard_error, parameter, high));
  // Illinois regula falsi: an end kept twice in a row has its distance to the target halved,
  // so that the bracket closes from both sides.
  double weight_a = 1.0, weight_b = 1.0;
  int kept = 0;  // +1: a kept (b moved) last time; -1: b kept
  for (int k = 2; k < max_evaluations; ++k) {
    if (std::abs(a.mean - target) <= a.standard_error || std::abs(b.mean - target) <= b.standard_error) {
      search.converged = true;
      break;
    }
    const double fa = weight_a * (a.mean - target), fb = weight_b * (b.mean - target);
    double x = a.value - fa * (b.value - a.value) / (fb - fa);
    // Never at an end: a tenth of the bracket from either.
    const double margin = 0.1 * (b.value - a.value);
    x = std::clamp(x, a.value + margin, b.value - margin);
    const Bracket m = evaluate(x);
    if (m.mean >= target) {  // still denser than measured: the crossing lies above x
      a = m, weight_a = 1.0;
      weight_b = kept == -1 ? 0.5 * weight_b : 1.0;
      kept = -1;
    } else {
      b = m, weight_b = 1.0;
      weight_a = kept == 1 ? 0.5 * weight_a : 1.0;
      kept = 1;
    }
  }
  if (!search.converged)
    search.converged = std::abs(a.mean - target) <= a.standard_error || std::abs(b.mean - target) <= b.standard_error;
  search.value = std::clamp(crossing(a, b, target), low, high);
  const double noise = std::max(a.standard_error, b.standard_error);
  const double x1 = crossing(a, b, target - noise), x2 = crossing(a, b, target + noise);
  search.band_low = std::min(x1, x2), search.band_high = std::max(x1, x2);
  search.band_clipped = search.band_low < low || search.band_high > high;
  search.band_low = std::clamp(search.band_low, low, high);
  search.band_high = std::clamp(search.band_high, low, high);
  return search;
}

namespace {

bool has_dem_step(const Protocol& protocol) {
  return std::any_of(protocol.steps.begin(), protocol.steps.end(), [](const Step& s) {
    return std::holds_alternative<PourStep>(s.kind) || std::holds_alternative<SettleStep>(s.kind) ||
           std::holds_alternative<TapStep>(s.kind) || std::holds_alternative<RodStep>(s.kind) ||
           std::holds_alternative<JigStep>(s.kind);
  });
}

// The scenario key of material k's `parameter`: material.rolling_friction, materials.sand.friction_particle.
std::string key_of(const Scenario& sc, std::size_t k, const std::string& parameter) {
  return fmt::format("{}.{}", k == 0 ? std::string("material") : "materials." + material_name(sc, k),
                     material_key(parameter));
}

// Nothing else gives the fitted materials' parameter a value the fit would not move: a
// [[material_pairs]] entry of a pair of the bed, or the scenario's own calibrated_by.
void check_nothing_else_sets(const Scenario& sc, const std::vector<std::size_t>& fitted, const std::string& parameter) {
  const std::vector<std::size_t> used = used_materials(sc);
  const bool from_file = sc.particles.file.has_value();
  const auto in = [](const std::vector<std::size_t>& list, std::size_t k) {
    return std::find(list.begin(), list.end(), k) != list.end();
  };
  for (const MaterialPairCoefficients& pair : sc.material_pairs) {
    // A pair of the bed (both materials in it) with a fitted material.
    const bool occurs = from_file || (in(used, pair.first) && in(used, pair.second));
    const bool fitted_pair = occurs && (in(fitted, pair.first) || in(fitted, pair.second));
    const auto& given = parameter == "friction" ? pair.friction : pair.rolling_friction;
    if (fitted_pair && given)
      throw InputError(
          fmt::format("{}: [[material_pairs]] sets the {} of {} and {}, which the fit of {} would not "
                      "move: leave that pair to the mixing rule, or fit another parameter",
                      sc.file.string(), parameter, material_name(sc, pair.first), material_name(sc, pair.second),
                      material_key(parameter)));
  }
  // A key the scenario's own calibration already sets cannot be fitted again on top of it.
  for (const std::size_t k : fitted) {
    const std::string key = key_of(sc, k, parameter);
    for (const DemCalibrationFile& c : sc.calibrations)
      for (const std::string& a : c.assignments)
        if (a.starts_with(key + "="))
          throw InputError(
              fmt::format("{}: its calibrated_by {} already sets {}: calibrate the scenario without that "
                          "file",
                          sc.file.string(), c.file.string(), key));
  }
}

// The materials whose value is fitted, checked against the scenario: each one of its
// materials, some component made of it, and no [[material_pairs]] entry overriding the fitted
// parameter for a pair of it (the fit would not move that pair).
std::vector<std::size_t> fitted_materials(const Scenario& sc, const DemCalibrationOptions& options,
                                          const std::string& parameter) {
  std::vector<std::string> names;
  for (std::size_t k = 0; k < material_count(sc); ++k) names.push_back(material_name(sc, k));
  const std::vector<std::size_t> used = used_materials(sc);
  std::vector<std::string> used_names;
  for (const std::size_t k : used) used_names.push_back(names[k]);
  std::vector<std::size_t> fitted;
  // A bed read from a file takes its materials from the file's column: any of the scenario's may be in it.
  const bool from_file = sc.particles.file.has_value();
  if (options.materials.empty() && from_file && names.size() > 1)
    throw InputError(
        fmt::format("{}: the bed's materials come from its particle file: name the one to fit "
                    "(--materials NAME; the scenario's materials: {})",
                    sc.file.string(), fmt::join(names, ", ")));
  if (options.materials.empty()) {
    if (used.size() > 1)
      throw InputError(fmt::format(
          "{}: the bed is made of {} materials ({}): one measured density cannot fix the {} of each. Name the one "
          "to fit (--materials {}; the others keep the scenario's values, from the literature or their own "
          "calibration), or fit one value for all (--materials {} --shared)",
          sc.file.string(), used.size(), fmt::join(used_names, ", "), parameter, used_names.back(),
          fmt::join(used_names, ",")));
    fitted = used;
  } else {
    for (const std::string& name : options.materials) {
      const auto at = std::find(names.begin(), names.end(), name);
      if (at == names.end())
        throw InputError(fmt::format("--materials {}: not a material of {} (its materials: {})", name, sc.file.string(),
                                     fmt::join(names, ", ")));
      const auto k = static_cast<std::size_t>(at - names.begin());
      if (!from_file && std::find(used.begin(), used.end(), k) == used.end())
        throw InputError(
            fmt::format("--materials {}: no component of {} is made of it, so its {} does not move the "
                        "bed (the bed's materials: {})",
                        name, sc.file.string(), parameter, fmt::join(used_names, ", ")));
      if (std::find(fitted.begin(), fitted.end(), k) == fitted.end()) fitted.push_back(k);
    }
    if (fitted.size() > 1 && !options.shared)
      throw InputError(fmt::format(
          "--materials {}: one measured density cannot fix {} unknowns (the {} of each). Fit one of them (the others "
          "keep the scenario's values), calibrate each on a measurement of its own component alone, or fit one "
          "value for all of them (--shared)",
          fmt::join(options.materials, ","), fitted.size(), parameter));
  }
  check_nothing_else_sets(sc, fitted, parameter);
  return fitted;
}

// The value of `parameter` of material k in a scenario.
double parameter_of(const Scenario& sc, std::size_t k, const std::string& parameter) {
  const ContactParameters& c = material_of(sc, k).contact;
  return parameter == "friction" ? c.friction_particle : c.rolling_friction;
}

// The fit moves the fitted materials only: a named material that takes the key from [material]
// (it does not set it) would move with a fit of `default`.
void check_others_kept(const Scenario& sc, const Scenario& moved, const std::vector<std::size_t>& fitted,
                       const std::string& parameter) {
  for (const std::size_t k : used_materials(sc))
    if (std::find(fitted.begin(), fitted.end(), k) == fitted.end() &&
        parameter_of(sc, k, parameter) != parameter_of(moved, k, parameter))
      throw InputError(
          fmt::format("{}: [materials.{}] takes its {} from [material], so fitting default would move "
                      "it too: give [materials.{}] its own {}, or fit both (--materials default,{} "
                      "--shared)",
                      sc.file.string(), material_name(sc, k), material_key(parameter), material_name(sc, k),
                      material_key(parameter), material_name(sc, k)));
}

// The scenario keys that give the fitted materials `value`.
std::vector<std::string> assignments_for(const Scenario& sc, const std::vector<std::size_t>& fitted,
                                         const std::string& parameter, double value) {
  std::vector<std::string> out;
  for (const std::size_t k : fitted) out.push_back(key_of(sc, k, parameter) + "=" + format_value(value));
  return out;
}

// The options' own refusals, before the scenario is read: the parameter fitted and the range searched.
std::vector<double> checked_range(const DemCalibrationOptions& options) {
  if (options.fit.size() != 1)
    throw InputError(
        fmt::format("--fit {}: one measured density cannot fix {} unknowns: fit one parameter (the "
                    "other keeps the scenario's value), or calibrate on a second measurement",
                    fmt::join(options.fit, ","), options.fit.size()));
  const std::string& parameter = options.fit.front();
  if (parameter != "rolling_friction" && parameter != "friction")
    throw InputError(fmt::format("--fit {}: expected rolling_friction or friction", parameter));
  if (!(options.measured > 0.0 && options.measured < 1.0))
    throw InputError(fmt::format("--measured {}: expected a packing density between 0 and 1", options.measured));
  if (options.runs.seeds < 2 || options.runs.seeds > 100)
    throw InputError(
        fmt::format("--seeds {}: expected 2 to 100 with --dem: the seeds' scatter is the noise the fit's "
                    "band is made of",
                    options.runs.seeds));
  if (options.max_evaluations < 3 || options.max_evaluations > 30)
    throw InputError(fmt::format("--max-runs {}: expected 3 to 30 values", options.max_evaluations));
  const std::vector<double> range =
      options.range.value_or(parameter == "friction" ? std::vector<double>{0.1, 1.0} : std::vector<double>{0.0, 0.5});
  if (range.size() != 2 || !(range[0] >= 0.0 && range[1] > range[0] && std::isfinite(range[1])) ||
      (parameter == "friction" && !(range[0] > 0.0)))
    throw InputError(fmt::format("--range {}: expected LOW,HIGH with 0 {} LOW < HIGH", fmt::join(range, ","),
                                 parameter == "friction" ? "<" : "<="));
  return range;
}

// The runs of every seed checked as `aggpack check` would (their sizes made, their grains
// fitted), before the search's first run: the fitted value changes neither.
void check_every_seed(const Scenario& sc, const CalibrationOptions& runs, const std::string& what, std::ostream& log) {
  Campaign checks(runs.threads, true, log, static_cast<std::size_t>(runs.seeds), Campaign::Checkpoints::removed,
                  Campaign::Mode::check);
  for (int seed = 1; seed <= runs.seeds; ++seed) (void)checks.run(what, sc, static_cast<std::uint64_t>(seed));
}

}  // namespace

DemCalibration calibrate_dem(const DemCalibrationOptions& options, std::ostream& log) {
  // Everything one measurement cannot fix, or the DEM cannot run, is refused before any run.
  const std::vector<double> range = checked_range(options);
  const std::string& parameter = options.fit.front();
  const Scenario sc = load_scenario(options.runs.scenario, options.runs.overrides);
  if (sc.particles.bed_from_caller())
    throw InputError(fmt::format("{}: particles.from = \"-\": a bed given by the library's caller at run time; "
                                 "calibrate --dem runs the scenario again and again from its file: name a particle "
                                 "file or give sizes",
                                 sc.file.string()));
  const Protocol protocol = scenario_protocol(sc);
  if (!has_dem_step(protocol))
    throw InputError(
        fmt::format("{}: its protocol ({}) has no DEM step: friction and rolling friction act only in "
                    "the DEM (give the scenario a [pour], or a [dynamics] settling, or [tapping])",
                    sc.file.string(), fmt::join(protocol.stage_names(), ", ")));
  const std::vector<std::size_t> fitted = fitted_materials(sc, options, parameter);
  const auto scenario_at = [&](double value) {
    ScenarioOverrides o = options.runs.overrides;
    for (const std::string& a : assignments_for(sc, fitted, parameter, value)) {
      o.set.push_back(a);
      o.typed_as[a] = fmt::format("the fit's value ({} = {})", parameter, format_value(value));
    }
    return load_scenario(options.runs.scenario, o);
  };
  for (const double end : range) {  // both ends are scenarios the DEM takes, and move the fitted materials only
    std::optional<Scenario> at_end;
    try {
      at_end = scenario_at(end);
    } catch (const InputError& e) {
      throw InputError(fmt::format("at {} = {:g}, an end of the range (--range): {}", parameter, end, e.what()));
    }
    check_others_kept(sc, *at_end, fitted, parameter);
    check_every_seed(*at_end, options.runs, fmt::format("{} = {}", parameter, format_value(end)), log);
  }

  DemCalibration c;
  c.scenario = sc.file.string();
  c.protocol = fmt::format("{}", fmt::join(protocol.stage_names(), ", "));
  c.parameter = parameter;
  for (const std::size_t k : fitted) c.materials.push_back(material_name(sc, k));
  c.measured = options.measured;
  c.seeds = static_cast<std::uint64_t>(options.runs.seeds);
  c.range_low = range[0], c.range_high = range[1];
  Campaign campaign(options.runs.threads, options.runs.quiet, log,
                    static_cast<std::size_t>(options.max_evaluations) * static_cast<std::size_t>(options.runs.seeds));
  const auto density = [&](double value) {
    const Scenario at = scenario_at(value);
    const std::string what = fmt::format("{} = {}", parameter, format_value(value));
    std::vector<double> per_seed;
    for (int seed = 1; seed <= options.runs.seeds; ++seed) {
      const CaseRun run = campaign.run(what, at, static_cast<std::uint64_t>(seed), [&](const CaseRun& r) {
        return fmt::format("  calibrate --dem: {}, seed {}: density {:.4f}", what, seed, r.final_density());
      });
      per_seed.push_back(run.final_density());
    }
    return simulated_densities(what, per_seed);
  };
  c.search = find_crossing(density, range[0], range[1], options.measured, options.max_evaluations, parameter);
  campaign.clear_progress();
  c.assignments = assignments_for(sc, fitted, parameter, c.search.value);
  return c;
}

nlohmann::json to_json(const DemCalibration& c) {
  nlohmann::json evaluations = nlohmann::json::array();
  for (const DemEvaluation& e : c.search.evaluations)
    evaluations.push_back({{"value", e.value},
                           {"density_per_seed", e.density.density},
                           {"mean", e.density.mean},
                           {"standard_error", e.density.standard_error}});
  return {{"aggpack_version", kVersion},
          {"kind", kDemCalibrationKind},
          {"scenario_file", c.scenario},
          {"protocol", c.protocol},
          {"seeds", c.seeds},
          {"measured", {{"density", c.measured}, {"of", "the scenario's bed"}}},
          {"fit",
           {{"parameter", c.parameter},
            {"materials", c.materials},
            {"shared", c.materials.size() > 1},
            {"value", c.search.value},
            {"band", {c.search.band_low, c.search.band_high}},
            {"band_clipped_at_range", c.search.band_clipped},
            {"converged", c.search.converged},
            {"range", {c.range_low, c.range_high}},
            {"search",
             "regula falsi (Illinois) on the seed mean, the same seeds for every value; the value where the "
             "line between the last bracket's ends meets the measured density; the band, the same at the "
             "measured density -+ the larger standard error of the two ends' means"}}},
          {"evaluations", evaluations},
          {"assignments", c.assignments}};
}

}  // namespace aggpack
