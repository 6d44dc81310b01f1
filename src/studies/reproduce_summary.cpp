// aggpack reproduce: the report's header, its summary tables and the modelling notes.
#include "reproduce_parts.hpp"

#include <algorithm>

#include <fmt/format.h>
#include <omp.h>

#include "aggpack/core/version.hpp"

namespace aggpack::reproduction {

Table2Errors table2_errors(const std::vector<Table2Outcome>& mixes) {
  Table2Errors e;
  for (const Table2Outcome& m : mixes) {
    if (m.reported_stats().count == 0) continue;
    e.ours += 100.0 * (m.reported_stats().mean - m.row.experiment) / m.row.experiment;
    e.paper += 100.0 * (m.row.paper_mean - m.row.experiment) / m.row.experiment;
    ++e.mixes;
  }
  if (e.mixes > 0) e.ours /= static_cast<double>(e.mixes), e.paper /= static_cast<double>(e.mixes);
  return e;
}

// What was run, how, and in which mode.
void compose_header(Document& doc, const Reproduction& rep, const ReproduceOptions& options) {
  auto& b = doc.blocks;
  const Plan& plan = rep.plan;
  const int threads = options.threads > 0 ? options.threads : omp_get_max_threads();
  b.emplace_back(Paragraph{fmt::format(
      "aggpack {}, {} run: {} per case, {} in {:.0f} s of wall time ({:.1f} min) on {}{}. "
      "Command: {}. Every number below comes from the runs under runs/ (summary.json, timeseries.csv); "
      "reproduce.json has them all.",
      kVersion, options.quick ? "QUICK" : "full", counted(plan.seeds, "seed"), counted(rep.runs, "run"),
      rep.wall_clock_s, rep.wall_clock_s / 60.0, counted(threads, "thread"), options.threads > 0 ? "" : " (all cores)",
      options.command_line.empty() ? std::string("aggpack reproduce") : options.command_line)});
  if (rep.resumed_runs > 0)
    b.emplace_back(Paragraph{fmt::format(
        "{} continued from the checkpoints that an interrupted reproduce into this folder left (--resume): their "
        "results are the bytes an uninterrupted run gives; the wall time above is this invocation's, while each "
        "run's own wall times (the DEM's among them) count its time before the interruption too.",
        rep.resumed_runs == 1 ? std::string("One run was") : fmt::format("{} runs were", rep.resumed_runs))});
  if (options.quick)
    b.emplace_back(Paragraph{
        "This is the QUICK mode, made to check the pipeline in a few minutes: one seed, DEM stopped at 0.25 s "
        "simulated (before the beds are quiet), the pours at 0.6 s and two taps, and two rows of the Table 2 "
        "sensitivity study. Its numbers are "
        "indicative; run aggpack reproduce without --quick for the report of record."});
}

// The summary tables: the examples against the paper and the experiments, and Table 2's errors.
void compose_summary(Document& doc, nlohmann::json& result, const Reproduction& rep) {
  const std::map<std::string, SeedRuns>& examples_run = rep.examples;
  const std::vector<Table2Outcome>& mixes = rep.mixes;
  auto& b = doc.blocks;
  // Headline.
  b.emplace_back(Heading{2, "Summary"});
  Table headline;
  headline.header = {"case", "paper after deposition", "ours after deposition", "paper after DEM", "ours after DEM",
                     "experiment", "ours - experiment"};
  for (const PaperExample& ex_row : rep.paper) {
    const PaperExample* ex = &ex_row;
    const SeedRuns& outcome = examples_run.at(ex->id);
    headline.rows.push_back({ex->title, value_text(ex->after_deposition, 3), stat_text(outcome.deposition),
                             value_text(ex->after_dem, 3), stat_text(outcome.dynamics), value_text(ex->experiment),
                             difference_text(outcome.dynamics.mean, ex->experiment)});
    result["examples"][ex->id] = {
        {"after_deposition", outcome.json(&CaseRun::after_deposition)},
        {"after_dynamics", outcome.json(&CaseRun::after_dynamics)},
        {"paper", {{"after_deposition", ex->after_deposition}, {"after_dynamics", ex->after_dem}}},
        {"experiment", ex->experiment}};
  }
  const Table2Errors e = table2_errors(mixes);
  const bool table2_has_dem = !mixes.empty() && mixes.front().dem_runs().dynamics.count > 0;
  headline.caption = "Packing density: ours is the mean ± sd over seeds of the mean over the virtual boxes.";
  b.emplace_back(headline);
  // Table 2 in percentages, in its own table: its numbers are errors, not densities.
  if (e.mixes > 0) {
    Table errors;
    errors.header = {"case", "mixes", "measured density", "paper's computation − experiment",
                     table2_has_dem ? "ours after DEM − experiment" : "ours after deposition − experiment"};
    const auto [lowest, highest] = std::minmax_element(
        mixes.begin(), mixes.end(), [](const Table2Outcome& a, const Table2Outcome& c) { return a.row.experiment < c.row.experiment; });
    errors.rows.push_back({"Table 2: mean error against the experiments", fmt::format("{}", e.mixes),
                           fmt::format("{:.3f}–{:.3f}", lowest->row.experiment, highest->row.experiment),
                           fmt::format("{:+.1f} %", e.paper), fmt::format("{:+.1f} %", e.ours)});
    errors.caption = "Mean over the mixes of (computed − measured) / measured.";
    b.emplace_back(errors);
  }

}

// The modelling notes, case by case.
void compose_notes(Document& doc, const Reproduction& rep) {
  const std::map<std::string, SeedRuns>& examples_run = rep.examples;
  const std::vector<Table2Outcome>& mixes = rep.mixes;
  auto& b = doc.blocks;
  // Notes, case by case: each run says what its numbers depend on.
  b.emplace_back(Heading{2, "Modelling notes (seed 1 of each case)"});
  const auto notes_of = [&](const std::string& case_name, const CaseRun& r) {
    b.emplace_back(Heading{3, case_name});
    Table notes_table;
    notes_table.header = {"note"};
    for (const std::string& n : r.result.report.modelling_notes()) notes_table.rows.push_back({n});
    b.emplace_back(notes_table);
  };
  for (const PaperExample& ex : rep.paper)
    if (!examples_run.at(ex.id).runs.empty()) notes_of(ex.title, examples_run.at(ex.id).runs.front());
  if (!mixes.empty() && !mixes.front().runs.empty())
    notes_of(fmt::format("Table 2 mix {} (the other mixes differ only in Ca/Fa)", mixes.front().row.mix),
             mixes.front().runs.front());
}

}  // namespace aggpack::reproduction
