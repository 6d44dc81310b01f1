// A blend's prediction against the DEM of the blend.
#include "aggpack/blends/blend_check.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "aggpack/blends/blend.hpp"
#include "aggpack/core/error.hpp"
#include "aggpack/labtests/class_bed.hpp"

namespace aggpack {

namespace {
constexpr double kMm = 1e-3;
}  // namespace

MaterialBetas cut_below(const MaterialBetas& b, double d_min) {
  if (!(d_min > 0.0)) return b;
  MaterialBetas out = b;
  out.classes.clear();
  double total = 0.0;
  for (ClassBeta c : b.classes) {
    if (c.d_hi <= d_min * (1.0 + 1e-12)) continue;
    if (c.d_lo < d_min) {
      c.volume_fraction *= std::log(c.d_hi / d_min) / std::log(c.d_hi / c.d_lo);
      c.d_lo = d_min;
      c.diameter = std::sqrt(c.d_lo * c.d_hi);
    }
    total += c.volume_fraction;
    out.classes.push_back(c);
  }
  if (out.classes.empty() || !(total > 0.0))
    throw InputError(
        fmt::format("{}: nothing of {} is coarser than {:g} mm", b.file.string(), b.material, d_min / kMm));
  for (ClassBeta& c : out.classes) c.volume_fraction /= total;
  out.source += fmt::format("; cut at {:g} mm", d_min / kMm);
  return out;
}

double BlendCheck::largest_difference() const {
  double worst = 0.0;
  for (const BlendCheckPoint& p : points) worst = std::max(worst, std::abs(p.predicted - p.simulated.mean));
  return worst;
}

BlendCheck check_blend(const BlendCheckOptions& o, std::ostream& log) {
  const AggregateMaterial coarse = load_material_file(o.coarse), fine = load_material_file(o.fine);
  if (o.percents.empty()) throw InputError("--check: no points; expected fine volume percents, e.g. 30,40");
  for (const double pc : o.percents)
    if (!(pc > 0.0 && pc < 100.0))
      throw InputError(fmt::format("--check {}: expected a percent between 0 and 100", pc));
  const BedProcedure procedure = bed_procedure(coarse, o.betas), fine_procedure = bed_procedure(fine, o.betas);
  if (procedure.test != fine_procedure.test || procedure.method != fine_procedure.method)
    throw InputError(
        fmt::format("--check: {} is filled by {} {} and {} by {} {}; a blend bed has one procedure: "
                    "expected materials calibrated on the same test and method",
                    o.coarse.string(), name_of(kLabTestNames, procedure.test), procedure.method, o.fine.string(),
                    name_of(kLabTestNames, fine_procedure.test), fine_procedure.method));
  BlendCheck check;
  // Every bed planned (and its scenario read) before any simulation.
  std::vector<ClassBed> beds;
  for (const double pc : o.percents)
    beds.push_back(
        blend_bed({&coarse, &fine, pc / 100.0, o.fine_d_min, procedure.test, procedure.method, o.coarse_particles}));
  const auto scenario_of = [&](std::size_t i) {
    return parse_scenario(
        beds[i].scenario_text,
        o.coarse.parent_path() / fmt::format("blend bed, {:g} % {}", o.percents[i], o.fine.filename().string()));
  };
  for (std::size_t i = 0; i < beds.size(); ++i) scenario_of(i);

  SimulatedBetaOptions b = o.betas;
  b.material = o.coarse;
  check.coarse = simulated_betas(b, log);
  b.material = o.fine;
  b.finest_simulated_m = std::max(b.finest_simulated_m, o.fine_d_min);  // what the cut leaves out is not needed
  check.fine = cut_below(simulated_betas(b, log), o.fine_d_min);
  check.process = procedure.test == LabTestKind::C1252 ? c1252_process()
                                                       : c29_process(*value_of(kC29MethodNames, procedure.method));
  check.procedure = beds.front().procedure;
  check.interaction = o.interaction;
  check.modelling = beds.front().modelling;
  check.modelling.erase(std::remove_if(check.modelling.begin(), check.modelling.end(),
                                       [](const std::string& m) { return m.rfind("the bed:", 0) == 0; }),
                        check.modelling.end());
  check.modelling.push_back(fmt::format("CPM at K {:g} ({}), the K of the beds' procedure",
                                        check.process.compaction_index, check.process.name));
  Campaign campaign(b.threads, b.quiet, log, beds.size() * static_cast<std::size_t>(b.seeds));
  for (std::size_t i = 0; i < beds.size(); ++i) {
    BlendCheckPoint p;
    p.percent = o.percents[i];
    for (int seed = 1; seed <= b.seeds; ++seed) {
      const CaseRun run =
          campaign.run(fmt::format("blend {:g} %", p.percent), scenario_of(i), static_cast<std::uint64_t>(seed));
      p.packing.push_back(run.final_density());
      p.particles = run.particle_count;
      p.wall_clock_s += run.result.wall_clock_s;
    }
    p.simulated = seed_statistics(p.packing);
    check.points.push_back(std::move(p));
  }
  predict_again(check, o.interaction);  // CPM beside each point: nothing from the beds enters it
  return check;
}

namespace {
// CPM at a checked point's blend, with `interaction`.
BlendPoint predicted_at(const BlendCheck& c, const BlendCheckPoint& p, const CpmInteraction& interaction) {
  const MaterialBetas pair[2] = {c.coarse, c.fine};
  const double fractions[2] = {1.0 - p.percent / 100.0, p.percent / 100.0};
  return predict_blend(pair, fractions, c.process.compaction_index, interaction);
}
}  // namespace

void predict_again(BlendCheck& c, const CpmInteraction& interaction) {
  c.interaction = interaction;
  for (BlendCheckPoint& p : c.points) {
    const BlendPoint b = predicted_at(c, p, interaction);
    p.predicted = b.packing;
    p.predicted_low = b.packing_low;
    p.predicted_high = b.packing_high;
    p.predicted_published = predicted_at(c, p, {}).packing;
  }
}

BlendCheck read_blend_check(const nlohmann::json& j, const CpmInteraction& interaction,
                            const std::filesystem::path& file) {
  try {
    BlendCheck c;
    c.process = {j.at("process").get<std::string>(), j.at("compaction_index").get<double>()};
    c.procedure = j.at("procedure").get<std::string>();
    c.coarse = material_betas_from_json(j.at("coarse"));
    c.fine = material_betas_from_json(j.at("fine"));
    c.modelling = j.at("modelling").get<std::vector<std::string>>();
    for (const nlohmann::json& p : j.at("points")) {
      BlendCheckPoint point;
      point.percent = p.at("fine_volume_percent").get<double>();
      point.packing = p.at("simulated").get<std::vector<double>>();
      point.simulated = seed_statistics(point.packing);
      point.particles = p.at("particles").get<std::size_t>();
      point.wall_clock_s = p.at("wall_clock_s").get<double>();
      if (point.packing.empty() || !(point.percent > 0.0 && point.percent < 100.0))
        throw std::runtime_error("a point without a simulated packing or a percent outside (0, 100)");
      c.points.push_back(std::move(point));
    }
    predict_again(c, interaction);
    return c;
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(
        fmt::format("{}: not a blend check as aggpack blend --check writes it ({})", file.string(), e.what()));
  }
}

double largest_difference(std::span<const BlendCheck> checks, const CpmInteraction& interaction) {
  double worst = 0.0;
  for (const BlendCheck& c : checks)
    for (const BlendCheckPoint& p : c.points)
      worst = std::max(worst, std::abs(predicted_at(c, p, interaction).packing - p.simulated.mean));
  return worst;
}

CpmInteraction fit_interaction(std::span<const BlendCheck> checks) {
  std::size_t points = 0;
  for (const BlendCheck& c : checks) points += c.points.size();
  if (points == 0) throw InputError("fitting CPM's interaction: no checked blend");
  // A coarse grid in log of each exponent, then three finer grids around the best.
  CpmInteraction best;
  double best_error = largest_difference(checks, best);
  double lo_l = std::log(0.02), hi_l = std::log(3.0), lo_w = std::log(0.1), hi_w = std::log(6.0);
  for (int level = 0; level < 4; ++level) {
    constexpr int kSteps = 24;
    for (int i = 0; i <= kSteps; ++i)
      for (int j = 0; j <= kSteps; ++j) {
        const CpmInteraction x{std::exp(lo_l + (hi_l - lo_l) * i / kSteps),
                               std::exp(lo_w + (hi_w - lo_w) * j / kSteps)};
        const double e = largest_difference(checks, x);
        if (e < best_error) best_error = e, best = x;
      }
    // The next grid: four steps either side of the best.
    const double step_l = 4.0 * (hi_l - lo_l) / kSteps, step_w = 4.0 * (hi_w - lo_w) / kSteps;
    lo_l = std::log(best.loosening_exponent) - step_l, hi_l = std::log(best.loosening_exponent) + step_l;
    lo_w = std::log(best.wall_exponent) - step_w, hi_w = std::log(best.wall_exponent) + step_w;
  }
  return best;
}

nlohmann::json to_json(const BlendCheck& c) {
  nlohmann::json points = nlohmann::json::array();
  for (const BlendCheckPoint& p : c.points)
    points.push_back({{"fine_volume_percent", p.percent},
                      {"simulated", p.packing},
                      {"simulated_mean", p.simulated.mean},
                      {"simulated_sd", std::isnan(p.simulated.sd) ? 0.0 : p.simulated.sd},
                      {"predicted", p.predicted},
                      {"predicted_low", p.predicted_low},
                      {"predicted_high", p.predicted_high},
                      {"predicted_published_interaction", p.predicted_published},
                      {"difference", p.predicted - p.simulated.mean},
                      {"particles", p.particles},
                      {"wall_clock_s", p.wall_clock_s}});
  return {{"process", c.process.name},
          {"compaction_index", c.process.compaction_index},
          {"procedure", c.procedure},
          {"interaction",
           {{"loosening_exponent", c.interaction.loosening_exponent}, {"wall_exponent", c.interaction.wall_exponent}}},
          {"coarse", to_json(c.coarse)},
          {"fine", to_json(c.fine)},
          {"points", points},
          {"largest_difference", c.largest_difference()},
          {"modelling", c.modelling}};
}

std::string describe(const BlendCheck& c) {
  std::string out = fmt::format("\ncheck against the DEM of the blend ({} beds; CPM at K {:g}, {}):\n", c.procedure,
                                c.process.compaction_index, c.process.name);
  out += fmt::format("  interaction exponents: loosening {:.4g}, wall {:.4g}{}\n", c.interaction.loosening_exponent,
                     c.interaction.wall_exponent,
                     c.interaction.loosening_exponent == CpmInteraction{}.loosening_exponent &&
                             c.interaction.wall_exponent == CpmInteraction{}.wall_exponent
                         ? " (de Larrard's)"
                         : "");
  out += fmt::format("  {:>8} {:>18} {:>10} {:>11} {:>10} {:>10}\n", "fine %", "simulated", "predicted", "difference",
                     "published", "particles");
  for (const BlendCheckPoint& p : c.points)
    out += fmt::format("  {:>8.1f} {:>9.4f} +- {:<6.4f} {:>10.4f} {:>+11.4f} {:>10.4f} {:>10}\n", p.percent,
                       p.simulated.mean, std::isnan(p.simulated.sd) ? 0.0 : p.simulated.sd, p.predicted,
                       p.predicted - p.simulated.mean, p.predicted_published, p.particles);
  out += fmt::format("  largest difference {:.4f}\n", c.largest_difference());
  for (const std::string& m : c.modelling) out += fmt::format("  - {}\n", m);
  return out;
}

}  // namespace aggpack
