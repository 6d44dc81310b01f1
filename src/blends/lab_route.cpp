// The lab route to a material's betas: its C29 or C1252 number read backwards through CPM.
#include <fmt/format.h>

#include <cmath>

#include "aggpack/blends/material_betas.hpp"
#include "aggpack/core/error.hpp"
#include "aggpack/labtests/standards.hpp"

namespace aggpack {

double container_perturbed_fraction(double diameter, double measure_diameter, double measure_height) {
  const double side = std::max(0.0, 1.0 - diameter / measure_diameter);
  const double floor = std::max(0.0, 1.0 - diameter / (2.0 * measure_height));
  return 1.0 - side * side * floor;
}

TestProcess c29_process(C29Method method) {
  switch (method) {
    case C29Method::Shovelling:
      return {"poured", *compaction_index_of("poured")};
    case C29Method::Rodding:
      return {"rodded", *compaction_index_of("rodded")};
    case C29Method::Jigging:
      return {"vibrated", *compaction_index_of("vibrated")};
  }
  return {};
}

TestProcess c1252_process() {
  return {"poured", *compaction_index_of("poured")};
}

namespace {

constexpr double kMm = 1e-3;

// What the lab filled its measure with, and how.
struct LabSample {
  std::vector<ModelDistribution> distributions;  // C1252 B: three, the result their mean; else one
  double measure_diameter_m = 0.0, measure_height_m = 0.0;
  TestProcess process;
  double packing = 0.0;  // the lab's packing fraction
  std::string test;      // "ASTM C29 rodding, 1580 kg/m3 (packing 0.597)"
};

ModelDistribution fractions_distribution(const std::vector<SieveFraction>& fractions, const std::string& name) {
  const Grading g = grading_of_fractions(fractions, name);
  return grading_classes(g, g.smallest());
}

LabSample lab_sample(const AggregateMaterial& m) {
  LabSample s;
  if (m.c29) {
    const Measure measure = c29_measure(nominal_maximum_size(m.grading.grading), m.file.string());
    s.distributions.push_back(grading_classes(m.grading.grading));
    s.measure_diameter_m = measure.diameter_m;
    s.measure_height_m = measure.height_m;
    s.process = c29_process(m.c29->method);
    s.packing = 1.0 - voids_percent(m, m.c29->kg_per_m3) / 100.0;
    s.test = fmt::format("ASTM C29 {}, {:.0f} kg/m3 in the {} measure (packing {:.4f})",
                         name_of(kC29MethodNames, m.c29->method), m.c29->kg_per_m3, measure.name, s.packing);
    return s;
  }
  if (m.c1252) {
    switch (m.c1252->method) {
      case C1252Method::A:
        s.distributions.push_back(fractions_distribution(c1252_method_a_fractions(), "C1252 A"));
        break;
      case C1252Method::B:
        for (const SieveFraction& f : c1252_method_b_fractions())
          s.distributions.push_back(fractions_distribution({f}, "C1252 B"));
        break;
      case C1252Method::C:
        s.distributions.push_back(grading_classes(m.grading.grading, std::nullopt, kC1252MethodCLargest));
    }
    s.measure_diameter_m = kC1252Diameter;
    s.measure_height_m = kC1252Height;
    s.process = c1252_process();
    s.packing = 1.0 - m.c1252->percent / 100.0;
    s.test = fmt::format("ASTM C1252 method {}, uncompacted voids {:.1f} % (packing {:.4f})",
                         name_of(kC1252MethodNames, m.c1252->method), m.c1252->percent, s.packing);
    return s;
  }
  throw InputError(
      fmt::format("{}: the material has no lab number ([lab.c29] or [lab.c1252]); the lab route needs "
                  "one (or calibrate the material and take the simulation route)",
                  m.file.string()));
}

// The sample's packing in its measure when every class has residual packing density `beta`.
double sample_packing(const LabSample& s, double beta) {
  double sum = 0.0;
  for (const ModelDistribution& d : s.distributions) {
    std::vector<double> in_measure;
    for (const ModelClass& c : d.classes)
      in_measure.push_back(
          beta * (1.0 - (1.0 - kContainerWallFactor) *
                            container_perturbed_fraction(c.diameter, s.measure_diameter_m, s.measure_height_m)));
    sum += cpm(d, in_measure, s.process.compaction_index).density;
  }
  return sum / static_cast<double>(s.distributions.size());
}

constexpr double kHighestBeta = 0.99;

}  // namespace

MaterialBetas lab_route_betas(const AggregateMaterial& m) {
  const LabSample s = lab_sample(m);
  double lo = 0.05, hi = kHighestBeta;
  const double reach = sample_packing(s, hi);
  if (s.packing >= reach)
    throw InputError(
        fmt::format("{}: {}: CPM at K {:g} reaches at most {:.4f} in that measure (beta {:g}); the lab's "
                    "number is out of the model's reach",
                    m.file.string(), s.test, s.process.compaction_index, reach, kHighestBeta));
  if (s.packing <= sample_packing(s, lo))
    throw InputError(
        fmt::format("{}: {}: a packing this loose needs a beta below {:g}; expected a lab number of a "
                    "granular bed",
                    m.file.string(), s.test, lo));
  for (int it = 0; it < 200 && hi - lo > 1e-12; ++it) {
    const double mid = 0.5 * (lo + hi);
    (sample_packing(s, mid) < s.packing ? lo : hi) = mid;
  }
  const double beta = 0.5 * (lo + hi);

  MaterialBetas out;
  out.file = m.file;
  out.material = m.name;
  out.route = BetaRoute::LabTest;
  out.source = fmt::format("{} read backwards through CPM: one beta {:.4f} for every class", s.test, beta);
  out.particle_density_kg_m3 = oven_dry_particle_density(m);
  for (const ModelClass& c : grading_classes(m.grading.grading).classes)
    out.classes.push_back({c.d_lo, c.d_hi, c.diameter, c.volume_fraction, beta, 0.0, {}});
  out.modelling = {
      fmt::format("the lab route: the test's sample ({}) at the test's compaction index K {:g} ({}, de Larrard 1999 "
                  "Table 1.2)",
                  s.distributions.front().rule, s.process.compaction_index, s.process.name),
      fmt::format("the measure's wall effect ({:.0f} x {:.0f} mm): a layer d/2 deep at the side and the floor packing "
                  "at k_w = {:g} of the bulk (de Larrard's container wall effect, recalled, not read)",
                  s.measure_diameter_m / kMm, s.measure_height_m / kMm, kContainerWallFactor),
      "one beta for every class of the material: the lab's one number cannot tell its classes apart"};
  return out;
}

ModelDistribution model_distribution(const MaterialBetas& b) {
  ModelDistribution d;
  for (const ClassBeta& c : b.classes) d.classes.push_back({c.diameter, c.d_lo, c.d_hi, c.volume_fraction});
  d.rule = fmt::format("the sieve fractions of {}", b.material);
  return d;
}

nlohmann::json to_json(const MaterialBetas& b) {
  nlohmann::json classes = nlohmann::json::array();
  for (const ClassBeta& c : b.classes)
    classes.push_back({{"d_lo_m", c.d_lo},
                       {"d_hi_m", c.d_hi},
                       {"diameter_m", c.diameter},
                       {"volume_fraction", c.volume_fraction},
                       {"beta", c.beta},
                       {"beta_sd", c.beta_sd},
                       {"packing", c.packing}});
  return {{"file", b.file.string()},
          {"material", b.material},
          {"route", name_of(kBetaRouteNames, b.route)},
          {"source", b.source},
          {"particle_density_kg_m3", b.particle_density_kg_m3},
          {"classes", classes},
          {"modelling", b.modelling}};
}

MaterialBetas material_betas_from_json(const nlohmann::json& j) {
  MaterialBetas b;
  b.file = j.at("file").get<std::string>();
  b.material = j.at("material").get<std::string>();
  const auto route = value_of(kBetaRouteNames, j.at("route").get<std::string>());
  if (!route) throw std::runtime_error("an unknown route");
  b.route = *route;
  b.source = j.at("source").get<std::string>();
  b.particle_density_kg_m3 = j.at("particle_density_kg_m3").get<double>();
  b.modelling = j.at("modelling").get<std::vector<std::string>>();
  for (const nlohmann::json& c : j.at("classes")) {
    ClassBeta k{c.at("d_lo_m").get<double>(),
                c.at("d_hi_m").get<double>(),
                c.at("diameter_m").get<double>(),
                c.at("volume_fraction").get<double>(),
                c.at("beta").get<double>(),
                c.at("beta_sd").get<double>(),
                c.at("packing").get<std::vector<double>>()};
    if (!(k.beta > 0.0 && k.beta < 1.0) || !(k.volume_fraction >= 0.0) || !(k.d_lo > 0.0 && k.d_lo < k.d_hi))
      throw std::runtime_error("a class's values are out of range");
    b.classes.push_back(std::move(k));
  }
  if (b.classes.empty()) throw std::runtime_error("no classes");
  return b;
}

}  // namespace aggpack
