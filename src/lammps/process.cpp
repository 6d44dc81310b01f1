#include "aggpack/lammps/process.hpp"

#include <cstdio>
#include <cstdlib>
#include <unistd.h>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/core/input_file.hpp"

namespace aggpack {

namespace {
// The first executable called `name` on PATH (or `name` itself when it holds a slash).
std::optional<std::filesystem::path> on_path(const std::string& name) {
  if (name.find('/') != std::string::npos)
    return ::access(name.c_str(), X_OK) == 0 ? std::optional<std::filesystem::path>(name) : std::nullopt;
  const char* path = std::getenv("PATH");
  std::string_view dirs = path ? path : "/usr/bin:/bin";
  while (!dirs.empty()) {
    const std::size_t colon = dirs.find(':');
    const std::filesystem::path candidate = std::filesystem::path(dirs.substr(0, colon)) / name;
    if (::access(candidate.c_str(), X_OK) == 0) return candidate;
    dirs = colon == std::string_view::npos ? std::string_view() : dirs.substr(colon + 1);
  }
  return std::nullopt;
}

std::string shell_quoted(const std::string& s) {
  std::string q = "'";
  for (const char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}
}  // namespace

std::string lammps_command_line(const DynamicsStage& stage) {
  return (stage.lammps_ranks > 1 ? fmt::format("mpirun --allow-run-as-root -np {} ", stage.lammps_ranks) : "") +
         shell_quoted(stage.lammps_binary);
}

void check_lammps_available(const Scenario& sc) {
  if (!sc.dynamics || sc.dynamics->engine != DemEngine::Lammps) return;
  if (!on_path(sc.dynamics->lammps_binary))
    throw InputError(fmt::format("{}: dynamics.engine = \"lammps\": \"{}\" is not on PATH; install LAMMPS (Debian: "
                                 "apt-get install lammps openmpi-bin) or set dynamics.lammps_binary",
                                 sc.file.string(), sc.dynamics->lammps_binary));
  if (sc.dynamics->lammps_ranks > 1 && !on_path("mpirun"))
    throw InputError(fmt::format("{}: dynamics.lammps_ranks = {} needs mpirun, which is not on PATH (Debian: "
                                 "apt-get install openmpi-bin)",
                                 sc.file.string(), sc.dynamics->lammps_ranks));
}

LammpsBed read_lammps_dump(const std::filesystem::path& file, const Scenario& sc, std::optional<std::int64_t> timestep) {
  return parse_lammps_dump(read_input_text(file, "LAMMPS's dump", sc.limits.max_input_bytes()), file.string(), 1.0, sc.material.density,
                           timestep);
}

std::vector<std::string> tagged_lines(const std::string& log, const std::string& tag) {
  std::vector<std::string> lines;
  for (std::size_t at = log.find(tag); at != std::string::npos; at = log.find(tag, at + 1))
    if (at == 0 || log[at - 1] == '\n') lines.push_back(log.substr(at, log.find('\n', at) - at));
  return lines;
}

std::string run_lammps(const Scenario& sc, const std::filesystem::path& folder, const LammpsDeck& deck) {
  std::filesystem::remove(folder / LammpsDeck::kDumpFile);
  write_lammps_deck(folder, deck);
  const std::string command = fmt::format("cd {} && {} -in {} -log {} > lammps.out 2>&1", shell_quoted(folder.string()),
                                          lammps_command_line(*sc.dynamics), deck.deck_file, LammpsDeck::kLogFile);
  const int status = std::system(command.c_str());
  if (status != 0 || !std::filesystem::exists(folder / LammpsDeck::kDumpFile))
    throw InputError(fmt::format("{}: LAMMPS failed on the {} step (exit status {}); its log is {}", sc.file.string(),
                                 deck.step, status, (folder / LammpsDeck::kLogFile).string()));
  return read_input_text(folder / LammpsDeck::kLogFile, "LAMMPS's log", kDefaultMaxInputFileBytes);
}

SettledLine settled_line(const std::string& log, const std::filesystem::path& folder) {
  const std::vector<std::string> lines = tagged_lines(log, "aggpack-settled: ");
  SettledLine s;
  long long quiet_samples = 0;
  if (lines.empty() || std::sscanf(lines.back().c_str(), "aggpack-settled: time %lf energy %lf quiet_samples %lld",
                                   &s.time, &s.energy, &quiet_samples) != 3)
    throw InputError(
        fmt::format("{}: the LAMMPS log has no \"aggpack-settled:\" line", (folder / LammpsDeck::kLogFile).string()));
  return s;
}

}  // namespace aggpack
