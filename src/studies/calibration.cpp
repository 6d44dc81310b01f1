#include "aggpack/studies/calibration.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <fmt/ranges.h>

#include "aggpack/core/error.hpp"
#include "aggpack/core/input_file.hpp"
#include "aggpack/core/version.hpp"
#include "aggpack/studies/campaign.hpp"
#include "aggpack/run/generate_sizes.hpp"
#include "aggpack/run/protocol.hpp"
#include "aggpack/run/run.hpp"

namespace aggpack {

CalibratedParameters solve_calibration(const ModelDistribution& mix, double phi_mono, double phi_mix) {
  if (!(phi_mono > 0.0 && phi_mono < 1.0 && phi_mix > 0.0 && phi_mix < 1.0))
    throw InputError(fmt::format("calibration: densities {} and {} are not between 0 and 1", phi_mono, phi_mix));
  // K above phi/(1 - phi) keeps beta = phi (1 + 1/K) below 1; up to 1e4 (beyond, beta = phi).
  const double k_lo = phi_mono / (1.0 - phi_mono) * (1.0 + 1e-9), k_hi = 1e4;
  const auto misfit = [&](double k) {
    const std::vector<double> beta{cpm_beta_from_monosized(phi_mono, k)};
    return cpm(mix, beta, k).density - phi_mix;
  };
  // The first sign change on a logarithmic scan, then bisection.
  const int n = 400;
  double a = k_lo, fa = misfit(a), lowest = fa, highest = fa;
  for (int i = 1; i <= n; ++i) {
    double b = k_lo * std::pow(k_hi / k_lo, static_cast<double>(i) / n);
    const double fb = misfit(b);
    lowest = std::min(lowest, fb), highest = std::max(highest, fb);
    if ((fa <= 0.0) != (fb <= 0.0)) {
      for (int k = 0; k < 200; ++k) {
        const double m = std::sqrt(a * b);
        if (m <= a || m >= b) break;
        const double fm = misfit(m);
        if ((fa <= 0.0) == (fm <= 0.0)) a = m, fa = fm;
        else b = m;
      }
      const double k = std::sqrt(a * b);
      return {k, cpm_beta_from_monosized(phi_mono, k)};
    }
    a = b, fa = fb;
  }
  throw InputError(fmt::format("calibration: with beta from the monosized density {:.4f}, CPM gives the mix densities "
                               "from {:.4f} to {:.4f} for K in [{:.3g}, {:g}], not the simulated {:.4f}: the model "
                               "does not fit these simulations",
                               phi_mono, phi_mix + lowest, phi_mix + highest, k_lo, k_hi, phi_mix));
}

SimulatedDensities simulated_densities(std::string what, std::vector<double> densities) {
  SimulatedDensities s;
  s.what = std::move(what);
  const SeedStatistics stats = seed_statistics(densities);
  s.density = std::move(densities);
  s.mean = stats.mean;
  s.standard_error = stats.count > 1 ? stats.sd / std::sqrt(static_cast<double>(stats.count)) : 0.0;
  return s;
}

Calibration calibrate(const CalibrationOptions& options, std::ostream& log) {
  if (options.seeds < 1 || options.seeds > 100)
    throw InputError(fmt::format("--seeds {}: expected 1 to 100", options.seeds));
  const Scenario sc = load_scenario(options.scenario, options.overrides);
  if (sc.particles.file)
    throw InputError(fmt::format("{}: its particles {}; calibration simulates a monosized bed and the scenario's own "
                                 "sizes, so it needs sizes (classes or a grading)",
                                 sc.file.string(),
                                 sc.particles.bed_from_caller() ? "are a bed given by the caller (particles.from = \"-\")"
                                                                : "come from a file"));
  const ModelDistribution mix =
      predict_scenario(sc, default_model_parameters(false)).distributions.front().classes;
  if (mix.classes.size() < 2)
    throw InputError(fmt::format("{}: one size class: its density gives beta only for a known K; calibrate with a "
                                 "scenario of two sizes or more (a binary mix or a grading)",
                                 sc.file.string()));
  // The monosized bed: the coarsest class, the same solid volume, the same protocol.
  const double d = mix.classes.front().diameter;
  double solid = 0.0;
  for (const double x : generate_sizes(sc.particles, sc.seed).diameters) solid += x * x * x;
  Scenario mono = sc;
  mono.particles.graded.reset();
  SizeSpec spec;
  spec.classes.push_back({d, static_cast<std::size_t>(std::llround(solid / (d * d * d))), std::nullopt});
  mono.particles.sizes = spec;

  const Protocol protocol = scenario_protocol(sc);
  std::vector<double> mono_densities, mix_densities;
  const std::string mono_text =
      fmt::format("monosized (d = {:.4g} m, {} spheres)", d, spec.classes[0].count.value_or(0));
  Campaign campaign(options.threads, options.quiet, log, 2 * static_cast<std::size_t>(options.seeds));
  for (int seed = 1; seed <= options.seeds; ++seed) {
    for (const Scenario* s : std::array<const Scenario*, 2>{&mono, &sc}) {
      const std::string what = s == &mono ? mono_text : std::string("the scenario's mix");
      const CaseRun c = campaign.run(what, *s, static_cast<std::uint64_t>(seed), [&](const CaseRun& r) {
        return fmt::format("  calibrate: seed {} {}: density {:.4f}", seed, what, r.result.report.final.density.mean);
      });
      (s == &mono ? mono_densities : mix_densities).push_back(c.result.report.final.density.mean);
    }
  }
  campaign.clear_progress();
  Calibration c;
  c.scenario = sc.file.string();
  c.protocol = fmt::format("{}", fmt::join(protocol.stage_names(), ", "));
  c.seeds = static_cast<std::uint64_t>(options.seeds);
  c.monosized = simulated_densities(fmt::format("monosized, d = {:.6g} m", d), mono_densities);
  c.mix = simulated_densities("the scenario's mix", mix_densities);
  const CalibratedParameters best = solve_calibration(mix, c.monosized.mean, c.mix.mean);
  c.compaction_index = best.compaction_index;
  c.beta = best.beta;
  c.compaction_low = c.compaction_high = best.compaction_index;
  c.beta_low = c.beta_high = best.beta;
  // The band: the densities one standard error either way, in all four pairings.
  for (const double m : {-1.0, 1.0})
    for (const double x : {-1.0, 1.0}) {
      try {
        const CalibratedParameters p = solve_calibration(mix, c.monosized.mean + m * c.monosized.standard_error,
                                                         c.mix.mean + x * c.mix.standard_error);
        c.compaction_low = std::min(c.compaction_low, p.compaction_index);
        c.compaction_high = std::max(c.compaction_high, p.compaction_index);
        c.beta_low = std::min(c.beta_low, p.beta);
        c.beta_high = std::max(c.beta_high, p.beta);
      } catch (const InputError&) {
        c.compaction_high = std::numeric_limits<double>::infinity();  // no fit at that corner: unbounded
      }
    }
  return c;
}

nlohmann::json to_json(const Calibration& c) {
  const auto densities = [](const SimulatedDensities& s) {
    return nlohmann::json{{"what", s.what}, {"density_per_seed", s.density}, {"mean", s.mean},
                          {"standard_error", s.standard_error}};
  };
  const auto finite = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
  return {{"aggpack_version", kVersion},
          {"kind", "aggpack CPM calibration"},
          {"scenario_file", c.scenario},
          {"protocol", c.protocol},
          {"seeds", c.seeds},
          {"monosized", densities(c.monosized)},
          {"mix", densities(c.mix)},
          {"cpm",
           {{"compaction_index", c.compaction_index},
            {"compaction_index_range", {finite(c.compaction_low), finite(c.compaction_high)}},
            {"residual_packing_density", c.beta},
            {"residual_packing_density_range", {finite(c.beta_low), finite(c.beta_high)}}}}};
}

}  // namespace aggpack
