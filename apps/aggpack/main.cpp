// The aggpack command line: parses arguments and calls the library. Exit codes:
// 0 success, 2 bad input (scenario, particle file, arguments), 1 internal failure.
// The subcommands and their options are in commands.hpp's groups.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <algorithm>
#include <exception>
#include <optional>
#include <string>
#include <vector>

#include "aggpack/core/error.hpp"
#include "aggpack/core/stop_request.hpp"
#include "aggpack/core/version.hpp"
#include "commands.hpp"

namespace {

std::vector<Subcommand> add_subcommands(CLI::App& app, int argc, char** argv) {
  std::vector<Subcommand> all;
  for (auto group : {add_run_commands(app), add_bed_commands(app), add_study_commands(app, argc, argv),
                     add_lab_commands(app), std::vector<Subcommand>{add_blend_command(app)}, add_lammps_commands(app),
                     std::vector<Subcommand>{add_specimen_command(app)}})
    all.insert(all.end(), group.begin(), group.end());
  return all;
}

// CLI11 would say "A subcommand is required" for a misspelt one: name it, with the list. The
// exit code when the first word names no subcommand.
std::optional<int> refuse_unknown_subcommand(const CLI::App& app, int argc, char** argv) {
  if (argc <= 1 || argv[1][0] == '-') return std::nullopt;
  const std::string word = argv[1];
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands({})) names.push_back(sub->get_name());
  if (std::find(names.begin(), names.end(), word) != names.end()) return std::nullopt;
  fmt::print(stderr, "aggpack: error: unknown subcommand '{}'; the subcommands are: {} (aggpack --help)\n", word,
             fmt::join(names, ", "));
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"aggpack: 3-D random packings of polydisperse spheres and concrete aggregate gradings"};
  app.set_version_flag("--version", aggpack::kVersion);
  app.require_subcommand(1);
  const std::vector<Subcommand> subcommands = add_subcommands(app, argc, argv);
  if (const auto code = refuse_unknown_subcommand(app, argc, argv)) return *code;

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }

  try {
    for (const Subcommand& subcommand : subcommands)
      if (*subcommand.app) return subcommand.run();
  } catch (const aggpack::InputError& e) {
    fmt::print(stderr, "aggpack: error: {}\n", e.what());
    return 2;
  } catch (const aggpack::Interrupted& e) {  // stopped before the run had anything to write
    fmt::print(stderr, "aggpack: {}; nothing was written\n", e.what());
    return 128 + e.signal_number();
  } catch (const std::exception& e) {
    fmt::print(stderr, "aggpack: internal error: {}\n", e.what());
    return 1;
  }
  return 0;
}
