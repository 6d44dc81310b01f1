// `aggpack test c29|c1252 MATERIAL`: a standard's test of one aggregate, simulated.
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "aggpack/core/units.hpp"
#include "aggpack/io/atomic_file.hpp"
#include "aggpack/io/output_directory.hpp"
#include "aggpack/labtests/lab_test.hpp"
#include "arguments.hpp"
#include "commands.hpp"

namespace {

struct TestArguments {
  aggpack::LabTestOptions options;
  std::string out, finest;
  bool json = false;
};

// The folder's default: out/test_<test>_<method>_<material file's stem>.
std::filesystem::path default_folder(const aggpack::LabTestOptions& o) {
  return std::filesystem::path("out") /
         fmt::format("test_{}_{}_{}", aggpack::name_of(aggpack::kLabTestNames, o.test), o.method,
                     o.material.stem().string());
}

int run_test(TestArguments& a) {
  aggpack::LabTestOptions& o = a.options;
  if (!a.finest.empty()) {
    std::string why;
    const auto length = aggpack::parse_length(a.finest, &why);
    if (!length || *length <= 0.0)
      throw aggpack::InputError(fmt::format("--finest {}: expected a length with its unit (\"2.36 mm\"){}", a.finest,
                                            why.empty() ? "" : ": " + why));
    o.finest_size_m = *length;
  }
  const std::filesystem::path folder = a.out.empty() ? default_folder(o) : std::filesystem::path(a.out);
  const aggpack::LabTestPlan plan = aggpack::plan_lab_test(o);  // every check before any run or file
  aggpack::check_output_directory(folder, true, "--out");
  // The scenarios first: what runs can be read (and run alone) while it runs.
  for (std::size_t i = 0; i < plan.parts.size(); ++i)
    aggpack::write_file_atomically(folder / fmt::format("scenario_{}.toml", i + 1), plan.parts[i].scenario_text);
  aggpack::Campaign campaign(o.threads, o.quiet || a.json, std::cerr, plan.parts.size() * std::size_t(o.seeds));
  const aggpack::LabTestResult result = aggpack::run_lab_test(plan, o, campaign);
  const nlohmann::json summary = aggpack::to_json(result);
  aggpack::write_file_atomically(folder / "summary.json", summary.dump(1) + "\n");
  if (a.json) fmt::print("{}\n", summary.dump(1));
  else if (!o.quiet) fmt::print("{}aggpack: wrote {}\n", aggpack::describe(result), (folder / "summary.json").string());
  return 0;
}

Subcommand add_test_kind(CLI::App* test, aggpack::LabTestKind kind, const char* help, const char* methods) {
  const auto a = std::make_shared<TestArguments>();
  a->options.test = kind;
  auto* cmd = test->add_subcommand(std::string(aggpack::name_of(aggpack::kLabTestNames, kind)), help);
  cmd->add_option("material", a->options.material, "The aggregate's material file (TOML)")->required();
  cmd->add_option("--method", a->options.method, methods)->required();
  cmd->add_option("--seeds", a->options.seeds, "Seeds 1..N (default 3)")->check(CLI::Range(1, 100));
  add_threads_option(cmd, a->options.threads);
  cmd->add_option("--out", a->out, "Output folder (default out/test_<test>_<method>_<material>)");
  cmd->add_option("--set", a->options.set, "Override a key of the test's scenario: key.path=value");
  cmd->add_option("--finest", a->finest, "Cut-off of fines, a length (\"2.36 mm\"): finer material is left out");
  if (kind == aggpack::LabTestKind::C1252)
    cmd->add_option("--max-particles", a->options.max_particles,
                    "The most particles a simulated cylinder holds (default 50000): a test whose cylinder would "
                    "hold more is simulated in a smaller one of its proportions, read as the full one's")
        ->check(CLI::Range(100.0, 1e8));
  cmd->add_flag("--json", a->json, "Print summary.json instead of the lines");
  cmd->add_flag("--quiet", a->options.quiet, "Print nothing on success");
  return {cmd, [a] { return run_test(*a); }};
}

}  // namespace

std::vector<Subcommand> add_lab_commands(CLI::App& app) {
  auto* test = app.add_subcommand("test", "A standard's test of one aggregate, simulated in the standard's measure");
  test->require_subcommand(1);
  return {add_test_kind(test, aggpack::LabTestKind::C29,
                        "ASTM C29 bulk density and voids (AASHTO T 19), in its measure for the size",
                        "shovelling, rodding or jigging"),
          add_test_kind(test, aggpack::LabTestKind::C1252,
                        "ASTM C1252 uncompacted voids of a fine aggregate (AASHTO T 304), in its 100 mL cylinder",
                        "A (standard grading), B (three fractions) or C (as received)")};
}
