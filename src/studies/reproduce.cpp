#include "aggpack/studies/reproduce.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <utility>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <iostream>
#include <omp.h>

#include "aggpack/analysis/bulk_density.hpp"
#include "aggpack/core/error.hpp"
#include "aggpack/core/text.hpp"
#include "aggpack/core/version.hpp"
#include "aggpack/dynamics/contact_law_registry.hpp"
#include "aggpack/io/atomic_file.hpp"
#include "aggpack/studies/campaign.hpp"
#include "aggpack/run/predictions.hpp"
#include "aggpack/studies/whole_grading.hpp"
#include "aggpack/report/document.hpp"
#include "aggpack/report/render.hpp"
#include "aggpack/report/svg_plot.hpp"
#include "aggpack/sizes/grading.hpp"

namespace aggpack {

namespace {

namespace fs = std::filesystem;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInch = 0.0254;

// Calls row(fields, line number) for every data row of a shipped CSV table (after its
// header; '#' lines and blank lines skipped).
template <class Row>
void for_each_data_row(const fs::path& file, const std::string& what, Row&& row) {
  std::ifstream in(file);
  if (!in) throw InputError(fmt::format("{}: cannot open {} (give --examples DIR)", file.string(), what));
  std::string line;
  bool header = true;
  for (std::size_t number = 1; std::getline(in, line); ++number) {
    if (line.empty() || line[0] == '#') continue;
    if (std::exchange(header, false)) continue;
    row(split_csv_fields(line), number);
  }
}

// One of the paper's two examples (section 3), as examples/fu2003_examples.csv gives it.
struct PaperExample {
  std::string id, short_name, title, scenario, figure;  // figure: the paper's density-vs-time figure
  double after_deposition = 0, after_dem = 0, experiment = 0;
  double box_spread_min_percent = kNaN, box_spread_max_percent = kNaN;  // over the paper's virtual boxes
};

std::vector<PaperExample> read_examples(const fs::path& file) {
  std::vector<PaperExample> rows;
  for_each_data_row(file, "the paper's examples", [&](const std::vector<std::string>& f, std::size_t number) {
    const auto optional_number = [](const std::string& cell) { return cell.empty() ? kNaN : std::stod(cell); };
    try {
      if (f.size() != 10) throw std::invalid_argument("columns");
      rows.push_back({f[0], f[1], f[2], f[3], f[4], std::stod(f[5]), std::stod(f[6]), std::stod(f[7]),
                      optional_number(f[8]), optional_number(f[9])});
    } catch (const std::exception&) {
      throw InputError(fmt::format("{}:{}: expected id,short_name,title,scenario,figure,after_deposition,after_dem,"
                                   "experiment,box_spread_min_percent,box_spread_max_percent",
                                   file.string(), number));
    }
  });
  for (const char* id : {"example1", "example2"})
    if (std::none_of(rows.begin(), rows.end(), [&](const PaperExample& e) { return e.id == id; }))
      throw InputError(fmt::format("{}: no row for {}", file.string(), id));
  return rows;
}

struct Table2Row {
  int mix = 0;
  std::string state;
  double ca_fa = 0, fa_percent = 0, paper_mean = 0, paper_sd = 0, experiment = 0;
};

std::vector<Table2Row> read_table2(const fs::path& file) {
  std::vector<Table2Row> rows;
  for_each_data_row(file, "the paper's Table 2", [&](const std::vector<std::string>& f, std::size_t number) {
    try {
      if (f.size() < 7) throw std::invalid_argument("too few columns");
      rows.push_back({std::stoi(f[0]), f[1], std::stod(f[2]), std::stod(f[3]), std::stod(f[4]), std::stod(f[5]),
                      std::stod(f[6])});
    } catch (const std::exception&) {
      throw InputError(fmt::format("{}:{}: expected mix_id,state,ca_fa,fa_percent,phi_com_mean,phi_com_sd,phi_exp",
                                   file.string(), number));
    }
  });
  if (rows.empty()) throw InputError(fmt::format("{}: no rows", file.string()));
  return rows;
}

std::string stat_text(const SeedStatistics& s, int decimals = 4) {
  if (s.count == 0) return "—";
  if (std::isnan(s.sd)) return fmt::format("{:.{}f}", s.mean, decimals);
  return fmt::format("{:.{}f} ± {:.{}f}", s.mean, decimals, s.sd, decimals);
}

// "1 seed", "3 seeds".
std::string counted(std::size_t n, const std::string& noun) { return fmt::format("{} {}{}", n, noun, n == 1 ? "" : "s"); }

std::string value_text(double v, int decimals = 4) { return std::isnan(v) ? "—" : fmt::format("{:.{}f}", v, decimals); }

std::string difference_text(double ours, double reference) {
  if (std::isnan(ours) || std::isnan(reference)) return "—";
  return fmt::format("{:+.4f} ({:+.1f} %)", ours - reference, 100.0 * (ours - reference) / reference);
}

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

// Largest minus smallest virtual-box density of seed 1's final bed.
double box_spread(const std::vector<CaseRun>& runs) {
  if (runs.empty()) return kNaN;
  double lo = 1.0, hi = 0.0;
  for (const BoxDensity& box : runs.front().result.report.final.density.boxes) {
    lo = std::min(lo, box.density);
    hi = std::max(hi, box.density);
  }
  return hi - lo;
}

std::size_t particle_count(const CaseRun& r) { return r.particle_count; }

// Figures are kept in memory for the HTML page and written as files for report.md; a plot's
// data goes beside its SVG as a CSV of the same name, for readers who replot it.
class FigureSet {
 public:
  explicit FigureSet(fs::path dir) : dir_(std::move(dir)) {}
  std::string add(const std::string& name, std::string content) {
    const std::string file = "figures/" + name;
    files_[file] = std::move(content);
    return file;
  }
  // `name` ends in .svg; its data is written as the same name with .csv.
  std::string add(const std::string& name, const Plot& plot) {
    data_["figures/" + fs::path(name).replace_extension(".csv").string()] = plot_csv(plot);
    return add(name, svg_plot(plot));
  }
  void write() const {
    fs::create_directories(dir_ / "figures");
    for (const auto& [file, content] : files_) write_file_atomically(dir_ / file, content);
    for (const auto& [file, content] : data_) write_file_atomically(dir_ / file, content);
  }
  [[nodiscard]] const std::map<std::string, std::string>& files() const { return files_; }
  [[nodiscard]] const std::map<std::string, std::string>& data() const { return data_; }

 private:
  fs::path dir_;
  std::map<std::string, std::string> files_, data_;
};

PlotSeries reference_line(const std::string& label, double x0, double x1, double y, const std::string& colour) {
  PlotSeries s{label, {x0, x1}, {y, y}, {}, Mark::Line, true, colour};
  return s;
}

// Density against simulated time, one curve per seed, with the paper's and the experiment's values.
Plot density_time_plot(const PaperExample& ex, const std::vector<CaseRun>& runs) {
  Plot plot;
  plot.title = fmt::format("{}: density during DEM settling (the paper's {})", ex.short_name, ex.figure);
  plot.legend_at_bottom = true;
  plot.x_label = "simulated time (s)";
  plot.y_label = "packing density in the virtual boxes";
  plot.x_column = "time_s";
  plot.y_column = "packing_density";
  double t_max = 0.0, lo = std::min(ex.after_deposition, ex.experiment), hi = std::max(ex.after_dem, ex.experiment);
  for (std::size_t k = 0; k < runs.size(); ++k) {
    PlotSeries s;
    s.label = fmt::format("aggpack, seed {}", runs[k].result.report.scenario.seed);
    for (const TimeSample& sample : runs[k].result.report.series.samples)
      if (!std::isnan(sample.density)) {
        s.x.push_back(sample.time);
        s.y.push_back(sample.density);
        t_max = std::max(t_max, sample.time);
        lo = std::min(lo, sample.density);
        hi = std::max(hi, sample.density);
      }
    plot.series.push_back(std::move(s));
  }
  if (t_max <= 0) t_max = 1.0;
  plot.series.push_back(reference_line(fmt::format("paper after DEM {:.3f}", ex.after_dem), 0, t_max, ex.after_dem, "#555555"));
  plot.series.push_back(reference_line(fmt::format("experiment {:.4f}", ex.experiment), 0, t_max, ex.experiment, "#000000"));
  plot.series.push_back(reference_line(fmt::format("paper after deposition {:.3f}", ex.after_deposition), 0, t_max,
                                       ex.after_deposition, "#aaaaaa"));
  plot.x_range = {{0.0, t_max}};
  plot.y_range = {{std::floor(lo * 100 - 0.5) / 100, std::ceil(hi * 100 + 0.5) / 100}};
  return plot;
}

Box bed_frame(const ParticleStore& particles, const Box& container) {
  Box frame = container;
  double top = container.lo.z;
  for (std::size_t i = 0; i < particles.size(); ++i) top = std::max(top, particles.position[i].z + particles.radius[i]);
  frame.hi.z = std::min(container.hi.z, top);
  return frame;
}

// One column of a component's sieve report (the target, or what was generated) as a curve.
Grading report_curve(const GradingReport& report, bool generated) {
  Grading g;
  for (const GradingReportRow& row : report.rows)
    g.sieves.push_back({"", row.sieve.opening, generated ? row.generated : row.sieve.percent_passing});
  return g;
}

// The blend's target curve (components at the requested Ca/Fa) and the generated one (at the
// generated volumes), at every sieve of either component.
Plot grading_plot(const Table2Row& row, const SizesReport& sizes) {
  const std::vector<SizesComponent>& comps = sizes.components;
  std::set<double> openings;
  for (const SizesComponent& c : comps)
    for (const GradingReportRow& s : c.generated.rows) openings.insert(s.sieve.opening);
  const double r = sizes.order ? sizes.ca_fa_requested : 1.0;
  double generated_volume = 0.0;
  for (const SizesComponent& c : comps) generated_volume += c.generated.solid_volume;
  PlotSeries target{"target after the cut-offs", {}, {}, {}, Mark::LineAndPoints, true, "#000000"};
  PlotSeries generated{"generated by aggpack", {}, {}, {}, Mark::LineAndPoints, false, "#d62728"};
  std::vector<Grading> targets, generated_curves;
  for (const SizesComponent& c : comps) {
    targets.push_back(report_curve(c.generated, false));
    generated_curves.push_back(report_curve(c.generated, true));
  }
  for (const double o : openings) {
    double t = 0, g = 0;
    for (std::size_t k = 0; k < comps.size(); ++k) {
      const double target_weight = comps.size() == 2 ? (k == 0 ? r / (1 + r) : 1 / (1 + r)) : 1.0;
      t += target_weight * percent_passing_at(targets[k], o);
      g += comps[k].generated.solid_volume / generated_volume * percent_passing_at(generated_curves[k], o);
    }
    target.x.push_back(o * 1e3);
    target.y.push_back(t);
    generated.x.push_back(o * 1e3);
    generated.y.push_back(g);
  }
  Plot plot;
  plot.title = fmt::format("Table 2 mix {} ({}), Ca/Fa = {:.2f}: grading of the blend", row.mix, row.state, row.ca_fa);
  plot.x_label = "sieve opening (mm, log scale)";
  plot.y_label = "percent passing by volume";
  plot.x_column = "sieve_opening_mm";
  plot.y_column = "percent_passing_by_volume";
  plot.log_x = true;
  plot.legend_at_bottom = true;
  plot.y_range = {{0.0, 100.0}};
  plot.series = {target, generated};
  return plot;
}

struct Table2Outcome : SeedRuns {
  Table2Row row;
  std::vector<std::pair<double, SeedRuns>> cut_series;  // sand cut-off (in), deposited runs at it
  // The runs at a sand cut-off of the series, if it has it.
  [[nodiscard]] const SeedRuns* at_cut(double cut_in) const {
    for (const auto& [cut, series_runs] : cut_series)
      if (std::abs(cut - cut_in) < 1e-12) return &series_runs;
    return nullptr;
  }
};

// Least-squares slope of y against x, per 10 points of x (two points or more, of distinct x).
double slope_per_10(const std::vector<double>& x, const std::vector<double>& y) { return 10.0 * fit_line(x, y).slope; }

// The trend with the sand fraction: ours, the paper's and the experiments', as fitted slopes.
std::string trend_text(const std::vector<Table2Outcome>& mixes) {
  std::vector<double> fa, ours, paper, measured;
  for (const Table2Outcome& m : mixes) {
    if (m.final_stats().count == 0) continue;
    fa.push_back(m.row.fa_percent);
    ours.push_back(m.final_stats().mean);
    paper.push_back(m.row.paper_mean);
    measured.push_back(m.row.experiment);
  }
  if (fa.size() < 2) return {};
  // The scatter between seeds, where there were several.
  std::optional<double> largest_sd;
  for (const Table2Outcome& m : mixes)
    if (!std::isnan(m.final_stats().sd)) largest_sd = std::max(largest_sd.value_or(0.0), m.final_stats().sd);
  // The virtual boxes and the largest particle, from the first mix's run.
  const RunReport& first = mixes.front().runs.front().result.report;
  const auto [lv_lo, lv_hi] = std::minmax_element(first.final.density.boxes.begin(), first.final.density.boxes.end(),
                                                  [](const BoxDensity& a, const BoxDensity& c) { return a.side < c.side; });
  const std::string scatter =
      largest_sd ? fmt::format("within the scatter between seeds (sd up to {:.3f}, from the small virtual boxes: "
                               "LV = {:.1f}-{:.1f} in against particles of up to {:.2g} in)",
                               *largest_sd, lv_lo->side / kInch, lv_hi->side / kInch, first.final.bed.d_max / kInch)
                 : std::string("though one seed per mix cannot say how much of that is scatter between seeds "
                               "(run with --seeds 3)");
  return fmt::format(
      "Fitted against Fa %, the density changes by {:+.4f} per 10 points of Fa in the experiments, {:+.4f} in the "
      "paper's computation and {:+.4f} in ours: the experiments lose density as sand replaces coarse aggregate "
      "over this range, {}",
      slope_per_10(fa, measured), slope_per_10(fa, paper), slope_per_10(fa, ours),
      std::abs(slope_per_10(fa, ours)) < 0.5 * std::abs(slope_per_10(fa, measured))
          ? fmt::format("while ours change less than half as much, {}. With the sand cut at {:.2g} mm, this range "
                        "of Fa lies on the flat top of the spheres' density curve (README, aggpack sweep).",
                        scatter, 1e3 * first.final.bed.d_min)
          : std::string("and ours follow."));
}

// The settled beds of Table 2 (seed 1 of each mix under --settle-table2, or every seed when the
// scenarios have a [dynamics] table): the protocol, what DEM added, the overlaps and the cost.
std::string table2_settled_text(const std::vector<Table2Outcome>& mixes) {
  std::vector<double> gain, mean_overlap, max_overlap, wall, simulated;
  const SettlingRun* first = nullptr;
  const Material* material = nullptr;
  const QuietCriterion* quiet = nullptr;
  std::size_t beds = 0, cut = 0;
  for (const Table2Outcome& m : mixes)
    for (const CaseRun& r : m.runs) {
      if (!r.result.report.dynamics || r.result.report.dynamics->runs.empty()) continue;
      const SettlingReport& d = *r.result.report.dynamics;
      if (!first) {
        first = &d.runs.front();
        material = &r.result.report.scenario.material;
        quiet = &r.result.report.scenario.dynamics->quiet;
      }
      ++beds;
      cut += d.runs_ended_by_max_time();
      gain.push_back(r.after_dynamics - r.after_deposition);
      mean_overlap.push_back(d.runs.back().last.contacts.mean_overlap);
      max_overlap.push_back(d.runs.back().last.contacts.max_overlap);
      wall.push_back(d.wall_clock_s());
      simulated.push_back(d.simulated_time());
    }
  if (!first) return {};
  const auto range = [](const std::vector<double>& v, const char* spec) {
    const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
    return fmt::format(fmt::runtime(std::string("{:") + spec + "} to {:" + spec + "}"), *lo, *hi);
  };
  const double modulus = material->contact.youngs_modulus;
  return fmt::format(
      "The DEM column: {} settled after deposition{}, with Hertz-Mindlin contacts at a Young's modulus of {:.3g} GPa "
      "({}), a time step of {:.2g} s ({:.2g} of the Rayleigh time of the smallest sphere), until the kinetic energy "
      "stayed below {:.0e} m g d and the box density within {:.0e} for {:g} s{}. DEM raises the density by {} "
      "(each settled bed against its own deposited state), far more than for the monosized and binary examples: "
      "in a graded bed small grains find room in the pores of the large ones as the bed moves. Overlaps at the "
      "end: mean {} and maximum {} of r_i + r_j. Each bed took {} s of wall time for {} s simulated.",
      counted(beds, "bed"), beds == mixes.size() ? " (seed 1 of each mix)" : "", 1e-9 * modulus,
      modulus < 20e9 ? "a reduced stiffness: on mix 3, E/10, E/100 and E/1000 of natural aggregate gave settled "
                       "densities within 0.0032 of each other, docs/validation.md"
                     : "the aggregate's own stiffness",
      first->time_step, first->time_step / first->rayleigh_time, quiet->kinetic_fraction, quiet->density_tolerance,
      quiet->window, cut > 0 ? fmt::format("; {} reached max_time first", counted(cut, "bed")) : std::string(),
      range(gain, "+.4f"), range(mean_overlap, ".1e"), range(max_overlap, ".1e"), range(wall, ".0f"),
      range(simulated, ".2f"));
}

// Each settled Table 2 bed on its own row: its size, how long it ran and how it ended, its
// overlaps and its wall time. None when no bed was settled.
std::optional<Table> table2_settled_table(const std::vector<Table2Outcome>& mixes) {
  Table t;
  t.header = {"mix", "seed", "particles", "after deposition", "after DEM", "steps", "simulated s", "ended by",
              "overlap mean / max", "DEM wall s", "million particle-steps/s"};
  for (const Table2Outcome& m : mixes)
    for (const CaseRun& r : m.runs) {
      if (!r.result.report.dynamics || r.result.report.dynamics->runs.empty()) continue;
      const SettlingReport& d = *r.result.report.dynamics;
      const auto& end = d.runs.back().last.contacts;
      t.rows.push_back({fmt::format("{}", m.row.mix), fmt::format("{}", r.result.report.scenario.seed),
                        fmt::format("{}", particle_count(r)), fmt::format("{:.4f}", r.after_deposition),
                        fmt::format("{:.4f}", r.after_dynamics), fmt::format("{}", d.steps()),
                        fmt::format("{:.3f}", d.simulated_time()), std::string(settle_end_name(d.runs.back().ended_by)),
                        fmt::format("{:.1e} / {:.1e}", end.mean_overlap, end.max_overlap),
                        fmt::format("{:.0f}", d.wall_clock_s()), fmt::format("{:.2f}", 1e-6 * d.particle_steps_per_second())});
    }
  if (t.rows.empty()) return std::nullopt;
  t.caption = "The Table 2 beds settled by DEM, one row per bed: densities are the mean over the virtual boxes, "
              "overlaps relative to r_i + r_j at the end, the wall time is the DEM stage's alone.";
  return t;
}

// Why Table 2 has no DEM column unless the scenarios ask for it: the cost of the first bed at
// the DEM speed our examples just ran at, and what DEM added to them.
std::string table2_dem_text(const std::vector<Table2Outcome>& mixes, const std::map<std::string, SeedRuns>& examples) {
  if (mixes.empty() || mixes.front().runs.empty()) return {};
  if (std::any_of(mixes.begin(), mixes.end(), [](const Table2Outcome& m) { return m.dynamics.count > 0; }))
    return table2_settled_text(mixes);
  const CaseRun& first = mixes.front().runs.front();
  const Material& material = first.result.report.scenario.material;
  const double r_min = 0.5 * first.result.report.final.bed.d_min;
  // The default time step a [dynamics] table would take for these beds.
  const double step = TimeStepRule{}.step(stable_time_scale(material.contact, r_min, material.density));
  const double particle_steps = static_cast<double>(particle_count(first)) * 0.5 / step;
  double speed = 0.0, gain_lo = kNaN, gain_hi = kNaN;
  for (const auto& [id, runs] : examples) {
    for (const CaseRun& r : runs.runs)
      if (r.result.report.dynamics)
        for (const SettlingRun& run : r.result.report.dynamics->runs) speed = std::max(speed, run.particle_steps_per_second);
    const double gain = runs.dynamics.mean - runs.deposition.mean;
    if (std::isnan(gain)) continue;
    gain_lo = std::isnan(gain_lo) ? gain : std::min(gain_lo, gain);
    gain_hi = std::isnan(gain_hi) ? gain : std::max(gain_hi, gain);
  }
  if (!(speed > 0.0)) return fmt::format("These beds are not settled by DEM: {} particles down to {:.2f} mm need time "
                                         "steps of {:.1e} s at the aggregate's stiffness.",
                                         particle_count(first), 2e3 * r_min, step);
  // The cost at a rate measured once, not at this run's own pace: that depends on what else the
  // machine was doing (17 h in one report, 38 h in another).
  constexpr double kReferenceRate = 5.4e6;  // particle-steps/s: a Table 2 bed settled on two cores (BENCHMARKS.md)
  return fmt::format(
      "These beds are not settled by DEM: {} particles down to {:.2f} mm need time steps of {:.1e} s at the "
      "aggregate's stiffness, so half a second of settling is {:.0e} particle-steps, about {:.0f} hours per bed at "
      "{:.1f} million particle-steps per second (a Table 2 bed settled on two cores, BENCHMARKS.md). The examples "
      "show what DEM adds to a deposited bed ({:+.3f} to {:+.3f}). Add a [dynamics] table to a Table 2 scenario to "
      "run it anyway.",
      particle_count(first), 2e3 * r_min, step, particle_steps, particle_steps / kReferenceRate / 3600.0,
      1e-6 * kReferenceRate, gain_lo, gain_hi);
}

// A variant of the sensitivity study: extra --set overrides on Table 2 mix 3.
struct SensitivityCase {
  std::string label;
  std::vector<std::string> sets;
  double sand_cut_in = kNaN;  // the fines cut-off of this variant, when it is one of the cut-off series
};

struct Variant : SeedRuns {
  SensitivityCase spec;
};

// How the density moves with the sand cut-off, from the variants of the cut-off series.
std::string cutoff_text(const std::vector<Variant>& variants) {
  std::vector<std::pair<double, double>> series;  // cut-off (in), mean density
  if (variants.empty()) return {};
  const Variant& shipped = variants.front();  // the plan's first variant is the scenario as shipped
  for (const Variant& v : variants)
    if (!std::isnan(v.spec.sand_cut_in)) series.emplace_back(v.spec.sand_cut_in, v.deposition.mean);
  if (series.size() < 3) return {};
  std::sort(series.begin(), series.end(), std::greater<>());
  std::string list;
  for (const auto& [cut, density] : series) list += fmt::format("{}{:g} in: {:.3f}", list.empty() ? "" : ", ", cut, density);
  return fmt::format(
      "This agreement rests on the sand cut-off, which the paper does not give: for mix 3 the density after "
      "deposition keeps rising as the cut-off falls ({}), with no sign of levelling off, so with the whole sand "
      "our spheres would pack denser than the measured aggregate, as smooth spheres pack denser than crushed "
      "stone. The shipped {:g} in is a cost choice ({} particles), not a converged one.",
      list, shipped.spec.sand_cut_in, shipped.runs.empty() ? std::size_t{0} : shipped.runs.front().particle_count);
}

// What each mode runs. The quick mode exercises every table and figure in a few minutes.
struct Plan {
  int seeds;
  std::vector<std::string> example_sets;  // applied to Examples 1 and 2
  std::vector<std::string> table2_dem;    // applied to seed 1 of each Table 2 mix; none: deposition only
  std::vector<std::string> poured_sets;   // the examples' pour-then-tap runs (exampleN_pour.toml)
  std::vector<double> table2_cuts_in;     // more sand cut-offs for every mix, for its whole grading (in)
  std::string tapping_label;              // that protocol in words
  std::vector<SensitivityCase> sensitivity;
};

Plan make_plan(const ReproduceOptions& o) {
  Plan p;
  p.seeds = o.seeds > 0 ? o.seeds : (o.quick ? 1 : 3);
  const SensitivityCase shipped{"as shipped (5 in walls, sand cut at 0.04 in, mass sampling)", {}, 0.04};
  const auto cut = [](double inches) {
    return SensitivityCase{fmt::format("sand cut at {:g} in", inches),
                           {fmt::format("particles.fine.d_min=\"{:g} in\"", inches)}, inches};
  };
  // Table 2's DEM protocol: a reduced stiffness, E/1000 of natural aggregate (50 GPa), which
  // moved mix 3's settled density by at most 0.0032 against E/10 and E/100 (docs/validation.md,
  // scripts/validate_stiffness.sh), and a bed called settled when the kinetic energy stays below
  // 1e-3 m g d and the box density within 5e-4 for 0.02 s: the density is then within 3e-4 of
  // its value at 1e-5 m g d, for under a third of the simulated time.
  if (o.settle_table2)
    p.table2_dem = {"material.youngs_modulus=5e7",         "material.wall_youngs_modulus=5e7",
                    "dynamics.friction_model=\"mindlin\"", "dynamics.quiet_kinetic_fraction=1e-3",
                    "dynamics.quiet_window=0.02",           o.quick ? "dynamics.max_time=0.05" : "dynamics.max_time=1"};
  // The examples poured, then tapped: 10 taps of 2 g at 30 Hz, 0.15 s apart (a light tapping;
  // docs/validation.md has 100 taps at 2 g and 5 g).
  p.poured_sets = {"tapping.taps=10", "tapping.intensity=2", "tapping.frequency=30", "tapping.rest_time=0.15",
                   "output.formats=[]"};
  p.tapping_label = "10 taps of 2 g at 30 Hz, 0.15 s apart";
  if (o.quick) {
    p.poured_sets = {"tapping.taps=2", "tapping.intensity=2", "tapping.frequency=30", "tapping.rest_time=0.15",
                     "dynamics.max_time=0.6", "output.formats=[]"};
    p.tapping_label = "2 taps of 2 g at 30 Hz, 0.15 s apart (QUICK: the pour cut at 0.6 s)";
  }
  // Every mix at the sand cut-offs of docs/validation.md's whole-grading table (the 0.02 in cut
  // is what narrows the band, and costs some 30 s a run).
  if (o.whole_grading) p.table2_cuts_in = o.quick ? std::vector<double>{0.1, 0.06} : std::vector<double>{0.1, 0.07, 0.02};
  if (o.quick) {
    p.example_sets = {"dynamics.max_time=0.25"};
    p.sensitivity = {shipped, cut(0.1), cut(0.06)};
    return p;
  }
  p.sensitivity = {shipped,
                   cut(0.1),
                   cut(0.06),
                   cut(0.03),
                   cut(0.02),
                   {"container 4.5 in", {"container.side=\"4.5 in\""}},
                   {"container 6 in", {"container.side=\"6 in\""}},
                   {"periodic sides (no walls)", {"container.sides=\"periodic\""}},
                   {"number sampling (the paper's Eq. 11)", {"particles.sampling=\"number\""}}};
  return p;
}

// What a reproduction ran: every case's runs over seeds.
struct Reproduction {
  Plan plan;
  std::vector<PaperExample> paper;           // examples/fu2003_examples.csv
  std::map<std::string, SeedRuns> examples;  // by PaperExample::id
  std::map<std::string, SeedRuns> poured;    // the same, poured then tapped (when exampleN_pour.toml exists)
  std::vector<Table2Outcome> mixes;
  std::vector<Variant> variants;             // of the sensitivity mix, in the plan's order
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
Table2Errors table2_errors(const std::vector<Table2Outcome>& mixes) {
  Table2Errors e;
  for (const Table2Outcome& m : mixes) {
    if (m.final_stats().count == 0) continue;
    e.ours += 100.0 * (m.final_stats().mean - m.row.experiment) / m.row.experiment;
    e.paper += 100.0 * (m.row.paper_mean - m.row.experiment) / m.row.experiment;
    ++e.mixes;
  }
  if (e.mixes > 0) e.ours /= static_cast<double>(e.mixes), e.paper /= static_cast<double>(e.mixes);
  return e;
}

// The paper's tables and the scenarios a reproduction reads, all checked before any run.
struct ReproduceInputs {
  fs::path examples;
  std::vector<Table2Row> table2;
  std::vector<PaperExample> paper;
  [[nodiscard]] fs::path pour_scenario(const PaperExample& ex) const {
    return examples / (fs::path(ex.scenario).stem().string() + "_pour.toml");
  }
};

ReproduceInputs read_inputs(const fs::path& examples) {
  ReproduceInputs in{examples, read_table2(examples / "fu2003_table2.csv"),
                     read_examples(examples / "fu2003_examples.csv")};
  for (const PaperExample& ex : in.paper)
    if (!fs::exists(examples / ex.scenario))
      throw InputError(fmt::format("{}: not found (give --examples DIR, the folder of the shipped scenarios)",
                                   (examples / ex.scenario).string()));
  for (const Table2Row& row : in.table2) {
    const fs::path f = examples / fmt::format("table2_mix{}.toml", row.mix);
    if (!fs::exists(f)) throw InputError(fmt::format("{}: not found (one scenario per Table 2 mix)", f.string()));
  }
  return in;
}

// The shipped variant of the sensitivity study is Table 2's own mix 3: not run twice. So is a
// sand cut-off that every mix's series already ran.
bool runs_of_its_own(const Plan& plan, const SensitivityCase& c) {
  return !c.sets.empty() && std::none_of(plan.table2_cuts_in.begin(), plan.table2_cuts_in.end(),
                                         [&](double cut) { return std::abs(cut - c.sand_cut_in) < 1e-12; });
}

// The runs of every case, over all seeds: what the campaign announces and `--dry-run` lists.
std::vector<std::pair<std::string, std::size_t>> planned_cases(const Plan& plan, const ReproduceInputs& in) {
  const std::size_t seeds = static_cast<std::size_t>(plan.seeds);
  std::vector<std::pair<std::string, std::size_t>> cases;
  for (const PaperExample& ex : in.paper) cases.emplace_back(ex.title, seeds);
  for (const PaperExample& ex : in.paper)
    if (fs::exists(in.pour_scenario(ex))) cases.emplace_back(ex.short_name + " poured and tapped", seeds);
  for (const Table2Row& row : in.table2) {
    cases.emplace_back(fmt::format("Table 2 mix {}", row.mix), seeds);
    for (const double cut : plan.table2_cuts_in)
      cases.emplace_back(fmt::format("Table 2 mix {}, sand cut at {:g} in", row.mix, cut), seeds);
  }
  const auto mix3 = std::find_if(in.table2.begin(), in.table2.end(), [](const Table2Row& r) { return r.mix == 3; });
  const int sensitivity_mix = mix3 != in.table2.end() ? mix3->mix : in.table2.empty() ? 0 : in.table2.front().mix;
  for (const SensitivityCase& c : plan.sensitivity)
    if (runs_of_its_own(plan, c))
      cases.emplace_back(fmt::format("mix {} sensitivity: {}", sensitivity_mix, c.label), seeds);
  return cases;
}

std::size_t total_runs(const std::vector<std::pair<std::string, std::size_t>>& cases) {
  std::size_t runs = 0;
  for (const auto& [what, count] : cases) runs += count;
  return runs;
}

// Runs every case of the plan: Examples 1 and 2, the Table 2 mixes and the sensitivity variants.
Reproduction run_cases(const ReproduceOptions& options, std::ostream& log) {
  const Plan plan = make_plan(options);
  const ReproduceInputs inputs = read_inputs(options.examples);
  const fs::path& examples = inputs.examples;
  const std::vector<Table2Row>& table2 = inputs.table2;
  const std::vector<PaperExample>& paper = inputs.paper;
  const std::size_t seeds = static_cast<std::size_t>(plan.seeds);
  const auto pour_scenario = [&](const PaperExample& ex) { return inputs.pour_scenario(ex); };
  Campaign campaign(options.threads, options.quiet, log, total_runs(planned_cases(plan, inputs)),
                    options.resume ? Campaign::Checkpoints::kept_and_resumed : Campaign::Checkpoints::kept);
  const fs::path runs_dir = options.out / "runs";
  const std::vector<std::string> no_particle_files = {"output.formats=[]"};

  // Beds are kept only where a picture is drawn (seed 1 of Example 2 and of the first mix):
  // a Table 2 bed holds 10^5-10^6 spheres.
  const auto keep_bed_if = [](bool keep, CaseRun run) {
    if (!keep) {
      run.result.report.particles = ParticleStore{};
      run.result.report.deposited.reset();
    }
    return run;
  };

  Reproduction rep;
  rep.plan = plan;
  rep.paper = paper;
  // Examples 1 and 2.
  std::map<std::string, SeedRuns>& examples_run = rep.examples;
  for (const PaperExample& ex : paper)
    for (std::size_t s = 1; s <= seeds; ++s)
      examples_run[ex.id].add(keep_bed_if(
          ex.id == "example2" && s == 1, campaign.run(ex.title, examples / ex.scenario, plan.example_sets, s,
                                                     runs_dir / ex.id / fmt::format("seed_{}", s))));

  // The examples poured, then tapped.
  for (const PaperExample& ex : paper)
    if (fs::exists(pour_scenario(ex)))
      for (std::size_t s = 1; s <= seeds; ++s)
        rep.poured[ex.id].add(keep_bed_if(false, campaign.run(fmt::format("{} poured and tapped", ex.short_name),
                                                              pour_scenario(ex), plan.poured_sets, s,
                                                              runs_dir / (ex.id + "_poured") / fmt::format("seed_{}", s))));

  // Table 2.
  std::vector<Table2Outcome>& mixes = rep.mixes;
  std::vector<std::string> table2_dem_sets = no_particle_files;
  table2_dem_sets.insert(table2_dem_sets.end(), plan.table2_dem.begin(), plan.table2_dem.end());
  for (const Table2Row& row : table2) {
    Table2Outcome m;
    m.row = row;
    for (std::size_t s = 1; s <= seeds; ++s) {
      const bool settle = s == 1 && !plan.table2_dem.empty();
      m.add(keep_bed_if(
          mixes.empty() && s == 1,
          campaign.run(fmt::format("Table 2 mix {}{}", row.mix, settle ? " (with DEM)" : ""),
                       examples / fmt::format("table2_mix{}.toml", row.mix), settle ? table2_dem_sets : no_particle_files,
                       s, runs_dir / fmt::format("table2_mix{}", row.mix) / fmt::format("seed_{}", s))));
    }
    for (const double cut : plan.table2_cuts_in) {
      std::vector<std::string> sets = no_particle_files;
      sets.push_back(fmt::format("particles.fine.d_min=\"{:g} in\"", cut));
      SeedRuns runs;
      for (std::size_t s = 1; s <= seeds; ++s)
        runs.add(keep_bed_if(false, campaign.run(fmt::format("Table 2 mix {}, sand cut at {:g} in", row.mix, cut),
                                                 examples / fmt::format("table2_mix{}.toml", row.mix), sets, s,
                                                 runs_dir / fmt::format("table2_mix{}_cut_{:g}in", row.mix, cut) /
                                                     fmt::format("seed_{}", s))));
      m.cut_series.emplace_back(cut, std::move(runs));
    }
    mixes.push_back(std::move(m));
  }

  // Sensitivity of Table 2 mix 3 to the choices the paper leaves open.
  const Table2Outcome& sensitivity_mix = rep.sensitivity_mix();
  const Table2Row& sensitivity_row = sensitivity_mix.row;
  std::vector<Variant>& variants = rep.variants;
  for (std::size_t v = 0; v < plan.sensitivity.size(); ++v) {
    const SensitivityCase& spec = plan.sensitivity[v];
    Variant variant;
    variant.spec = spec;
    if (spec.sets.empty()) {
      for (CaseRun r : sensitivity_mix.runs) {
        // The study compares deposited beds: the seed that Table 2's DEM protocol settled counts
        // here by its deposited density, as the other variants' seeds do.
        if (!plan.table2_dem.empty()) r.after_dynamics = kNaN;
        variant.add(keep_bed_if(false, std::move(r)));
      }
    } else if (const SeedRuns* done = sensitivity_mix.at_cut(spec.sand_cut_in)) {
      for (const CaseRun& r : done->runs) variant.add(r);
    } else {
      std::vector<std::string> sets = no_particle_files;
      sets.insert(sets.end(), spec.sets.begin(), spec.sets.end());
      for (std::size_t s = 1; s <= seeds; ++s)
        variant.add(keep_bed_if(
            false, campaign.run(fmt::format("mix {} sensitivity: {}", sensitivity_row.mix, spec.label),
                                examples / fmt::format("table2_mix{}.toml", sensitivity_row.mix), sets, s,
                                runs_dir / fmt::format("sensitivity_{}", v) / fmt::format("seed_{}", s))));
    }
    variants.push_back(std::move(variant));
  }
  campaign.clear_progress();
  rep.runs = campaign.runs_done();
  rep.resumed_runs = campaign.runs_resumed();
  rep.kept_checkpoints = campaign.kept_checkpoints();
  rep.threads = options.threads;
  rep.wall_clock_s = campaign.seconds();
  return rep;

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
  const bool table2_has_dem = !mixes.empty() && mixes.front().dynamics.count > 0;
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

// One section per example: its runs, its boxes, its density-time figure, a paragraph and pictures.
void compose_examples(Document& doc, FigureSet& figures, const Reproduction& rep) {
  const std::map<std::string, SeedRuns>& examples_run = rep.examples;
  auto& b = doc.blocks;
  // Examples.
  for (const PaperExample& ex_row : rep.paper) {
    const PaperExample* ex = &ex_row;
    const SeedRuns& outcome = examples_run.at(ex->id);
    const auto& runs = outcome.runs;
    const SeedStatistics &dep = outcome.deposition, &dyn = outcome.dynamics;
    b.emplace_back(Heading{2, ex->title});
    Table t;
    t.header = {"seed", "particles", "after deposition", "after DEM", "DEM ended by", "simulated s", "max overlap / (r_i + r_j)"};
    for (const CaseRun& r : runs) {
      const std::optional<SettlingReport>& d = r.result.report.dynamics;
      t.rows.push_back({fmt::format("{}", r.result.report.scenario.seed), fmt::format("{}", particle_count(r)),
                        value_text(r.after_deposition), value_text(r.after_dynamics),
                        d ? std::string(settle_end_name(d->runs.back().ended_by)) : std::string("—"),
                        fmt::format("{:.2f}", d ? d->simulated_time() : 0.0),
                        fmt::format("{:.1e}", d ? d->runs.back().last.contacts.max_overlap : 0.0)});
    }
    t.rows.push_back({"mean ± sd", "", stat_text(dep), stat_text(dyn), "", "", ""});
    t.rows.push_back({"paper", "", value_text(ex->after_deposition, 3), value_text(ex->after_dem, 3), "", "", ""});
    t.rows.push_back({"experiment", "", "", value_text(ex->experiment), "", "", ""});
    b.emplace_back(t);
    if (!runs.empty()) {
      Table boxes;
      boxes.caption = "Final density in each virtual box (seed 1): the paper's point that the box size hardly matters.";
      boxes.header = {"box side LV (in)", "density"};
      for (const BoxDensity& box : runs.front().result.report.final.density.boxes)
        boxes.rows.push_back({fmt::format("{:.2f}", box.side / kInch), value_text(box.density)});
      b.emplace_back(boxes);
    }
    const std::string fig = figures.add(fmt::format("{}_density_vs_time.svg", ex->id), density_time_plot(*ex, runs));
    b.emplace_back(Figure{fig, fmt::format("Density in the virtual boxes during DEM settling (the paper's {}), one "
                                           "curve per seed; dashed: the paper's values and the experiment.", ex->figure)});
    if (ex->id == "example1")
      b.emplace_back(Paragraph{fmt::format(
          "Example 1. Our drop-and-roll deposition gives {} against the paper's {:.3f}: ours is the exact steepest "
          "descent with three supports (docs/method.md section 3), which sits near the random loose packing "
          "limit for monosized spheres measured away from walls (docs/validation.md), while the paper's value is "
          "below it. DEM settling then gives {} against the paper's {:.3f} and the experiment's {:.4f} ({} "
          "from the experiment). We stay below the references because the DEM starts from a bed that is already "
          "at rest almost everywhere and, with a Mindlin spring, most contacts stick; the paper's own "
          "sliding law (friction_model = \"fu2003\", contacts never stick) reaches the paper's value from the same "
          "start (docs/validation.md), which is most likely how the paper got there.",
          stat_text(dep), ex->after_deposition, stat_text(dyn), ex->after_dem, ex->experiment,
          difference_text(dyn.mean, ex->experiment))});
    else
      b.emplace_back(Paragraph{fmt::format(
          "Example 2. Deposition gives {} against the paper's {:.3f} and DEM {} against the paper's about {:.2f} "
          "and the experiment's {:.3f} ({} from the experiment). Settling adds {:+.4f} here and {:+.4f} to "
          "Example 1 (the paper: {:+.3f} and {:+.3f}): the same sticking contacts hold our bed, and LAMMPS and "
          "LIGGGHTS pours of the same spheres also stay below the paper (docs/validation.md), so its value is at "
          "the high end of what frictional spheres give. The box-size table shows the paper's virtual-box point: "
          "the six LV span {:.4f}, {:.1f} % of the density (the paper: {:g}-{:g} %).",
          stat_text(dep), ex->after_deposition, stat_text(dyn), ex->after_dem, ex->experiment,
          difference_text(dyn.mean, ex->experiment), dyn.mean - dep.mean,
          examples_run.at("example1").dynamics.mean - examples_run.at("example1").deposition.mean,
          ex->after_dem - ex->after_deposition,
          rep.example("example1").after_dem - rep.example("example1").after_deposition, box_spread(runs),
          100.0 * box_spread(runs) / dyn.mean, ex->box_spread_min_percent, ex->box_spread_max_percent)});
    if (ex->id == "example2" && !runs.empty() && runs.front().result.report.deposited) {
      const CaseRun& r = runs.front();
      const Box frame = bed_frame(r.result.report.particles, r.result.report.scenario.container.bounds);
      RenderOptions view;
      view.d_lo = 0.5 * kInch;
      view.d_hi = 1.0 * kInch;
      view.supersample = 2;
      view.legend = true;
      const std::string before = figures.add("example2_after_deposition.png",
                                             encode_png(render_spheres(*r.result.report.deposited, frame, view)));
      const std::string after = figures.add("example2_after_dem.png", encode_png(render_spheres(r.result.report.particles, frame, view)));
      b.emplace_back(Figure{before, "Example 2 after deposition (the paper's Fig. 6a), seed 1: 0.5 in spheres purple, "
                                    "1 in spheres yellow (viridis; colour bar below); the scale bar holds in the picture "
                                    "plane (an orthographic view)."});
      b.emplace_back(Figure{after, "Example 2 after DEM settling (Fig. 6b), seed 1, same view and colours."});
    }
  }

}

// The compaction curves of the poured-and-tapped runs: density against tap number (0: as poured).
Plot compaction_plot(const PaperExample& ex, const std::vector<CaseRun>& runs, const std::string& tapping) {
  Plot plot;
  plot.title = fmt::format("{} poured, then tapped: the compaction curve", ex.short_name);
  plot.legend_at_bottom = true;
  plot.x_label = fmt::format("taps ({})", tapping);
  plot.y_label = "packing density in the virtual boxes";
  plot.x_column = "tap";
  plot.y_column = "packing_density";
  double taps = 1.0, lo = ex.experiment, hi = ex.experiment;
  for (const CaseRun& r : runs)
    for (const TapReport& t : r.result.report.tappings) {
      PlotSeries s;
      s.label = fmt::format("aggpack, seed {}", r.result.report.scenario.seed);
      s.mark = Mark::LineAndPoints;
      if (!std::isnan(t.density_before)) s.x.push_back(0.0), s.y.push_back(t.density_before);
      for (const TapSample& sample : t.samples)
        if (!std::isnan(sample.density)) s.x.push_back(static_cast<double>(sample.tap)), s.y.push_back(sample.density);
      for (const double y : s.y) lo = std::min(lo, y), hi = std::max(hi, y);
      taps = std::max(taps, static_cast<double>(t.taps));
      plot.series.push_back(std::move(s));
    }
  plot.series.push_back(reference_line(fmt::format("experiment {:.4f}", ex.experiment), 0, taps, ex.experiment, "#000000"));
  plot.x_range = {{0.0, taps}};
  plot.y_range = {{std::floor(lo * 100 - 0.5) / 100, std::ceil(hi * 100 + 0.5) / 100}};
  return plot;
}

// How the bed is made, for each example: drop-and-roll, with DEM, poured, poured and tapped,
// against the paper and the experiment, with the wall time per run.
void compose_protocols(Document& doc, FigureSet& figures, nlohmann::json& result, const Reproduction& rep) {
  if (rep.poured.empty()) return;
  auto& b = doc.blocks;
  b.emplace_back(Heading{2, "How the bed is made: four protocols for Examples 1 and 2"});
  Table t;
  t.header = {"case", "protocol", "density (mean ± sd over seeds)", "wall time per run, s", "ours − experiment"};
  const auto mean_of = [](const std::vector<CaseRun>& runs, auto&& seconds) {
    double sum = 0.0;
    for (const CaseRun& r : runs) sum += seconds(r.result.report);
    return runs.empty() ? kNaN : sum / static_cast<double>(runs.size());
  };
  const auto deposition_s = [](const RunReport& r) { return r.deposition ? r.deposition->wall_clock_s : 0.0; };
  const auto dynamics_s = [](const RunReport& r) { return r.dynamics ? r.dynamics->wall_clock_s() : 0.0; };
  const auto tapping_s = [](const RunReport& r) {
    double s = 0.0;
    for (const TapReport& tap : r.tappings) s += tap.wall_clock_s;
    return s;
  };
  // "Until quiet" only where every run's DEM ended quiet; a DEM cut by its time limit says so.
  const auto how_long = [](const std::vector<CaseRun>& runs) {
    std::size_t cut = 0;
    double longest = 0.0;
    for (const CaseRun& r : runs) {
      const std::optional<RunReport::RestState> rest = r.result.report.rest_state();
      if (rest && !rest->settled) ++cut;
      const auto& dynamics = r.result.report.scenario.dynamics;
      if (dynamics) longest = std::max(longest, dynamics->quiet.max_time);
    }
    return cut == 0 ? std::string("until quiet")
                    : fmt::format("cut at its time limit ({:g} s simulated) before quiet in {} of {} runs", longest, cut,
                                  runs.size());
  };
  for (const PaperExample& ex : rep.paper) {
    const auto found = rep.poured.find(ex.id);
    if (found == rep.poured.end()) continue;
    const SeedRuns& deposited = rep.examples.at(ex.id);
    const SeedRuns& poured = found->second;
    std::vector<double> pour_values;
    for (const CaseRun& r : poured.runs) {
      const auto a = r.result.report.analyses.find("pour");
      pour_values.push_back(a != r.result.report.analyses.end() ? a->second.report.density.mean : kNaN);
    }
    const SeedStatistics pour_only = seed_statistics(pour_values);
    const auto seconds = [](double s) {
      return std::isnan(s) ? std::string("—") : fmt::format(fmt::runtime(s < 1.0 ? "{:.2f}" : "{:.1f}"), s);
    };
    const auto row = [&](const std::string& protocol, const SeedStatistics& stats, double wall) {
      t.rows.push_back({ex.short_name, protocol, stat_text(stats), seconds(wall), difference_text(stats.mean, ex.experiment)});
    };
    row("drop-and-roll", deposited.deposition, mean_of(deposited.runs, deposition_s));
    row(fmt::format("drop-and-roll, then DEM {} (the paper's method)", how_long(deposited.runs)), deposited.dynamics,
        mean_of(deposited.runs, [&](const RunReport& r) { return deposition_s(r) + dynamics_s(r); }));
    row(fmt::format("pour: a random gas at solid fraction 0.2, fallen through the DEM {}", how_long(poured.runs)),
        pour_only, mean_of(poured.runs, dynamics_s));
    row("pour, then " + rep.plan.tapping_label, poured.dynamics,
        mean_of(poured.runs, [&](const RunReport& r) { return dynamics_s(r) + tapping_s(r); }));
    t.rows.push_back({ex.short_name, "the paper (drop, then DEM)", value_text(ex.after_dem, 3), "", ""});
    t.rows.push_back({ex.short_name, "experiment", value_text(ex.experiment), "", ""});
    result["protocols"][ex.id] = {
        {"drop_and_roll", deposited.json(&CaseRun::after_deposition)},
        {"drop_and_roll_then_dem", deposited.json(&CaseRun::after_dynamics)},
        {"pour", {{"mean", std::isnan(pour_only.mean) ? nlohmann::json() : nlohmann::json(pour_only.mean)},
                  {"sd", std::isnan(pour_only.sd) ? nlohmann::json() : nlohmann::json(pour_only.sd)},
                  {"values", pour_values}}},
        {"pour_then_tapping", poured.json(&CaseRun::after_dynamics)},
        {"tapping", rep.plan.tapping_label}};
  }
  const int threads = rep.threads > 0 ? rep.threads : omp_get_max_threads();
  t.caption = fmt::format("Wall time per run on {} of this machine: the stages that make the bed (deposition, "
                          "DEM, tapping), not sizes, analysis or outputs.", counted(static_cast<std::size_t>(threads), "thread"));
  b.emplace_back(t);
  b.emplace_back(Paragraph{
      "A pour (README, \"Pour\") inserts the spheres as a random gas and lets them fall through the same DEM as the "
      "paper's settling stage; tapping (README, \"Tapping\") then moves the container up and back and lets the bed "
      "land again, as a lab compacts a sample. The material is the examples' own in every row (docs/validation.md "
      "compares the pours with LAMMPS and LIGGGHTS and has the compaction curves over 100 taps)."});
  for (const PaperExample& ex : rep.paper) {
    const auto found = rep.poured.find(ex.id);
    if (found == rep.poured.end()) continue;
    const std::string fig = figures.add(fmt::format("{}_compaction.svg", ex.id),
                                        compaction_plot(ex, found->second.runs, rep.plan.tapping_label));
    b.emplace_back(Figure{fig, fmt::format("{} poured, then tapped ({}): the density after each tap (taps.csv of "
                                           "runs/{}_poured/seed_N), one curve per seed.",
                                           ex.short_name, rep.plan.tapping_label, ex.id)});
  }
}

// The scenario Table 2's mixes were run from (mix 3's, which they share but for Ca/Fa), if any ran.
const Scenario* table2_scenario(const Reproduction& rep) {
  if (rep.mixes.empty() || rep.sensitivity_mix().runs.empty()) return nullptr;
  const Scenario& sc = rep.sensitivity_mix().runs.front().result.report.scenario;
  return sc.particles.graded && sc.particles.graded->fine ? &sc : nullptr;
}

// CPM's parameters for Table 2, as the runs' predictions take them.
ModelParameters table2_parameters(const Reproduction& rep) {
  const Scenario* sc = table2_scenario(rep);
  return sc ? whole_grading_parameters(*sc, std::nullopt) : default_model_parameters(false);
}

std::string cpm_parameters_text(const Reproduction& rep) {
  const ModelParameters p = table2_parameters(rep);
  return fmt::format("K = {:g}, beta = {:g}", p.compaction_index, p.beta);
}

// CPM against Fa %, on the blend as simulated (the runs' cut-offs) and on the whole grading.
std::vector<PlotSeries> cpm_curves(const Reproduction& rep) {
  const Scenario* base = table2_scenario(rep);
  if (!base) return {};
  const ModelParameters parameters = table2_parameters(rep);
  PlotSeries simulated{"CPM, the blend as simulated", {}, {}, {}, Mark::Line, true, "#9467bd"};
  PlotSeries whole{"CPM, the whole grading", {}, {}, {}, Mark::Line, true, "#ff7f0e"};
  double lo = 100.0, hi = 0.0;
  for (const Table2Outcome& m : rep.mixes) lo = std::min(lo, m.row.fa_percent), hi = std::max(hi, m.row.fa_percent);
  for (double fa = std::floor(lo) - 2.0; fa <= std::ceil(hi) + 2.0 + 1e-9; fa += 0.5) {
    Scenario sc = *base;
    sc.particles.graded->ca_fa = (100.0 - fa) / fa;
    const Predictions p = predict_scenario(sc, parameters);
    simulated.x.push_back(fa), simulated.y.push_back(p.distributions.front().cpm.density);
    whole.x.push_back(fa), whole.y.push_back(p.distributions.back().cpm.density);
  }
  return {simulated, whole};
}

// Table 2 as a concrete lab reports it (ASTM C29): voids content and dry bulk density, ours
// beside the experiment's, from the scenario's particle density.
std::optional<Table> table2_engineers_table(const std::vector<Table2Outcome>& mixes) {
  if (mixes.empty() || mixes.front().runs.empty()) return std::nullopt;
  const double particle_density = mixes.front().runs.front().result.report.scenario.material.density;
  Table t;
  t.header = {"mix", "ours: voids %", "ours: dry bulk density kg/m³", "ours: lb/ft³", "experiment: voids %",
              "experiment: kg/m³", "experiment: lb/ft³"};
  for (const Table2Outcome& m : mixes) {
    const BulkDensity ours = bulk_density(m.final_stats().mean, particle_density),
                      measured = bulk_density(m.row.experiment, particle_density);
    t.rows.push_back({fmt::format("{}", m.row.mix), fmt::format("{:.1f}", ours.voids_percent),
                      fmt::format("{:.0f}", ours.kg_per_m3), fmt::format("{:.1f}", ours.lb_per_ft3),
                      fmt::format("{:.1f}", measured.voids_percent), fmt::format("{:.0f}", measured.kg_per_m3),
                      fmt::format("{:.1f}", measured.lb_per_ft3)});
  }
  t.caption = fmt::format(
      "The densities of Table 2 as a concrete lab reports them (ASTM C29/C29M): voids content 100 (1 − density) % "
      "and dry bulk density, density × the grains' oven-dry density, {:g} kg/m³ (the scenarios' material.density; "
      "the experiments' own is not printed, so theirs is converted at the same). Ours: after DEM where it ran, else "
      "after deposition.",
      particle_density);
  return t;
}

// Table 2: the mixes, Fig. 9, a paragraph, each mix's grading and one bed.
// The paper's Fig. 9 redrawn: density against Fa %, ours, the paper's and the experiments'.
void compose_fig9(Document& doc, FigureSet& figures, const Reproduction& rep) {
  auto& b = doc.blocks;
  const std::vector<Table2Outcome>& mixes = rep.mixes;
  const Plan& plan = rep.plan;
  Plot plot;
  plot.title = "Table 2: density against the sand fraction (the paper's Fig. 9)";
  plot.legend_at_bottom = true;
  plot.x_label = "fine aggregate Fa (% of aggregate volume)";
  plot.y_label = "packing density";
  plot.x_column = "fa_percent";
  plot.y_column = "packing_density";
  // Ours solid, CPM's curves dashed: the caption tells them apart by that.
  PlotSeries dep{"aggpack after deposition", {}, {}, {}, Mark::LineAndPoints, false, "#2ca02c"};
  PlotSeries dyn{"aggpack after DEM", {}, {}, {}, Mark::LineAndPoints, false, "#1f77b4"};
  PlotSeries paper{"paper, computed", {}, {}, {}, Mark::Points, false, "#d62728"};
  PlotSeries exp{"experiment", {}, {}, {}, Mark::Points, false, "#000000"};
  for (const Table2Outcome& m : mixes) {
    dep.x.push_back(m.row.fa_percent), dep.y.push_back(m.deposition.mean);
    dep.y_error.push_back(std::isnan(m.deposition.sd) ? 0.0 : m.deposition.sd);
    if (m.dynamics.count) {
      dyn.x.push_back(m.row.fa_percent), dyn.y.push_back(m.dynamics.mean);
      dyn.y_error.push_back(std::isnan(m.dynamics.sd) ? 0.0 : m.dynamics.sd);
    }
    paper.x.push_back(m.row.fa_percent), paper.y.push_back(m.row.paper_mean), paper.y_error.push_back(m.row.paper_sd);
    exp.x.push_back(m.row.fa_percent), exp.y.push_back(m.row.experiment);
  }
  plot.series = {dep, paper, exp};
  if (!dyn.x.empty()) plot.series.insert(plot.series.begin() + 1, dyn);
  // CPM's curves: the mixes share their gradings and differ in Ca/Fa only.
  const std::vector<PlotSeries> model = cpm_curves(rep);
  plot.series.insert(plot.series.end(), model.begin(), model.end());
  const std::string fig = figures.add("table2_density_vs_fa.svg", plot);
  b.emplace_back(Figure{fig, fmt::format("Computed and measured density against Fa % (the paper's Fig. 9); error "
                                         "bars: {}sd over the four virtual boxes (paper). Dashed: CPM (de Larrard's "
                                         "Compressible Packing Model, {}) on the blend between the runs' cut-offs "
                                         "and on the whole grading.",
                                         plan.seeds > 1 ? "sd over seeds (ours) and "
                                                        : "ours has one seed per mix, so no bar; ",
                                         cpm_parameters_text(rep))});
}

// Each mix's generated grading against its target, and one bed cut open.
void compose_table2_figures(Document& doc, FigureSet& figures, const Reproduction& rep) {
  auto& b = doc.blocks;
  const std::vector<Table2Outcome>& mixes = rep.mixes;
  for (const Table2Outcome& m : mixes) {
    if (m.runs.empty() || !m.runs.front().result.report.sizes) continue;
    const std::string fig = figures.add(fmt::format("table2_mix{}_grading.svg", m.row.mix),
                                        grading_plot(m.row, m.runs.front().result.report.sizes->report));
    const std::vector<SizesComponent>& comps = m.runs.front().result.report.sizes->report.components;
    b.emplace_back(Figure{fig, fmt::format(
        "Mix {}: the blend's generated grading (seed 1, by volume) against its target. The target is the blend "
        "after the cut-offs, renormalised: they remove {:.1f} % of the coarse and {:.1f} % of the sand volume.",
        m.row.mix, comps.size() > 0 ? 100 * comps[0].cut.cut_below : kNaN,
        comps.size() > 1 ? 100 * comps[1].cut.cut_below : kNaN)});
  }
  if (!mixes.empty() && !mixes.front().runs.empty()) {
    const CaseRun& r = mixes.front().runs.front();
    const Box frame = bed_frame(r.result.report.particles, r.result.report.scenario.container.bounds);
    // The sand is 1 mm in a 5 in container, about 5 pixels at 720: 3 x 3 rays per pixel keep it round.
    RenderOptions section;
    section.cut_away = true;
    section.supersample = 3;
    section.legend = true;
    section.log_colour = true;  // the sand's sizes told apart, not all one colour
    const std::string fig = figures.add(fmt::format("table2_mix{}_packing.png", mixes.front().row.mix),
                                        encode_png(render_spheres(r.result.report.particles, frame, section)));
    b.emplace_back(Figure{fig, fmt::format("Table 2 mix {} ({} particles), seed 1, the deposited bed cut through its "
                                           "middle, coloured by diameter (viridis on a log scale of diameter: {:.1f} mm "
                                           "purple to {:.1f} mm yellow, colour bar and scale bar below the picture).",
                                           mixes.front().row.mix, particle_count(r),
                                           1e3 * r.result.report.final.bed.d_min,
                                           1e3 * r.result.report.final.bed.d_max)});
  }

}

// The settled runs of a Table 2 mix for reproduce.json: seed, cost, overlaps, how each ended.
nlohmann::json dem_json(const Table2Outcome& m) {
  nlohmann::json runs = nlohmann::json::array();
  for (const CaseRun& r : m.runs) {
    if (!r.result.report.dynamics || r.result.report.dynamics->runs.empty()) continue;
    const SettlingReport& d = *r.result.report.dynamics;
    runs.push_back({{"seed", r.result.report.scenario.seed},
                    {"wall_clock_s", d.wall_clock_s()},
                    {"simulated_time_s", d.simulated_time()},
                    {"steps", d.steps()},
                    {"particle_steps_per_second", d.particle_steps_per_second()},
                    {"ended_by", settle_end_name(d.runs.back().ended_by)},
                    {"mean_overlap_rel", d.runs.back().last.contacts.mean_overlap},
                    {"max_overlap_rel", d.runs.back().last.contacts.max_overlap}});
  }
  return runs;
}

// A mix's deposited runs at every sand cut-off it was run at (its own, its --whole-grading
// series and, for the sensitivity mix, the cut-off variants), carried to the whole grading by
// CPM with aggpack whole-grading's fit; none below three cut-offs.
std::optional<WholeGradingEstimate> table2_whole_grading(const Reproduction& rep, const Table2Outcome& m) {
  if (m.runs.empty()) return std::nullopt;
  const ModelParameters parameters = table2_parameters(rep);
  std::vector<CutOffPoint> points;
  const auto add = [&](const SeedRuns& runs) {
    if (runs.runs.empty()) return;
    const Scenario& at_cut = runs.runs.front().result.report.scenario;
    const std::optional<double> cut = at_cut.particles.graded->fine->d_min;
    if (!cut) return;
    for (const CutOffPoint& p : points)
      if (std::abs(p.cut_off - *cut) < 1e-12) return;  // one point per cut-off
    points.push_back(cut_off_point(at_cut, parameters, *cut, runs.values(&CaseRun::after_deposition),
                                   runs.runs.front().particle_count));
  };
  add(m);
  for (const auto& cut_runs : m.cut_series) add(cut_runs.second);
  if (&m == &rep.sensitivity_mix())
    for (const Variant& v : rep.variants)
      if (!std::isnan(v.spec.sand_cut_in)) add(v);
  if (points.size() < 3) return std::nullopt;
  return fit_whole_grading(m.runs.front().result.report.scenario, parameters, std::move(points));
}

// The sensitivity mix's cut-off series carried to its whole grading, with its plot.
void compose_whole_grading(Document& doc, FigureSet& figures, nlohmann::json& result, const Reproduction& rep) {
  if (!table2_scenario(rep)) return;
  const std::optional<WholeGradingEstimate> estimate = table2_whole_grading(rep, rep.sensitivity_mix());
  if (!estimate) return;
  const Table2Row& row = rep.sensitivity_mix().row;
  const WholeGradingEstimate& e = *estimate;
  nlohmann::json j = to_json(e);
  j["mix"] = row.mix;
  j["experiment"] = row.experiment;
  result["table2_whole_grading"] = j;
  auto& b = doc.blocks;
  std::string series;
  for (const CutOffPoint& p : e.points)
    series += fmt::format("{}{:g} in: {:.3f}", series.empty() ? "" : ", ", p.cut_off / 0.0254, p.mean);
  // A band wider than 0.04 gives no estimate: then no number is quoted as one.
  const std::string outcome =
      e.trustworthy()
          ? fmt::format("The whole grading then packs at {:.3f} (band {:.3f} to {:.3f}), against {:.3f} measured: "
                        "{:+.3f}.",
                        e.density, e.low, e.high, row.experiment, e.density - row.experiment)
          : fmt::format("Its band, {:.3f} to {:.3f}, is wider than 0.04: these runs give no estimate of the whole "
                        "grading (measured: {:.3f}).",
                        e.low, e.high, row.experiment);
  b.emplace_back(Paragraph{fmt::format(
      "The whole grading of mix {}. Its cut-off series after deposition ({}) is carried below the finest cut by "
      "CPM ({}): the residual simulated − CPM, a line in the volume left out, is extrapolated to nothing left out "
      "(aggpack whole-grading's fit, on these runs). {} The simulation covers {:.1f} % of the blend's volume, the "
      "model the {:.1f} % below the finest cut. {}",
      row.mix, series, cpm_parameters_text(rep), outcome, 100.0 * e.simulated_fraction,
      100.0 * (1.0 - e.simulated_fraction),
      !e.trustworthy() ? "The band is too wide to conclude anything; more seeds and finer cut-offs narrow it."
      : e.low > row.experiment
          ? "Frictionless spheres laid by drop-and-roll pack denser than the measured aggregate once the whole sand "
            "is kept: the remaining difference is the particles, not the cut-off (CPM with a sand looser than "
            "spheres, beta 0.58 to 0.62, falls into the experiments' range; docs/validation.md, all eight mixes)."
          : "The experiment lies within the band or above it.")});
  const std::string fig = figures.add(
      fmt::format("table2_mix{}_whole_grading.svg", row.mix),
      whole_grading_plot(e, row.experiment, fmt::format("Table 2 mix {}: density against the sand cut-off", row.mix)));
  b.emplace_back(Figure{fig, fmt::format("Mix {}: the density after deposition against the volume of the blend the "
                                         "cut-offs leave out (each point a sand cut-off, mean ± se over seeds), CPM on "
                                         "each simulated distribution, and the model fitted to them carried to the "
                                         "whole grading (left edge, with its band); black: the experiment.",
                                         row.mix)});
}

// A whole-grading estimate for a table cell: "0.782 (0.771–0.793)", "wide" past 0.04, or none.
std::string whole_grading_text(const std::optional<WholeGradingEstimate>& e) {
  if (!e) return "—";
  return fmt::format("{:.3f} ({:.3f}–{:.3f}){}", e->density, e->low, e->high, e->trustworthy() ? "" : ", wide");
}

void compose_table2(Document& doc, FigureSet& figures, nlohmann::json& result, const Reproduction& rep) {
  const std::vector<Table2Outcome>& mixes = rep.mixes;
  const std::vector<Variant>& variants = rep.variants;
  auto& b = doc.blocks;
  const Table2Errors errors = table2_errors(mixes);
  // Table 2.
  b.emplace_back(Heading{2, "Table 2: eight concrete aggregate blends"});
  Table t2;
  t2.header = {"mix", "state", "Ca/Fa", "Fa %", "ours after deposition", "ours after DEM", "CPM as simulated",
               "CPM whole grading", "whole grading (band)", "paper (computed)", "experiment", "ours - paper",
               "ours - experiment"};
  nlohmann::json t2_json = nlohmann::json::array();
  std::string cpm_parameters;
  for (const Table2Outcome& m : mixes) {
    const double ours = m.final_stats().mean;
    const std::optional<WholeGradingEstimate> whole = table2_whole_grading(rep, m);
    // The analytic model beside the simulation: the first seed's predictions (the same for every seed).
    const nlohmann::json predictions =
        m.runs.empty() ? nlohmann::json() : m.runs.front().result.summary.value("predictions", nlohmann::json());
    const auto cpm = [&](const char* which) {
      return predictions.contains(which) ? predictions[which]["cpm"]["density"].get<double>() : kNaN;
    };
    if (predictions.contains("parameters"))
      cpm_parameters = fmt::format("K = {:g} ({}), beta = {:g} ({})", predictions["parameters"]["cpm_compaction_index"].get<double>(),
                                   predictions["parameters"]["cpm_compaction_index_source"].get<std::string>(),
                                   predictions["parameters"]["cpm_residual_packing_density"].get<double>(),
                                   predictions["parameters"]["cpm_residual_packing_density_source"].get<std::string>());
    t2.rows.push_back({fmt::format("{}", m.row.mix), m.row.state, fmt::format("{:.2f}", m.row.ca_fa),
                       fmt::format("{:.0f}", m.row.fa_percent), stat_text(m.deposition), stat_text(m.dynamics),
                       value_text(cpm("simulated")), value_text(cpm("whole_grading")), whole_grading_text(whole),
                       fmt::format("{:.3f} ± {:.3f}", m.row.paper_mean, m.row.paper_sd), value_text(m.row.experiment, 3),
                       difference_text(ours, m.row.paper_mean), difference_text(ours, m.row.experiment)});
    t2_json.push_back({{"mix", m.row.mix}, {"state", m.row.state}, {"ca_fa", m.row.ca_fa}, {"fa_percent", m.row.fa_percent},
                       {"after_deposition", m.json(&CaseRun::after_deposition)},
                       {"after_dynamics", m.json(&CaseRun::after_dynamics)},
                       {"paper", {{"mean", m.row.paper_mean}, {"sd", m.row.paper_sd}}},
                       {"experiment", m.row.experiment},
                       {"particles", m.runs.empty() ? 0 : particle_count(m.runs.front())},
                       {"cpm", {{"simulated", cpm("simulated")}, {"whole_grading", cpm("whole_grading")}}},
                       {"whole_grading", whole ? nlohmann::json{{"density", whole->density},
                                                                {"band", {whole->low, whole->high}},
                                                                {"trustworthy", whole->trustworthy()},
                                                                {"cut_offs", whole->points.size()}}
                                               : nlohmann::json()},
                       {"dem", dem_json(m)}});
  }
  t2.caption = "Ours: mean ± sd over seeds (after DEM: over the settled seeds, see below); the differences use ours "
               "after DEM (after deposition when DEM was not run). CPM: de Larrard's Compressible Packing Model on the "
               "simulated distribution (above the cut-offs) and on the whole grading, " +
               (cpm_parameters.empty() ? std::string("not computed") : cpm_parameters) +
               " (README, \"Analytic packing models\"). Whole grading: the mix's deposited densities at its sand "
               "cut-offs (three or more) carried below the finest by CPM, as aggpack whole-grading does, with a band of "
               "two standard errors, \"wide\" beyond 0.04; " +
               (rep.plan.table2_cuts_in.empty()
                    ? std::string("only mix 3's sensitivity runs have a series; reproduce --whole-grading runs every "
                                  "mix at more cut-offs")
                    : fmt::format("every mix also ran at {} in", nlohmann::json(rep.plan.table2_cuts_in).dump())) +
               ".";
  b.emplace_back(t2);
  result["table2"] = t2_json;
  if (std::optional<Table> engineers = table2_engineers_table(mixes)) b.emplace_back(std::move(*engineers));
  compose_fig9(doc, figures, rep);
  {
    b.emplace_back(Paragraph{fmt::format(
        "Table 2. The paper prints neither the sand gradings nor the container nor the fines cut-off. We use its "
        "Table 1 coarse grading, the ASTM C33 mid-band sand (stated in every run's notes), mass sampling (the "
        "generated volume per sieve interval follows the curve; the paper's Eq. 11 makes the curve a number "
        "fraction, see the sensitivity table) and the container and cut-off justified in the scenario files. "
        "Over the eight mixes our densities average {:+.1f} % from the experiments, against the paper's {:+.1f} %. "
        "The paper explained its {:+.0f} % by the spheres standing for irregular aggregate; spheres of a well-graded "
        "blend can pack as densely as the measured aggregate when the sand keeps its volume in its own sizes "
        "(mass sampling). {} {} {}",
        errors.mixes ? errors.ours : kNaN, errors.mixes ? errors.paper : kNaN, errors.paper, cutoff_text(variants),
        trend_text(mixes), table2_dem_text(mixes, rep.examples))});
    if (std::optional<Table> settled = table2_settled_table(mixes)) b.emplace_back(std::move(*settled));
  }
  compose_whole_grading(doc, figures, result, rep);
  compose_table2_figures(doc, figures, rep);
}

// How Table 2 mix 3 moves with the choices the paper leaves open.
void compose_sensitivity(Document& doc, nlohmann::json& result, const Reproduction& rep) {
  const std::vector<Variant>& variants = rep.variants;
  auto& b = doc.blocks;
  const Table2Row& sensitivity_row = rep.sensitivity_mix().row;
  b.emplace_back(Heading{3, fmt::format("How the Table 2 result moves with the choices the paper leaves open (mix {})",
                                        sensitivity_row.mix)});
  Table sens;
  sens.header = {"variant", "particles (seed 1)", "after deposition", "after DEM", "change from the first row"};
  nlohmann::json sens_json = nlohmann::json::array();
  double baseline = kNaN;
  for (const Variant& v : variants) {
    const SeedStatistics &dep = v.deposition, &dyn = v.dynamics;
    const double final_mean = dyn.count ? dyn.mean : dep.mean;
    if (std::isnan(baseline)) baseline = final_mean;
    sens.rows.push_back({v.spec.label, v.runs.empty() ? "—" : fmt::format("{}", particle_count(v.runs.front())),
                         stat_text(dep), stat_text(dyn), fmt::format("{:+.4f}", final_mean - baseline)});
    sens_json.push_back({{"variant", v.spec.label}, {"after_deposition", dep.mean},
                         {"after_dynamics", dyn.count ? nlohmann::json(dyn.mean) : nlohmann::json()}});
  }
  b.emplace_back(sens);
  result["sensitivity"] = sens_json;
  std::string number_sampling;
  for (const Variant& v : variants)
    if (v.spec.label.find("number sampling") != std::string::npos && !v.runs.empty())
      number_sampling = fmt::format(
          " Number sampling (the paper's Eq. 11: the sieve curve read as a number fraction) gives {} for mix {}, "
          "{:+.4f} from mass sampling: the paper's choice alone moves the result by this much.",
          stat_text(v.deposition), sensitivity_row.mix, v.deposition.mean - baseline);
  // How the particle count grows as the cut-off falls: log count against log cut-off, fitted.
  std::vector<double> log_cut, log_count;
  for (const Variant& v : variants)
    if (!std::isnan(v.spec.sand_cut_in) && !v.runs.empty() && v.runs.front().particle_count > 0) {
      log_cut.push_back(std::log(v.spec.sand_cut_in));
      log_count.push_back(std::log(static_cast<double>(v.runs.front().particle_count)));
    }
  const std::string per_halving =
      log_cut.size() >= 2
          ? fmt::format(" ({:.1f} times more per halving of the cut-off here)",
                        std::pow(2.0, -slope_per_10(log_cut, log_count) / 10.0))
          : std::string();
  // Only the variants this mode ran are spoken of (the quick mode runs cut-offs only).
  const bool walls_varied = std::any_of(variants.begin(), variants.end(), [](const Variant& v) {
    return !v.runs.empty() && (v.spec.label.find("container") != std::string::npos ||
                               v.spec.label.find("periodic") != std::string::npos);
  });
  b.emplace_back(Paragraph{
      "A finer sand cut-off keeps more of the sand, which fills voids between the coarse particles, at the cost of "
      "the particle count" + per_halving + "." +
      (walls_varied ? " A wider container or periodic sides show how much wall effect the virtual boxes leave."
                    : std::string()) +
      number_sampling});

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

}  // namespace

ReproducePlan plan_reproduce(const ReproduceOptions& options) {
  const Plan plan = make_plan(options);
  const ReproduceInputs inputs = read_inputs(options.examples);
  ReproducePlan p;
  p.examples = fs::absolute(options.examples).lexically_normal();
  p.seeds = plan.seeds;
  p.cases = planned_cases(plan, inputs);
  p.runs = total_runs(p.cases);
  return p;
}

std::string describe(const ReproducePlan& plan) {
  std::string text = fmt::format("examples: {}\n", plan.examples.string());
  for (const auto& [what, runs] : plan.cases) text += fmt::format("  {:3} x {}\n", runs, what);
  text += fmt::format("runs: {} ({} per case); nothing run or written (--dry-run)\n", plan.runs,
                      plan.seeds == 1 ? std::string("1 seed") : fmt::format("{} seeds", plan.seeds));
  return text;
}

nlohmann::json reproduce(const ReproduceOptions& options, std::ostream& log) {
  if (!options.quiet) fmt::print(log, "aggpack reproduce: scenarios from {}\n", options.examples.string());
  const Reproduction rep = run_cases(options, log);
  FigureSet figures(options.out);
  Document doc;
  doc.title = "Does aggpack reproduce Fu and Dekelbab (2003)?";
  nlohmann::json result;
  compose_header(doc, rep, options);
  compose_summary(doc, result, rep);
  compose_examples(doc, figures, rep);
  compose_protocols(doc, figures, result, rep);
  compose_table2(doc, figures, result, rep);
  compose_sensitivity(doc, result, rep);
  compose_notes(doc, rep);
  result["aggpack_version"] = kVersion;
  result["mode"] = options.quick ? "quick" : "full";
  result["seeds"] = rep.plan.seeds;
  result["runs"] = rep.runs;
  result["resumed_runs"] = rep.resumed_runs;
  result["wall_clock_s"] = rep.wall_clock_s;
  result["command_line"] = options.command_line;
  result["examples_dir"] = fs::absolute(options.examples).lexically_normal().string();
  nlohmann::json figure_list = nlohmann::json::array();
  for (const auto& [file, content] : figures.files()) figure_list.push_back(file);
  result["figures"] = figure_list;
  nlohmann::json data_list = nlohmann::json::array();  // each plot's data, beside its SVG
  for (const auto& [file, content] : figures.data()) data_list.push_back(file);
  result["figure_data"] = data_list;

  figures.write();
  write_file_atomically(options.out / "report.md", to_markdown(doc));
  write_file_atomically(options.out / "report.html", to_html(doc, figures.files()));
  write_file_atomically(options.out / "reproduce.json", result.dump(2) + "\n");
  remove_checkpoints(rep.kept_checkpoints);
  if (!options.quiet)
    fmt::print(log, "report: {} and {} ({:.1f} min)\n", (options.out / "report.html").string(),
               (options.out / "report.md").string(), rep.wall_clock_s / 60.0);
  return result;
}

}  // namespace aggpack
