#pragma once
// The parts of `aggpack reproduce` (reproduce.cpp and the reproduce_*.cpp beside it, one per
// section of the report): what a reproduction ran, and each section's composer. Private to
// the studies module.
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "aggpack/report/document.hpp"
#include "aggpack/report/svg_plot.hpp"
#include "aggpack/studies/campaign.hpp"
#include "aggpack/studies/leave_one_out.hpp"
#include "aggpack/studies/reproduce.hpp"
#include "aggpack/studies/whole_grading.hpp"

namespace aggpack::reproduction {

namespace fs = std::filesystem;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInch = 0.0254;

// One of the paper's two examples (section 3), as examples/fu2003_examples.csv gives it.
struct PaperExample {
  std::string id, short_name, title, scenario, figure;  // figure: the paper's density-vs-time figure
  double after_deposition = 0, after_dem = 0, experiment = 0;
  double box_spread_min_percent = kNaN, box_spread_max_percent = kNaN;  // over the paper's virtual boxes
};

struct Table2Row {
  int mix = 0;
  std::string state;
  double ca_fa = 0, fa_percent = 0, paper_mean = 0, paper_sd = 0, experiment = 0;
};

// One case's runs over seeds, with the statistics of its two densities kept in step.
struct SeedRuns {
  std::vector<CaseRun> runs;
  SeedStatistics deposition, dynamics;

  void add(CaseRun run) {
    runs.push_back(std::move(run));
    deposition = seed_statistics(values(&CaseRun::after_deposition));
    dynamics = seed_statistics(values(&CaseRun::after_dynamics));
  }
  [[nodiscard]] std::vector<double> values(double CaseRun::*member) const {
    std::vector<double> v;
    for (const CaseRun& r : runs) v.push_back(r.*member);
    return v;
  }
  [[nodiscard]] const SeedStatistics& final_stats() const { return dynamics.count ? dynamics : deposition; }
  // {mean, sd, values} for reproduce.json; nulls and no values for a stage that did not run.
  [[nodiscard]] nlohmann::json json(double CaseRun::*member) const {
    const SeedStatistics& s = member == &CaseRun::after_deposition ? deposition : dynamics;
    const auto or_null = [](double v) { return std::isnan(v) ? nlohmann::json() : nlohmann::json(v); };
    return {{"mean", or_null(s.mean)}, {"sd", or_null(s.sd)},
            {"values", s.count ? nlohmann::json(values(member)) : nlohmann::json::array()}};
  }
};

struct Table2Outcome : SeedRuns {
  Table2Row row;
  // Table 2's DEM protocol (--settle-table2): seed 1 deposited again on the protocol's own bed
  // and settled there. Empty when none ran, or when the mix's own runs were settled (a
  // [dynamics] table in the scenarios).
  SeedRuns settled;
  std::vector<std::pair<double, SeedRuns>> cut_series;  // sand cut-off (in), deposited runs at it
  // The runs that give the DEM column: the protocol's own bed, else the mix's runs.
  [[nodiscard]] const SeedRuns& dem_runs() const { return settled.runs.empty() ? *this : settled; }
  // The mix's reported density: after DEM where it ran (on the protocol's own bed, which
  // SeedRuns::final_stats cannot see), else after deposition.
  [[nodiscard]] const SeedStatistics& reported_stats() const {
    return dem_runs().dynamics.count ? dem_runs().dynamics : deposition;
  }
  // The runs at a sand cut-off of the series, if it has it.
  [[nodiscard]] const SeedRuns* at_cut(double cut_in) const {
    for (const auto& [cut, series_runs] : cut_series)
      if (std::abs(cut - cut_in) < 1e-12) return &series_runs;
    return nullptr;
  }
};

// A variant of the sensitivity study: extra --set overrides on Table 2 mix 3.
struct SensitivityCase {
  std::string label;
  std::vector<std::string> sets;
  double sand_cut_in = kNaN;  // the fines cut-off of this variant, when it is one of the cut-off series
};

struct Variant : SeedRuns {
  SensitivityCase spec;
};

// Table 2 predicted from one calibration mix (--calibrated-table2): every mix poured by the DEM
// from one scenario with a material per component, at each grid value of one material's rolling
// friction (the one unknown; the other material keeps its literature value).
struct CalibratedTable2Plan {
  std::string scenario;              // in the examples folder
  std::string material;              // whose rolling friction the grid varies
  std::vector<double> values;        // the grid, ascending
  std::vector<std::string> bed;      // the overrides that make the (reduced) bed
  std::string bed_label;             // those in words, for the report
};

// Table 2 with shape (--shaped-table2): every mix poured by the DEM from the stone-and-sand
// scenario on one reduced bed, twice: its stone as spheres, and as rigid grains of a stated
// shape (the sand stays spheres), each carried to its whole grading as the calibrated study's.
struct ShapedTable2Plan {
  std::string scenario;          // in the examples folder
  std::string shape;             // the stone's shape table, as particles.coarse.shape takes it
  std::string shape_label;       // that in words, with where its values come from
  std::vector<std::string> grains_sets;  // the overrides of the grains' runs (the shape among them)
  std::vector<std::string> bed;  // the overrides that make the (reduced) bed, for both runs
  std::string bed_label;         // those in words, for the report
};

// What each mode runs. The quick mode exercises every table and figure in a few minutes.
struct Plan {
  int seeds;
  std::vector<std::string> example_sets;  // applied to Examples 1 and 2
  std::vector<std::string> table2_dem;    // seed 1 of each Table 2 mix run again with these and settled; none: no DEM
  std::vector<std::string> poured_sets;   // the examples' pour-then-tap runs (exampleN_pour.toml)
  std::vector<double> table2_cuts_in;     // more sand cut-offs for every mix, for its whole grading (in)
  std::string tapping_label;              // that protocol in words
  std::vector<SensitivityCase> sensitivity;
  std::optional<CalibratedTable2Plan> calibrated_table2;
  std::optional<ShapedTable2Plan> shaped_table2;
  std::optional<MaterialsCurve> table2_materials;  // computed by the caller: predicted, nothing simulated
};

// A Table 2 mix of the calibrated study: its runs at each grid value, in the plan's order.
struct CalibratedMix {
  Table2Row row;
  std::vector<SeedRuns> at_value;
};

// A Table 2 mix of the shaped study: its runs with the stone as spheres and as grains.
struct ShapedMix {
  Table2Row row;
  SeedRuns spheres, grains;
};

// What a reproduction ran: every case's runs over seeds.
struct Reproduction {
  Plan plan;
  std::vector<PaperExample> paper;           // examples/fu2003_examples.csv
  std::map<std::string, SeedRuns> examples;  // by PaperExample::id
  std::map<std::string, SeedRuns> poured;    // the same, poured then tapped (when exampleN_pour.toml exists)
  std::vector<Table2Outcome> mixes;
  std::vector<Variant> variants;             // of the sensitivity mix, in the plan's order
  std::vector<CalibratedMix> calibrated;     // --calibrated-table2, in Table 2's order
  std::vector<ShapedMix> shaped;             // --shaped-table2, in Table 2's order
  std::size_t runs = 0;
  std::size_t resumed_runs = 0;  // continued from an interrupted reproduce's checkpoints
  std::vector<fs::path> kept_checkpoints;  // removed once the report is written
  double wall_clock_s = 0.0;
  int threads = 0;
  // Mix 3 (the paper's own example of a blend), or the first mix.
  [[nodiscard]] const PaperExample& example(std::string_view id) const {
    return *std::find_if(paper.begin(), paper.end(), [&](const PaperExample& e) { return e.id == id; });
  }
  [[nodiscard]] const Table2Outcome& sensitivity_mix() const {
    const auto mix3 = std::find_if(mixes.begin(), mixes.end(), [](const Table2Outcome& m) { return m.row.mix == 3; });
    return mix3 != mixes.end() ? *mix3 : mixes.front();
  }
};

// Table 2's mean errors against the experiments, in per cent, over the mixes that have a value.
struct Table2Errors {
  double ours = 0.0, paper = 0.0;
  std::size_t mixes = 0;
};

// The paper's tables and the scenarios a reproduction reads, all checked before any run.
struct ReproduceInputs {
  fs::path examples;
  std::vector<Table2Row> table2;
  std::vector<PaperExample> paper;
  [[nodiscard]] fs::path pour_scenario(const PaperExample& ex) const {
    return examples / (fs::path(ex.scenario).stem().string() + "_pour.toml");
  }
};

// Figures are kept in memory for the HTML page and written as files for report.md; a plot's
// data goes beside its SVG as a CSV of the same name, for readers who replot it.
class FigureSet {
 public:
  explicit FigureSet(fs::path dir) : dir_(std::move(dir)) {}
  std::string add(const std::string& name, std::string content);
  // `name` ends in .svg; its data is written as the same name with .csv.
  std::string add(const std::string& name, const Plot& plot);
  void write() const;
  [[nodiscard]] const std::map<std::string, std::string>& files() const { return files_; }
  [[nodiscard]] const std::map<std::string, std::string>& data() const { return data_; }

 private:
  fs::path dir_;
  std::map<std::string, std::string> files_, data_;
};

// reproduce_inputs.cpp: the paper's tables (examples/fu2003_*.csv) and the scenarios, all
// checked before any run.
ReproduceInputs read_inputs(const fs::path& examples);

// reproduce_figures.cpp: the helpers the sections share.
std::string stat_text(const SeedStatistics& s, int decimals = 4);
// "1 seed", "3 seeds".
std::string counted(std::size_t n, const std::string& noun);
std::string value_text(double v, int decimals = 4);
std::string difference_text(double ours, double reference);
inline std::size_t particle_count(const CaseRun& r) { return r.particle_count; }
// Least-squares slope of y against x, per 10 points of x (two points or more, of distinct x).
double slope_per_10(const std::vector<double>& x, const std::vector<double>& y);
PlotSeries reference_line(const std::string& label, double x0, double x1, double y, const std::string& colour);
// The container cut down to the top of the bed, for its pictures.
Box bed_frame(const ParticleStore& particles, const Box& container);

// reproduce_summary.cpp: the header, the summary tables and the modelling notes.
Table2Errors table2_errors(const std::vector<Table2Outcome>& mixes);
void compose_header(Document& doc, const Reproduction& rep, const ReproduceOptions& options);
void compose_summary(Document& doc, nlohmann::json& result, const Reproduction& rep);
void compose_notes(Document& doc, const Reproduction& rep);

// reproduce_examples.cpp: Examples 1 and 2.
void compose_examples(Document& doc, FigureSet& figures, const Reproduction& rep);

// reproduce_protocols.cpp: the examples made by the four protocols.
void compose_protocols(Document& doc, FigureSet& figures, nlohmann::json& result, const Reproduction& rep);

// reproduce_table2.cpp: Table 2, Fig. 9, the settled and engineers' tables, the gradings.
// The scenario Table 2's mixes were run from (mix 3's, which they share but for Ca/Fa), if any ran.
const Scenario* table2_scenario(const Reproduction& rep);
// CPM's parameters for Table 2, as the runs' predictions take them.
ModelParameters table2_parameters(const Reproduction& rep);
std::string cpm_parameters_text(const Reproduction& rep);
void compose_table2(Document& doc, FigureSet& figures, nlohmann::json& result, const Reproduction& rep);
// What Table 2 can decide: four states' materials, the within-state pairs' slopes beside the
// lab's overall one, the shipped stone and sand's predicted curve against the eight values, and
// the per-material measurements that would decide (reproduce_table2_materials.cpp).
void compose_table2_materials(Document& doc, FigureSet& figures, nlohmann::json& result, const Reproduction& rep);

// reproduce_whole_grading.cpp: the Table 2 mixes carried to their whole grading.
std::optional<WholeGradingEstimate> table2_whole_grading(const Reproduction& rep, const Table2Outcome& m);
// A whole-grading estimate for a table cell: "0.782 (0.771–0.793)", "wide" past 0.04, or none.
std::string whole_grading_text(const std::optional<WholeGradingEstimate>& e);
void compose_whole_grading(Document& doc, FigureSet& figures, nlohmann::json& result, const Reproduction& rep);

// reproduce_calibrated.cpp: Table 2 predicted from one calibration mix (--calibrated-table2).
// A calibrated-study run's density carried to its whole grading by CPM's own increment:
// simulated + CPM(whole grading) - CPM(simulated distribution).
double carried_density(const CaseRun& run);
// Every choice of the calibration mix; none when the study did not run.
std::optional<LeaveOneOutStudy> calibrated_study(const Reproduction& rep);
// Table 2's column of the median choice's predictions: "0.7412 (0.7390-0.7433)", "the calibration
// mix", or why nothing was predicted.
std::string calibrated_cell(const LeaveOneOutStudy& study, int mix);
void compose_calibrated_table2(Document& doc, FigureSet& figures, nlohmann::json& result, const Reproduction& rep);

// reproduce_shaped.cpp: Table 2 with the stone as rigid grains (--shaped-table2).
// Table 2's column of the grains carried to the whole grading: "0.7412 ± 0.0021", or "—".
std::string shaped_cell(const Reproduction& rep, int mix);
void compose_shaped_table2(Document& doc, FigureSet& figures, nlohmann::json& result, const Reproduction& rep);

// reproduce_sensitivity.cpp: how Table 2 mix 3 moves with the choices the paper leaves open.
// How the density moves with the sand cut-off, from the variants of the cut-off series.
std::string cutoff_text(const std::vector<Variant>& variants);
void compose_sensitivity(Document& doc, nlohmann::json& result, const Reproduction& rep);

}  // namespace aggpack::reproduction
