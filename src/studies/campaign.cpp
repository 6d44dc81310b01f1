#include "aggpack/studies/campaign.hpp"

#include <chrono>
#include <iostream>
#include <sstream>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "aggpack/core/error.hpp"
#include "aggpack/run/checkpoint.hpp"

namespace aggpack {

SeedStatistics seed_statistics(const std::vector<double>& values) {
  SeedStatistics s;
  double sum = 0.0;
  for (const double v : values)
    if (std::isfinite(v)) {
      sum += v;
      ++s.count;
    }
  if (s.count == 0) return s;
  s.mean = sum / static_cast<double>(s.count);
  if (s.count < 2) return s;
  double squares = 0.0;
  for (const double v : values)
    if (std::isfinite(v)) squares += (v - s.mean) * (v - s.mean);
  s.sd = std::sqrt(squares / static_cast<double>(s.count - 1));
  return s;
}

Campaign::Campaign(int threads, bool quiet, std::ostream& log, std::size_t planned_runs, Checkpoints checkpoints,
                   Mode mode)
    : threads_(threads),
      log_(quiet ? nullptr : &log),
      progress_(Progress::wanted(quiet) ? Progress(std::cerr) : Progress()),
      planned_(planned_runs),
      checkpoints_(checkpoints),
      mode_(mode),
      start_(std::chrono::steady_clock::now()) {}

void Campaign::check(const std::string& label, std::uint64_t seed, const std::function<void()>& checks) {
  progress_.set_run(fmt::format("[{}/{}] {} seed {}", done_ + 1, planned_, label, seed));
  progress_.update({"checking before any run"}, 0.0);
  try {
    checks();
  } catch (const InputError& e) {
    progress_.clear();
    throw InputError(fmt::format("{} seed {}, checked before any run: {}", label, seed, e.what()));
  }
  ++done_;
}

std::optional<std::string> Campaign::why_not_resumable(const std::filesystem::path& scenario,
                                                       const std::vector<std::string>& sets, std::uint64_t seed,
                                                       const std::filesystem::path& out_dir,
                                                       const std::optional<std::string>& stop_after) {
  Checkpoint checkpoint;
  try {
    checkpoint = read_checkpoint(out_dir);  // refuses another build's
  } catch (const InputError& e) {
    return e.what();
  }
  if (checkpoint.scenario_text != read_scenario_text(scenario))
    return "it holds another scenario text: the file changed since, or it is another run's";
  if (checkpoint.overrides.set != sets || checkpoint.overrides.seed != seed || checkpoint.stop_after != stop_after)
    return "it is of another run (other overrides, seed or stop)";
  return std::nullopt;
}

void remove_checkpoints(const std::vector<std::filesystem::path>& run_folders) {
  for (const std::filesystem::path& dir : run_folders) {
    std::error_code ec;
    std::filesystem::remove(dir / kCheckpointFile, ec);
  }
}

double Campaign::seconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void Campaign::announce(const std::string& label, std::uint64_t seed) {
  std::optional<double> left_in_all;  // s, from the pace of the runs so far
  if (done_ > 0) left_in_all = seconds() / static_cast<double>(done_) * static_cast<double>(planned_ - done_);
  progress_.set_run(fmt::format("[{}/{}] {} seed {}", done_ + 1, planned_, label, seed), left_in_all);
}

void Campaign::print_line(const std::string& line) {
  if (!log_) return;
  progress_.clear();
  fmt::print(*log_, "{}\n", line);
  log_->flush();
}

namespace {
// The densities a run is judged by, and its size, kept apart from its report (the bed may be dropped).
void measure(CaseRun& c) {
  c.particle_count = c.result.report.particles.size();
  c.after_deposition = c.result.report.density_after_deposition();
  c.after_dynamics = c.result.report.density_after_dynamics();
}
}  // namespace

std::string Campaign::result_line(const std::string& label, std::uint64_t seed, const CaseRun& c, bool resumed) {
  return fmt::format(
      "{} seed {}: density {:.4f}{} ({} particles, {:.1f} s{})", label, seed, c.final_density(),
      std::isnan(c.after_dynamics) ? std::string(" after deposition")
      : std::isnan(c.after_deposition)
          ? fmt::format(" after {}", c.result.report.last_dem_stage())  // poured: never deposited
          : fmt::format(" after {}, {:.4f} after deposition", c.result.report.last_dem_stage(), c.after_deposition),
      c.result.report.particles.size(), c.result.wall_clock_s,
      resumed ? fmt::format(", resumed from its checkpoint taken {}", *c.result.report.resumed_from) : "");
}

CaseRun Campaign::run(const std::string& label, const std::filesystem::path& scenario,
                      const std::vector<std::string>& sets, std::uint64_t seed, const std::filesystem::path& out_dir,
                      const std::optional<std::string>& stop_after) {
  RunOptions options;
  options.overrides.set = sets;
  options.overrides.seed = seed;
  options.overrides.output_directory = out_dir;
  options.threads = threads_;
  options.stop_after = stop_after;
  options.quiet = true;
  options.progress = &progress_;
  if (mode_ == Mode::check) {
    check(label, seed, [&] { (void)check_scenario(scenario, options.overrides); });
    return {};
  }
  announce(label, seed);
  options.keep_dem_checkpoint = checkpoints_ != Checkpoints::removed;
  bool resume = false;
  if (checkpoints_ == Checkpoints::kept_and_resumed && std::filesystem::exists(out_dir / kCheckpointFile)) {
    const std::optional<std::string> why_not = why_not_resumable(scenario, sets, seed, out_dir, stop_after);
    resume = !why_not;
    if (why_not)
      print_line(fmt::format("{} seed {}: run again, not resumed: the checkpoint in {} cannot continue it ({})", label,
                             seed, out_dir.string(), *why_not));
  }
  std::ostringstream discard;
  RunOptions resumed = options;  // the checkpoint holds the scenario, its overrides and the stop
  resumed.overrides = {};
  resumed.stop_after.reset();
  CaseRun c{resume ? resume_run(out_dir, resumed, discard) : run_scenario(scenario, options, discard)};
  ++done_;
  if (resume) ++resumed_;
  if (options.keep_dem_checkpoint && std::filesystem::exists(out_dir / kCheckpointFile)) kept_.push_back(out_dir);
  measure(c);
  print_line(result_line(label, seed, c, resume));
  return c;
}

CaseRun Campaign::run(const std::string& label, Scenario scenario, std::uint64_t seed, const ResultLine& line) {
  scenario.seed = seed;
  if (mode_ == Mode::check) {
    check(label, seed, [&] { check_scenario_inputs(scenario); });  // a run in memory writes no folder
    return {};
  }
  announce(label, seed);
  RunControls controls;
  controls.threads = threads_;
  const auto start = std::chrono::steady_clock::now();
  CaseRun c;
  c.result.report = aggpack::run(scenario, controls, progress_);
  c.result.wall_clock_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ++done_;
  measure(c);
  print_line(line ? line(c) : result_line(label, seed, c, false));
  return c;
}

}  // namespace aggpack
