#include "aggpack/run/run_grains.hpp"

#include <algorithm>
#include <iterator>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/core/rng.hpp"

namespace aggpack {

LibraryWatch templates_shown_on(Progress& progress, const StopRequest* stop) {
  progress.start_stage("grain templates");
  return {stop, [&progress](std::size_t drawn, std::size_t expected) {
            progress.update({fmt::format("template {} of at most {}", drawn, expected)},
                            static_cast<double>(drawn) / static_cast<double>(expected));
          }};
}

RunGrains make_run_grains(const ParticleSource& source, const GeneratedSizes& sizes, std::uint64_t seed,
                          const LibraryWatch& watch) {
  RunGrains grains;
  if (!source.has_grains()) return grains;
  const std::size_t components = source.component_shape.size();
  grains.libraries.resize(components);
  // The watch sees the components' draws as one count.
  std::size_t expected = 0, drawn_before = 0;
  for (const auto& spec : source.component_shape)
    if (spec) expected += most_templates_drawn(*spec);
  LibraryWatch component_watch{watch.stop, nullptr};
  if (watch.progress)
    component_watch.progress = [&](std::size_t drawn, std::size_t) { watch.progress(drawn_before + drawn, expected); };
  for (std::size_t c = 0; c < components; ++c) {
    const std::optional<GrainShapeSpec>& spec = source.component_shape[c];
    if (!spec) continue;
    std::vector<double> all;
    for (std::size_t i = 0; i < sizes.diameters.size(); ++i)
      if (static_cast<std::size_t>(sizes.component[i]) == c) all.push_back(sizes.diameters[i]);
    if (all.empty()) continue;
    const std::vector<double> widths = library_fit_sizes(std::move(all));
    try {
      // Each component its own stream of shapes.
      grains.libraries[c] = make_grain_library(*spec, widths, seed * 64 + c, component_watch);
      drawn_before += most_templates_drawn(*spec);
    } catch (const InputError& e) {
      throw InputError(fmt::format("the shape of component {} ({}): {}", c + 1,
                                   c < sizes.report.components.size() ? sizes.report.components[c].key : "a class",
                                   e.what()));
    }
  }
  std::vector<std::size_t> first_shape(components, 0);
  for (std::size_t c = 0; c < components; ++c) {
    first_shape[c] = grains.shapes.size();
    if (!grains.libraries[c]) continue;
    for (const LibraryGrain& g : grains.libraries[c]->grains) {
      grains.shapes.push_back(g.shape());
      grains.shapes.back().id = static_cast<std::uint32_t>(grains.shapes.size() - 1);
      grains.shape_grain.push_back(&g);
      grains.shape_component.push_back(static_cast<std::uint32_t>(c));
    }
  }
  // Each grain a template at random, from its own stream (adding a component's shape moves no size).
  Rng pick = make_rng(seed, RngPurpose::GrainTemplates);
  grains.shape_of.assign(sizes.diameters.size(), -1);
  for (std::size_t i = 0; i < sizes.diameters.size(); ++i) {
    const auto c = static_cast<std::size_t>(sizes.component[i]);
    if (c >= components || !grains.libraries[c]) continue;
    grains.shape_of[i] = static_cast<std::int32_t>(first_shape[c] + pick.below(grains.libraries[c]->grains.size()));
  }
  return grains;
}

nlohmann::json library_json(const GrainLibrary& library) {
  const GrainShapeSpec& spec = library.spec;
  const ProportionDistribution& d = library.distribution;
  nlohmann::json j = {{"family", family_name(spec.family)},
                      {"spheres", spec.spheres},
                      {"templates", spec.templates},
                      {"filling", "tangent spheres, largest gain first (Ferellec and McDowell 2010)"},
                      {"elongation", {{"mean", d.elongation_mean}, {"spread", d.elongation_spread}}},
                      {"flatness", {{"mean", d.flatness_mean}, {"spread", d.flatness_spread}}}};
  if (spec.family == GrainFamily::Angular) j["corners"] = spec.corners;
  if (library.fit) {
    const ShapeTarget& t = *spec.target;
    j["target"] = {{"measure", measure_name(t.measure)}, {"percent", t.percent}};
    if (t.measure == ShapeMeasure::FlatAndElongated) j["target"]["ratio"] = t.ratio;
    j["templates_percent"] = library.fit->achieved_percent;
    j["fitted"] = t.measure == ShapeMeasure::FlakinessIndex ? "flatness mean" : "elongation and flatness means";
  }
  return j;
}

nlohmann::json libraries_json(const RunGrains& grains, const std::vector<SizesComponent>& components) {
  nlohmann::json all = nlohmann::json::array();
  for (std::size_t c = 0; c < grains.libraries.size(); ++c) {
    if (!grains.libraries[c]) continue;
    nlohmann::json j = {{"component", c + 1}};
    if (c < components.size()) j["key"] = components[c].key;
    j.update(library_json(*grains.libraries[c]));
    all.push_back(j);
  }
  return all;
}

std::vector<GrainMeasure> measure_bodies(const ParticleStore& bed) {
  std::vector<GrainMeasure> measures;
  for (std::size_t b = 0; b < bed.bodies.size(); ++b) measures.push_back(measure_body(bed, b));
  return measures;
}

std::vector<SieveInterval> grain_sieve_intervals(const ParticleStore& bed, std::span<const GrainMeasure> measures,
                                                 const std::vector<std::uint32_t>& shape_component,
                                                 const SizesReport& sizes) {
  std::vector<SieveInterval> intervals(bed.bodies.size());
  if (sizes.method == "classes") return intervals;
  for (std::size_t b = 0; b < intervals.size(); ++b) {
    const std::size_t c = shape_component.at(bed.bodies.shape[b]);
    if (c >= sizes.components.size()) continue;
    const std::vector<Sieve>& sieves = sizes.components[c].cut.grading.sieves;  // by opening, ascending
    // The size the grading gave, to the rounding of its measure.
    const double width = measures[b].width * (1.0 - 1e-9);
    const auto passing = std::lower_bound(sieves.begin(), sieves.end(), width,
                                          [](const Sieve& s, double d) { return s.opening < d; });
    if (passing == sieves.end() || passing == sieves.begin()) continue;  // outside the curve's sieves
    intervals[b] = {std::prev(passing)->opening, passing->opening};
  }
  return intervals;
}

nlohmann::json shape_statistics_json(const ShapeStatistics& s) {
  const auto percent = [](const std::optional<double>& p) { return p ? nlohmann::json(*p) : nlohmann::json(nullptr); };
  nlohmann::json j = {{"grains", s.grains}};
  if (s.grains > 0) {
    j["mean_elongation"] = s.mean_elongation;
    j["mean_flatness"] = s.mean_flatness;
  }
  j["flakiness_index_percent"] = percent(s.flakiness_index);
  j["shape_index_percent"] = percent(s.shape_index);
  j["flat_elongated_2_to_1_percent"] = percent(s.flat_elongated_2);
  j["flat_elongated_3_to_1_percent"] = percent(s.flat_elongated_3);
  j["flat_elongated_5_to_1_percent"] = percent(s.flat_elongated_5);
  j["by"] = "mass, as the standards measure; L, I, S the extents of each grain's spheres along its principal axes";
  return j;
}

nlohmann::json bed_grains_json(const nlohmann::json& libraries, const ParticleStore& bed,
                               const std::vector<std::uint32_t>& shape_component) {
  nlohmann::json out = libraries;
  const std::vector<GrainMeasure> measures = measure_bodies(bed);
  for (nlohmann::json& j : out) {
    const auto c = j["component"].get<std::size_t>() - 1;
    std::vector<GrainMeasure> grains;
    for (std::size_t b = 0; b < measures.size(); ++b)
      if (shape_component.at(bed.bodies.shape[b]) == c) grains.push_back(measures[b]);
    j["bed"] = shape_statistics_json(shape_statistics(grains));
  }
  return out;
}

RunGrains::PourPart RunGrains::pour_part(std::span<const double> sieve_radii, std::size_t begin) const {
  PourPart part;
  for (std::size_t k = 0; k < sieve_radii.size(); ++k) {
    const std::int32_t s = empty() ? -1 : shape_of[begin + k];
    if (s < 0) {
      part.radii.push_back(sieve_radii[k]);
      part.shapes.push_back(nullptr);
      continue;
    }
    part.radii.push_back(shape_grain[static_cast<std::size_t>(s)]->reach_for_width(2.0 * sieve_radii[k]));
    part.shapes.push_back(&shapes[static_cast<std::size_t>(s)]);
  }
  return part;
}

void RunGrains::append_spheres(std::span<const double> sieve_radii, std::size_t begin, std::vector<double>& radii,
                               std::vector<std::uint32_t>& grain_of) const {
  const PourPart part = pour_part(sieve_radii, begin);
  for (std::size_t j = 0; j < part.radii.size(); ++j) {
    if (!part.shapes[j]) {
      radii.push_back(part.radii[j]);
      grain_of.push_back(kNoBody);
      continue;
    }
    for (const double member : part.shapes[j]->member_radii) {  // each at its grain's reach, as the pour
      radii.push_back(part.radii[j] * member);
      grain_of.push_back(static_cast<std::uint32_t>(begin + j));
    }
  }
}

}  // namespace aggpack
