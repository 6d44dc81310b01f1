// The subcommands on one bed, one grading or one material, with no simulation: analyze, grading,
// predict and material.
#include <fmt/format.h>

#include <algorithm>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "aggpack/blends/blend_request.hpp"
#include "aggpack/core/error.hpp"
#include "aggpack/core/units.hpp"
#include "aggpack/core/version.hpp"
#include "aggpack/io/material_file.hpp"
#include "aggpack/io/particle_file.hpp"
#include "aggpack/io/shape_option.hpp"
#include "aggpack/run/analyze.hpp"
#include "aggpack/run/analyze_bed.hpp"
#include "aggpack/run/grading_report.hpp"
#include "aggpack/run/predictions.hpp"
#include "arguments.hpp"
#include "commands.hpp"

namespace {

struct AnalyzeArguments {
  std::string file, unit = "m";
  std::vector<std::string> boxes, cubes;
  double tolerance = 1e-6;
  double overlap_tolerance = aggpack::ParticleSource{}.overlap_tolerance;
  bool soft_contacts = false;
  bool json = false;
  std::optional<std::int64_t> timestep;  // of a LAMMPS dump; none: the last
};

int analyze_command(const AnalyzeArguments& a) {
  const auto& [file, unit, boxes, cubes, tolerance, overlap_tolerance, soft_contacts, json, timestep] = a;
  const auto factor = aggpack::metres_per_unit(unit);
  if (!factor) throw aggpack::InputError(fmt::format("--length-unit {}: unknown unit; expected m, cm, mm, um, in, ft or yd", unit));
  aggpack::BedAnalysisOptions options;
  options.tolerance = tolerance;
  options.overlap_tolerance = overlap_tolerance;
  options.soft_contacts = soft_contacts;
  options.boxes_named = "--box, --cube";
  options.tolerance_named = "--tolerance";
  // Bare numbers in --box and --cube are in the file's unit, like the file's own numbers.
  for (const auto& b : boxes) options.boxes.push_back(box_argument(b, *factor));
  for (const auto& c : cubes) options.cube_sides.push_back(length_argument(c, "--cube", *factor));
  aggpack::check_box_count(options);  // before the file is read
  const aggpack::PackingFile packing =
      aggpack::read_packing_file(file, static_cast<double>(*factor), 1.0, aggpack::kDefaultMaxInputFileBytes, timestep);
  const aggpack::ParticleStore& particles = packing.particles;
  const aggpack::BedAnalysis analysis = aggpack::analyze_bed(particles, options, file);
  const aggpack::PackingReport& report = analysis.report;
  const aggpack::PairOverlap& overlap = analysis.overlap;
  if (json) {
    auto j = aggpack::to_json(analysis, particles.size(), soft_contacts);
    j["file"] = file;
    j["format"] = packing.format;
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  fmt::print("{} ({}): {} particles, d = {:.6g} .. {:.6g} m, free surface at {:.6g} m\n", file, packing.format, particles.size(),
             report.bed.d_min, report.bed.d_max, report.bed.surface);
  for (const auto& b : report.density.boxes)
    fmt::print("  box [{:.6g}, {:.6g}, {:.6g}] .. [{:.6g}, {:.6g}, {:.6g}] m: density {:.6f}\n", b.box.lo.x,
               b.box.lo.y, b.box.lo.z, b.box.hi.x, b.box.hi.y, b.box.hi.z, b.density);
  fmt::print("  mean density {:.6f}, sd {:.6f}\n", report.density.mean, report.density.sd);
  if (overlap.depth_over_radius > 1e-3)
    fmt::print("  spheres overlap by up to {:.3g} of the smaller radius (particles {} and {}): the shared volume "
               "counts twice\n", overlap.depth_over_radius, overlap.i, overlap.j);
  fmt::print("  mean coordination {:.4f} over {} spheres in the largest box\n", report.coordination.mean,
             report.coordination.particles_counted);
  return 0;
}

Subcommand add_analyze(CLI::App& app) {
  const auto a = std::make_shared<AnalyzeArguments>();
  auto* cmd = app.add_subcommand("analyze", "Measure density, coordination and profiles of a packing file");
  cmd->add_option("file", a->file, "Packing: CSV with header x,y,z,r (or diameter), whitespace x y z r, a LAMMPS dump or data file")
      ->required();
  cmd->add_option("--box", a->boxes, "Box xmin,ymin,zmin,xmax,ymax,zmax (lengths; bare numbers in --length-unit); repeatable");
  cmd->add_option("--cube", a->cubes, "Virtual cube side (bare number in --length-unit), placed as in docs/method.md section 2; repeatable");
  cmd->add_option("--length-unit", a->unit, "Unit of the file's numbers (m, mm, in, ...)");
  cmd->add_option("--tolerance", a->tolerance, "Relative contact tolerance for coordination")
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--overlap-tolerance", a->overlap_tolerance,
                  "Deepest overlap of two spheres accepted, / smaller radius (default 0.25)")
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_flag("--soft-contacts", a->soft_contacts,
                "The file comes from a soft-contact DEM: accept any overlap short of a centre inside another sphere");
  cmd->add_flag("--json", a->json, "Print machine-readable JSON");
  cmd->add_option("--timestep", a->timestep, "A LAMMPS dump's snapshot to read (default: the last)");
  return {cmd, [a] { return analyze_command(*a); }};
}

Subcommand add_grading(CLI::App& app) {
  struct Arguments {
    aggpack::GradingQuery query;
    std::string unit, d_min, d_max, shape, seed, ca_fa;
    bool json = false, list = false;
  };
  const auto a = std::make_shared<Arguments>();
  auto* cmd = app.add_subcommand("grading", "Print and check a grading (or a coarse/fine mix) without a run");
  cmd->add_option("grading", a->query.grading, "A shipped grading name or a CSV sieve analysis");
  cmd->add_option("--mix", a->query.fine, "A fine grading (name or file) to blend with it");
  auto* ca_fa_opt = cmd->add_option("--ca-fa", a->ca_fa, "Coarse/fine volume ratio of the mix (with --mix; no default)");
  cmd->add_option("--band", a->query.band, "Check against astm_c33_fine, astm_c33_57 or astm_c33_67");
  auto* d_min_opt = cmd->add_option("--d-min", a->d_min, "Cut-off below this size (length)");
  auto* d_max_opt = cmd->add_option("--d-max", a->d_max, "Cut-off above this size (length)");
  cmd->add_option("--length-unit", a->unit,
                  "Unit of a bare 'opening' column in files (none by default: such a column is refused)");
  cmd->add_flag("--json", a->json, "Print machine-readable JSON");
  auto* shape_opt = cmd->add_option(
      "--shape", a->shape,
      "The grading's grains, as a component's shape table: e.g. 'family=\"angular\", flakiness_index=18'; prints "
      "what the generated grains measure beside the target");
  auto* seed_opt =
      cmd->add_option("--seed", a->seed, "Seed of the sizes and grains --shape draws, 0 to 2^63-1 (default 1)")
          ->needs(shape_opt);
  cmd->add_flag("--list", a->list, "List the shipped gradings and bands");
  return {cmd, [a, d_min_opt, d_max_opt, shape_opt, seed_opt, ca_fa_opt] {
            aggpack::GradingQuery& query = a->query;
            if (*ca_fa_opt) query.ca_fa = positive_argument(a->ca_fa, "--ca-fa");
            if (a->list) {
              for (const auto& n : aggpack::named_grading_names()) fmt::print("grading {}\n", n);
              for (const auto& n : aggpack::named_band_names()) fmt::print("band {}\n", n);
              return 0;
            }
            if (query.grading.empty())
              throw aggpack::InputError("grading: give a shipped grading name or a CSV file (--list shows the names)");
            if (!a->unit.empty()) {
              const auto factor = aggpack::metres_per_unit(a->unit);
              if (!factor)
                throw aggpack::InputError(
                    fmt::format("--length-unit {}: unknown unit; expected m, cm, mm, um, in, ft or yd", a->unit));
              query.length_unit = static_cast<double>(*factor);
            }
            if (*d_min_opt) query.d_min = length_argument(a->d_min, "--d-min");
            if (*d_max_opt) query.d_max = length_argument(a->d_max, "--d-max");
            if (*shape_opt) query.shape = aggpack::read_shape_option(a->shape, "--shape");
            if (*seed_opt) query.seed = seed_argument(a->seed);
            const auto description = aggpack::describe_grading(query);
            if (a->json) std::cout << aggpack::to_json(description).dump(2) << "\n";
            else fmt::print("{}", aggpack::format_grading(description));
            return 0;
          }};
}

int predict_command(const aggpack::PredictRequest& predict, bool json) {
  const aggpack::Predictions p = aggpack::predict(predict);
  if (json) fmt::print("{}\n", aggpack::to_json(p).dump(1));
  else
    fmt::print("aggpack {}: analytic predictions for {}, no simulation\n  K = {:g}: {}\n  beta = {:g}: {}\n{}{}",
               aggpack::kVersion, predict.input, p.parameters.compaction_index, p.parameters.compaction_source,
               p.parameters.beta, p.parameters.beta_source,
               p.parameters.beta_fine ? fmt::format("  beta of the fine aggregate = {:g}: {}\n", *p.parameters.beta_fine,
                                                    p.parameters.beta_fine_source)
                                      : "",
               aggpack::describe(p));
  return 0;
}

// predict STONE.toml [--mix SAND.toml --ca-fa R]: materials' CPM at their betas, simulating
// nothing (a calibrated material's simulated betas from its cache, else its lab number's).
int predict_materials_command(const aggpack::PredictRequest& predict, const std::string& process, bool json,
                              const CLI::App& cmd) {
  for (const char* option : {"--k", "--beta", "--beta-fine", "--calibration", "--set"})
    if (cmd.count(option) > 0)
      throw aggpack::InputError(fmt::format(
          "predict {}: {} is for a scenario or a grading; a material's betas come from its lab number or its "
          "simulated beds, and --process sets K",
          predict.input, option));
  aggpack::BlendRequest r;
  r.materials.push_back(predict.input);
  if (predict.fine) {
    if (!aggpack::looks_like_material_file(*predict.fine))
      throw aggpack::InputError(
          fmt::format("--mix {}: expected a material file, as {} is", *predict.fine, predict.input));
    if (!predict.ca_fa)
      throw aggpack::InputError("--ca-fa is missing: the coarse/fine volume ratio of the two materials' blend");
    r.materials.push_back(*predict.fine);
    r.fractions.push_back({*predict.ca_fa / (1.0 + *predict.ca_fa), 1.0 / (1.0 + *predict.ca_fa)});
  } else {
    if (predict.ca_fa) throw aggpack::InputError("--ca-fa: needs --mix, the fine material");
    r.fractions.push_back({1.0});
  }
  r.process = aggpack::blend_process(process.empty() ? "rodded" : process, "--process");
  r.beds.quiet = true;
  r.may_simulate = false;
  const aggpack::BlendResult b = aggpack::predict_blends(r, std::cerr);
  if (json)
    fmt::print("{}\n", aggpack::to_json(b).dump(1));
  else
    fmt::print("{}", aggpack::describe(b));
  return 0;
}

Subcommand add_predict(CLI::App& app) {
  struct Arguments {
    aggpack::PredictRequest predict;
    std::string ca_fa;
    bool json = false;
  };
  const auto a = std::make_shared<Arguments>();
  aggpack::PredictRequest& predict = a->predict;
  auto* cmd = app.add_subcommand(
      "predict", "Analytic packing densities (CPM, Furnas, Desmond-Weeks) of a scenario's or a grading's sizes");
  cmd->add_option("input", predict.input,
                  "Scenario (.toml), a shipped grading's name, a CSV sieve analysis, or a material file (.toml)")
      ->required();
  cmd->add_option("--mix", predict.fine,
                  "A fine grading (name or file) to blend with the grading; a fine material file with a material");
  auto* ca_fa_opt = cmd->add_option("--ca-fa", a->ca_fa, "Coarse/fine volume ratio of the blend");
  cmd->add_option("--k", predict.compaction_index, "CPM compaction index K (4.1 poured ... 9 vibrated and compressed)");
  cmd->add_option("--process", predict.process,
                  "K of a lab process: poured, rodded, vibrated, vibrated_compressed (materials: loose or poured, "
                  "rodded, vibrated; default rodded)");
  cmd->add_option("--beta", predict.beta, "CPM residual packing density of every class (default 0.72, spheres)");
  cmd->add_option("--beta-fine", predict.beta_fine,
                  "CPM residual packing density of a blend's fine aggregate (default: --beta)");
  cmd->add_option("--calibration", predict.calibration, "K and beta from a file aggpack calibrate wrote");
  cmd->add_option("--set", predict.overrides.set, "Override a scenario key: key.path=value");
  cmd->add_flag("--json", a->json, "Print machine-readable JSON");
  return {cmd, [a, ca_fa_opt, cmd] {
            if (*ca_fa_opt) a->predict.ca_fa = positive_argument(a->ca_fa, "--ca-fa");
            if (aggpack::looks_like_material_file(a->predict.input))
              return predict_materials_command(a->predict, a->predict.process.value_or(""), a->json, *cmd);
            return predict_command(a->predict, a->json);
          }};
}

Subcommand add_material(CLI::App& app) {
  struct Arguments {
    std::string file;
    bool json = false;
  };
  const auto a = std::make_shared<Arguments>();
  auto* cmd = app.add_subcommand("material", "Check a material file (one aggregate: specific gravity, grading, shape, "
                                             "contact, lab results) and print it");
  cmd->add_option("file", a->file, "A material file (.toml): README.md, \"Materials: one file per aggregate\"")
      ->required();
  cmd->add_flag("--json", a->json, "Print machine-readable JSON");
  return {cmd, [a] {
            const aggpack::AggregateMaterial material = aggpack::load_material_file(a->file);
            if (a->json) std::cout << aggpack::to_json(material).dump(2) << "\n";
            else fmt::print("{}", aggpack::describe(material));
            return 0;
          }};
}

}  // namespace

// A braced list is evaluated in order: the subcommands are added, and listed, in this order.
std::vector<Subcommand> add_bed_commands(CLI::App& app) {
  return {add_analyze(app), add_grading(app), add_predict(app), add_material(app)};
}
