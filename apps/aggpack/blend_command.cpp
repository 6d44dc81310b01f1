// `aggpack blend STONE.toml SAND.toml [MORE.toml] --sweep 20:60:1 | --fractions 0.6,0.4`: the
// blends' packing predicted by CPM at each material's betas, in seconds.
#include <fmt/format.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "aggpack/blends/blend_check.hpp"
#include "aggpack/blends/blend_report.hpp"
#include "aggpack/blends/blend_request.hpp"
#include "aggpack/blends/simulated_betas.hpp"
#include "aggpack/core/error.hpp"
#include "aggpack/core/text.hpp"
#include "aggpack/core/units.hpp"
#include "aggpack/io/atomic_file.hpp"
#include "aggpack/io/output_directory.hpp"
#include "arguments.hpp"
#include "commands.hpp"

namespace {

struct BlendArguments {
  std::vector<std::filesystem::path> materials;
  std::string sweep;
  std::vector<std::string> fractions;
  std::string process = "rodded";
  std::string route = "auto";
  std::string out;
  aggpack::SimulatedBetaOptions beds;
  std::string check, check_cut;                // --check P1,P2: the DEM of the blend at those fine percents
  std::vector<std::filesystem::path> checked;  // --checked FILE: earlier checks (blend.json) read back
  double check_particles = 400;                // coarse particles in each blend bed
  std::string interaction;                     // --interaction L,W: CPM's exponents (empty: de Larrard's)
  aggpack::CpmInteraction cpm;                 // as read
  bool fit_interaction = false;                // --fit-interaction: fitted on the check's points
  bool json = false, quiet = false;
};

// A comma-separated list of numbers given to `option`; InputError saying what is `expected`.
std::vector<double> numbers_of(const std::string& text, const char* option, const char* expected) {
  std::vector<double> out;
  std::string field;
  for (const char ch : text + ",") {
    if (ch != ',') {
      field.push_back(ch);
      continue;
    }
    const auto x = aggpack::parse_finite_number(aggpack::trim(field));
    if (!x)
      throw aggpack::InputError(fmt::format("{} {}: '{}' is not a number; expected {}", option, text, field, expected));
    out.push_back(*x);
    field.clear();
  }
  return out;
}

std::vector<double> fractions_of(const std::string& text) {
  return numbers_of(text, "--fractions", "volume fractions summing to 1, one a material, e.g. 0.6,0.4");
}

// --check's points and bed: two materials, the fine's volume percents, its cut, the betas' beds.
aggpack::BlendCheckOptions check_options(const BlendArguments& a) {
  if (a.materials.size() != 2)
    throw aggpack::InputError(fmt::format("--check: the DEM check takes two materials, {} given", a.materials.size()));
  aggpack::BlendCheckOptions o;
  o.coarse = a.materials[0];
  o.fine = a.materials[1];
  o.percents = numbers_of(a.check, "--check", "the fine material's volume percents, e.g. 20,30,40");
  for (const double pc : o.percents)  // before the curve's betas, which may simulate
    if (!(pc > 0.0 && pc < 100.0))
      throw aggpack::InputError(fmt::format("--check {}: {} is not a percent between 0 and 100", a.check, pc));
  if (!a.check_cut.empty()) {
    std::string why;
    const auto cut = aggpack::parse_length(a.check_cut, &why);
    if (!cut || !(*cut > 0.0))
      throw aggpack::InputError(fmt::format("--check-cut {}: expected a length with its unit (\"1.18 mm\"){}",
                                            a.check_cut, why.empty() ? "" : ": " + why));
    o.fine_d_min = *cut;
  }
  if (!(a.check_particles >= 20.0 && a.check_particles <= 1e6))
    throw aggpack::InputError(fmt::format("--check-particles {}: expected 20 to 1e6", a.check_particles));
  o.coarse_particles = a.check_particles;
  o.betas = a.beds;
  o.betas.quiet = a.quiet || a.json;
  o.interaction = a.cpm;
  return o;
}

// The DEM of the blend at --check's points, into `summary` (and the exponents fitted on them).
aggpack::BlendCheck run_check(const BlendArguments& a, const aggpack::BlendCheckOptions& o, nlohmann::json& summary) {
  aggpack::BlendCheck checked = aggpack::check_blend(o, std::cerr);
  summary["check"] = aggpack::to_json(checked);
  if (a.fit_interaction) {
    const aggpack::BlendCheck one[] = {checked};
    const aggpack::CpmInteraction fitted = aggpack::fit_interaction(one);
    summary["fitted_interaction"] = {{"loosening_exponent", fitted.loosening_exponent},
                                     {"wall_exponent", fitted.wall_exponent},
                                     {"largest_difference", aggpack::largest_difference(one, fitted)},
                                     {"fitted_on", "this check's simulated blends (in-sample)"}};
  }
  return checked;
}

// A blend.json's check, read back and predicted again with `interaction`.
aggpack::BlendCheck read_checked(const std::filesystem::path& file, const aggpack::CpmInteraction& interaction) {
  std::ifstream in(file);
  if (!in) throw aggpack::InputError(fmt::format("--checked {}: cannot be read", file.string()));
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const std::exception& e) {
    throw aggpack::InputError(fmt::format("--checked {}: not JSON ({})", file.string(), e.what()));
  }
  if (!j.contains("check"))
    throw aggpack::InputError(
        fmt::format("--checked {}: no \"check\"; expected a blend.json of aggpack blend --check", file.string()));
  return aggpack::read_blend_check(j["check"], interaction, file);
}

// The earlier checks (and this run's) in `summary`, and the exponents fitted on all of them.
void refit(const BlendArguments& a, std::vector<aggpack::BlendCheck>& earlier,
           const std::optional<aggpack::BlendCheck>& checked, nlohmann::json& summary) {
  nlohmann::json all = nlohmann::json::array();
  for (const aggpack::BlendCheck& c : earlier) all.push_back(aggpack::to_json(c));
  summary["checked"] = all;
  if (!a.fit_interaction) return;
  std::vector<aggpack::BlendCheck> checks = earlier;
  if (checked) checks.push_back(*checked);
  const aggpack::CpmInteraction fitted = aggpack::fit_interaction(checks);
  summary["fitted_interaction"] = {{"loosening_exponent", fitted.loosening_exponent},
                                   {"wall_exponent", fitted.wall_exponent},
                                   {"largest_difference", aggpack::largest_difference(checks, fitted)},
                                   {"fitted_on", "the checked blends given (in-sample)"}};
}

// --interaction's two exponents; de Larrard's when not given.
aggpack::CpmInteraction interaction_of(const std::string& text) {
  if (text.empty()) return {};
  const std::vector<double> e = numbers_of(text, "--interaction", "two positive exponents, loosening,wall");
  if (e.size() != 2 || !(e[0] > 0.0 && e[1] > 0.0))
    throw aggpack::InputError(
        fmt::format("--interaction {}: expected two positive exponents, loosening,wall "
                    "(de Larrard's: 1.02,1.50)",
                    text));
  return {e[0], e[1]};
}

// The request of the blends asked: InputError for anything wrong, before any bed runs.
aggpack::BlendRequest request_of(const BlendArguments& a) {
  aggpack::BlendRequest r;
  r.materials = a.materials;
  if (!a.sweep.empty()) {
    if (a.materials.size() != 2)
      throw aggpack::InputError(fmt::format(
          "--sweep: a sweep takes two materials (the second's volume percent), {} given; expected --fractions for more",
          a.materials.size()));
    r.sweep_percents = aggpack::parse_sweep(a.sweep, "--sweep");
  }
  for (const std::string& f : a.fractions) r.fractions.push_back(fractions_of(f));
  r.process = aggpack::blend_process(a.process, "--process");
  r.route = a.route;
  if (r.route != "auto" && r.route != "lab" && r.route != "simulation")
    throw aggpack::InputError(fmt::format("--route {}: expected auto, lab or simulation", a.route));
  r.beds = a.beds;
  r.beds.quiet = a.quiet || a.json;
  r.interaction = a.cpm;
  return r;
}

int run_blend(BlendArguments& a) {
  const bool no_curve = a.sweep.empty() && a.fractions.empty();
  if (!a.sweep.empty() && !a.fractions.empty())
    throw aggpack::InputError("aggpack blend: --sweep and --fractions together; expected one of them");
  if (no_curve && a.checked.empty() && a.check.empty())
    throw aggpack::InputError(
        "aggpack blend: give --sweep FROM:TO:STEP (two materials) or --fractions F1,F2,... "
        "(or --check or --checked alone: the DEM check without a curve)");
  a.cpm = interaction_of(a.interaction);
  if (a.fit_interaction && a.check.empty() && a.checked.empty())
    throw aggpack::InputError("--fit-interaction: fits on the DEM of blends; expected --check or --checked too");
  std::vector<aggpack::BlendCheck> earlier;  // read (and refused) before any work
  for (const std::filesystem::path& file : a.checked) earlier.push_back(read_checked(file, a.cpm));
  const aggpack::BlendRequest request = request_of(a);
  if (!no_curve) aggpack::check_blend_request(request);
  std::optional<aggpack::BlendCheckOptions> check;
  if (!a.check.empty()) check = check_options(a);
  if (!a.out.empty()) aggpack::check_output_directory(a.out, true, "--out");
  aggpack::BlendResult r;
  r.process = request.process;
  if (!no_curve) r = aggpack::predict_blends(request, std::cerr);
  nlohmann::json summary = aggpack::to_json(r);
  std::optional<aggpack::BlendCheck> checked;
  if (check) checked = run_check(a, *check, summary);
  if (!earlier.empty()) refit(a, earlier, checked, summary);
  if (!a.out.empty()) {
    const std::filesystem::path folder(a.out);
    aggpack::write_file_atomically(folder / "blend.json", summary.dump(1) + "\n");
    if (r.sweep) {  // the DEM's points on the curve: this run's check, else the first --checked
      const aggpack::BlendCheck* shown = checked ? &*checked : earlier.empty() ? nullptr : &earlier.front();
      aggpack::write_file_atomically(folder / "blend.svg", aggpack::blend_svg(r, shown));
    }
  }
  if (a.json)
    fmt::print("{}\n", summary.dump(1));
  else if (!a.quiet) {
    fmt::print("{}{}", aggpack::describe(r), checked ? aggpack::describe(*checked) : "");
    for (const aggpack::BlendCheck& c : earlier) fmt::print("{}", aggpack::describe(c));
    if (summary.contains("fitted_interaction"))
      fmt::print("  fitted on these blends: --interaction {:.4g},{:.4g}, largest difference {:.4f} (in-sample)\n",
                 summary["fitted_interaction"]["loosening_exponent"].get<double>(),
                 summary["fitted_interaction"]["wall_exponent"].get<double>(),
                 summary["fitted_interaction"]["largest_difference"].get<double>());
  }
  return 0;
}

}  // namespace

Subcommand add_blend_command(CLI::App& app) {
  const auto a = std::make_shared<BlendArguments>();
  auto* cmd = app.add_subcommand("blend", "The packing of blends of materials, predicted by CPM in seconds");
  cmd->add_option("materials", a->materials, "Two or more material files (TOML), coarse first")
      ->required()
      ->expected(2, 20);
  cmd->add_option("--sweep", a->sweep, "FROM:TO:STEP: the second material's volume percent (two materials)");
  cmd->add_option("--fractions", a->fractions, "F1,F2,...: the materials' volume fractions (repeatable)");
  cmd->add_option("--process", a->process, "loose, rodded or vibrated: the K of CPM (default rodded)");
  cmd->add_option("--route", a->route,
                  "auto (a calibrated material by simulation, another by its lab number), lab or simulation");
  cmd->add_option("--out", a->out, "Folder for blend.json and blend.svg");
  cmd->add_option("--seeds", a->beds.seeds, "Simulation route: seeds of each class's beds (default 3)");
  cmd->add_option("--bed-particles", a->beds.particles, "Simulation route: particles in each bed (default 3000)");
  cmd->add_option("--beds", a->beds.procedure,
                  "Simulation route: the beds' procedure for every material, c29:shovelling|rodding|jigging or "
                  "c1252:A|B|C (default: each material's calibration test, else its lab test's)");
  cmd->add_option("--betas-cache", a->beds.cache_folder,
                  "Simulation route: the folder of the betas' caches (default: each material file's folder)");
  cmd->add_option("--check", a->check,
                  "P1,P2,...: the DEM of the blend (two materials, in a periodic bed) at these fine volume percents");
  cmd->add_option("--check-cut", a->check_cut, "--check: the fine material cut at this size (\"1.18 mm\")");
  cmd->add_option("--check-particles", a->check_particles, "--check: coarse particles in each bed (default 400)");
  cmd->add_option("--interaction", a->interaction,
                  "L,W: CPM's loosening and wall exponents (default de Larrard's 1.02,1.50)");
  cmd->add_option("--checked", a->checked,
                  "FILE: a blend.json of an earlier --check, its simulated blends predicted again (repeatable)");
  cmd->add_flag("--fit-interaction", a->fit_interaction,
                "With --check or --checked: fit the two exponents on the checked blends and print them");
  add_threads_option(cmd, a->beds.threads);
  cmd->add_flag("--json", a->json, "Print blend.json instead of the table");
  cmd->add_flag("--quiet", a->quiet, "Print nothing on success");
  return {cmd, [a] { return run_blend(*a); }};
}
