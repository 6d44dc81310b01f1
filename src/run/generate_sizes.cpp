#include "aggpack/run/generate_sizes.hpp"

#include <algorithm>
#include <numbers>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/core/rng.hpp"
#include "aggpack/run/grading_report.hpp"

namespace aggpack {

namespace {
double volume(double d) { return std::numbers::pi / 6.0 * d * d * d; }

SizesComponent component_report(const GradingSource& source, const GradingCut& cut,
                                const std::vector<double>& diameters) {
  return {source.key, source.grading.name, cut, report_generated(diameters, cut), source.band};
}

nlohmann::json to_json(const SizesComponent& c) {
  nlohmann::json j;
  j["key"] = c.key;
  j["grading"] = c.grading;
  j["d_lo_m"] = c.cut.d_lo;
  j["d_hi_m"] = c.cut.d_hi;
  j["cut_below_fraction"] = c.cut.cut_below;
  j["cut_above_fraction"] = c.cut.cut_above;
  j["renormalisation"] = "proportional";
  j["count"] = c.generated.count;
  j["solid_volume_m3"] = c.generated.solid_volume;
  j["largest_deviation_percent"] = c.generated.largest_deviation;
  j["snapped_sieves"] = snapped_sieves_json(c.cut.grading);
  j["sieves"] = nlohmann::json::array();
  for (const GradingReportRow& row : c.generated.rows)
    j["sieves"].push_back({{"sieve", row.sieve.name},
                           {"opening_m", row.sieve.opening},
                           {"target_percent", row.sieve.percent_passing},
                           {"generated_percent", row.generated}});
  if (c.band) j["band"] = band_check_json(*c.band, check_against_band(c.cut.grading, *c.band));
  return j;
}

std::string cut_note(const GradingSource& source, const GradingCut& cut) {
  const std::string snapped = snapped_sieves_text(source.grading.snapped);
  return fmt::format("{} ({}): sizes {:.4g} to {:.4g} mm generated; {:.2f} % of the volume finer and {:.2f} % coarser "
                     "was cut off and the rest renormalised proportionally{}",
                     source.key, source.grading.name, cut.d_lo * 1e3, cut.d_hi * 1e3, 100 * cut.cut_below,
                     100 * cut.cut_above, snapped.empty() ? "" : "; " + snapped);
}
}  // namespace

nlohmann::json to_json(const SizesReport& r) {
  nlohmann::json j{{"method", r.method}, {"count", r.count}};
  if (r.sampling) {
    const GradingReport& all = r.whole;
    j["sampling"] = name_of(kSamplingModeNames, *r.sampling);
    j["within_interval"] = *r.sampling == SamplingMode::Mass
                               ? "volume uniform in log diameter (as the curve between sieves)"
                               : "uniform in diameter by number (the paper's Eq. 11)";
    j["solid_volume_m3"] = all.solid_volume;
    j["d_min_m"] = all.d_min;
    j["d_max_m"] = all.d_max;
    j["d10_m"] = all.d10;
    j["d50_m"] = all.d50;
    j["d90_m"] = all.d90;
    j["fineness_modulus"] = all.fineness_modulus;
    j["components"] = nlohmann::json::array();
    for (const SizesComponent& c : r.components) j["components"].push_back(to_json(c));
  }
  if (r.order) {
    j["order"] = name_of(kMixOrderNames, *r.order);
    j["ca_fa_requested"] = r.ca_fa_requested;
    j["ca_fa_generated"] = r.ca_fa_generated;
  }
  return j;
}

double expected_particle_count(const ParticleSource& source) { return expected_amount(source).particles; }

namespace {

bool is_grain_component(const ParticleSource& source, std::size_t c) {
  return c < source.component_shape.size() && source.component_shape[c].has_value();
}

// The spheres one particle of component c is made of: a grain's members, or itself.
double spheres_of_component(const ParticleSource& source, std::size_t c) {
  return is_grain_component(source, c) ? static_cast<double>(source.component_shape[c]->spheres) : 1.0;
}

double most_spheres_of_a_component(const ParticleSource& source) {
  double most = 1.0;
  for (std::size_t c = 0; c < source.component_shape.size(); ++c) most = std::max(most, spheres_of_component(source, c));
  return most;
}

}  // namespace

ExpectedAmount expected_amount(const ParticleSource& source) {
  ExpectedAmount amount;
  const double most = most_spheres_of_a_component(source);
  const auto add_component = [&](double count, std::size_t c) {
    const double spheres = spheres_of_component(source, c);
    amount.particles += count;
    amount.spheres += count * spheres;
    if (is_grain_component(source, c)) amount.grains += count;
  };
  const auto add_unknown_split = [&](double count) {
    amount.particles += count;
    amount.spheres += count * most;
    if (source.has_grains()) amount.grains += count;
  };
  if (source.sizes) {
    const SizeSpec& spec = *source.sizes;
    if (spec.total_count) {
      add_unknown_split(static_cast<double>(*spec.total_count));
      return amount;
    }
    for (std::size_t k = 0; k < spec.classes.size(); ++k) {
      const SizeClass& c = spec.classes[k];
      if (c.count) add_component(static_cast<double>(*c.count), k);
      if (c.volume_fraction)
        add_component(spec.solid_volume.value_or(0.0) * *c.volume_fraction / volume(c.diameter), k);
    }
    return amount;
  }
  if (!source.graded) return amount;
  const GradedParticles& g = *source.graded;
  if (g.amount.count) {
    add_unknown_split(static_cast<double>(*g.amount.count));
    return amount;
  }
  const double solid = g.amount.solid_volume.value_or(0.0);
  const double main = GradingSampler(cut_grading(g.main.grading, g.main.d_min, g.main.d_max, g.main.key), g.sampling)
                          .mean_particle_volume();
  if (!g.fine) {
    add_component(solid / main, 0);
    return amount;
  }
  const double fine =
      GradingSampler(cut_grading(g.fine->grading, g.fine->d_min, g.fine->d_max, g.fine->key), g.sampling)
          .mean_particle_volume();
  add_component(solid / (1.0 + g.ca_fa) * g.ca_fa / main, 0);
  add_component(solid / (1.0 + g.ca_fa) / fine, 1);
  return amount;
}

ExpectedAmount drawn_amount(const ParticleSource& source, const GeneratedSizes& sizes) {
  ExpectedAmount amount;
  for (const std::int32_t c : sizes.component) {
    const auto component = static_cast<std::size_t>(c);
    amount.particles += 1.0;
    amount.spheres += spheres_of_component(source, component);
    if (is_grain_component(source, component)) amount.grains += 1.0;
  }
  return amount;
}

GeneratedSizes generate_sizes(const ParticleSource& source, std::uint64_t seed) {
  GeneratedSizes out;
  Rng rng = make_rng(seed, RngPurpose::Sizes);
  if (source.sizes) {
    out.diameters = generate_diameters(*source.sizes, rng);
    // The class of each diameter: the first listed with that diameter (two classes of one
    // diameter are one size).
    out.component.reserve(out.diameters.size());
    const auto& classes = source.sizes->classes;
    for (const double d : out.diameters) {
      const auto k = std::find_if(classes.begin(), classes.end(), [d](const auto& c) { return c.diameter == d; });
      out.component.push_back(static_cast<std::int32_t>(k - classes.begin()));
    }
    out.report.method = "classes";
    out.report.count = out.diameters.size();
  } else {
    const GradedParticles& g = *source.graded;
    const GradingCut main_cut = cut_grading(g.main.grading, g.main.d_min, g.main.d_max, g.main.key);
    const GradingSampler main(main_cut, g.sampling);
    out.report.sampling = g.sampling;
    out.notes.push_back(cut_note(g.main, main_cut));
    if (g.sampling == SamplingMode::Number)
      out.notes.push_back("sizes sampled by number (the paper's Eq. 11): percent passing read as a number "
                          "fraction, which generates far too few fines by volume; see sizes.components[].sieves");
    if (g.fine) {
      const GradingCut fine_cut = cut_grading(g.fine->grading, g.fine->d_min, g.fine->d_max, g.fine->key);
      const GradingSampler fine(fine_cut, g.sampling);
      std::vector<std::uint8_t> is_fine;
      out.diameters = sample_mix(main, fine, g.ca_fa, g.amount, g.order, rng, &is_fine);
      out.component.assign(is_fine.begin(), is_fine.end());
      std::vector<double> coarse_d, fine_d;
      for (std::size_t i = 0; i < out.diameters.size(); ++i)
        (is_fine[i] ? fine_d : coarse_d).push_back(out.diameters[i]);
      double vc = 0.0, vf = 0.0;
      for (double d : coarse_d) vc += volume(d);
      for (double d : fine_d) vf += volume(d);
      out.report.method = "mix";
      out.report.order = g.order;
      out.report.ca_fa_requested = g.ca_fa;
      out.report.ca_fa_generated = vf > 0 ? vc / vf : 0.0;
      out.report.components = {component_report(g.main, main_cut, coarse_d),
                               component_report(*g.fine, fine_cut, fine_d)};
      out.notes.push_back(cut_note(*g.fine, fine_cut));
    } else {
      out.diameters = sample_diameters(main, g.amount, rng);
      out.component.assign(out.diameters.size(), 0);
      out.report.method = "grading";
      out.report.components = {component_report(g.main, main_cut, out.diameters)};
    }
    if (g.fill_height)
      out.notes.push_back(fmt::format("the amount was set to fill {:.4g} m at an expected density of {:g}: "
                                      "solid volume {:.4g} m^3",
                                      *g.fill_height, g.expected_density, *g.amount.solid_volume));
    // The whole sample (both components of a mix) as one curve.
    out.report.whole = report_generated(out.diameters, main_cut);
    out.report.count = out.report.whole.count;
  }
  return out;
}

std::vector<std::uint8_t> sphere_materials(const ParticleSource& source, const GeneratedSizes& sizes) {
  const std::vector<std::uint8_t>& of_component = source.component_material;
  if (std::all_of(of_component.begin(), of_component.end(), [](std::uint8_t m) { return m == 0; })) return {};
  std::vector<std::uint8_t> materials;
  materials.reserve(sizes.component.size());
  for (const std::int32_t c : sizes.component) materials.push_back(of_component.at(static_cast<std::size_t>(c)));
  return materials;
}

}  // namespace aggpack
