#pragma once
#include <filesystem>
#include <optional>
#include <ostream>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "aggpack/io/scenario.hpp"
#include "aggpack/run/predictions.hpp"
#include "aggpack/report/svg_plot.hpp"

namespace aggpack {

// `aggpack whole-grading SCENARIO --cut-offs L1,L2,L3`: the density of the whole grading of a
// scenario that simulates its grading above a cut-off (README, "Analytic packing models").
// The scenario is simulated at each cut-off of its finest grading (seeds 1..N); at each, CPM
// (calibrated, or with the defaults) is evaluated on the same simulated distribution, and the
// residual r = simulated - CPM is fitted by least squares as r = r0 + s f, f the volume
// fraction of the whole grading the cut leaves out. The whole grading's density is CPM's on the
// whole grading plus r0 (the residual extrapolated to nothing left out), with a band of two
// standard errors of r0: the scatter about the line and each point's own standard error over
// seeds, carried through the fit. The simulated part is the volume above the finest cut; the
// rest is modelled.
struct WholeGradingOptions {
  std::filesystem::path scenario;
  ScenarioOverrides overrides;
  std::vector<double> cut_offs;  // m, of the finest grading's d_min
  std::vector<std::string> cut_off_texts;  // each as the user typed it, for messages (empty: none)
  int seeds = 3;
  std::optional<std::filesystem::path> calibration;  // CPM's K and beta; none: the scenario's or the defaults
  int threads = 0;
  bool quiet = false;
};

struct CutOffPoint {
  double cut_off = 0.0;          // m
  double left_out = 0.0;         // volume fraction of the whole grading below the cuts
  std::size_t spheres = 0;       // of the first seed's bed
  std::vector<double> density;   // per seed
  double mean = 0.0, standard_error = 0.0;
  double cpm = 0.0;              // on the same distribution
  [[nodiscard]] double residual() const { return mean - cpm; }
};

struct WholeGradingEstimate {
  std::string scenario, key;      // the scenario file, the cut-off's key (particles.fine.d_min, ...)
  ModelParameters parameters;
  std::vector<CutOffPoint> points;  // coarsest cut first
  double residual_at_zero = 0.0, residual_standard_error = 0.0, residual_slope = 0.0;
  double cpm_whole = 0.0;           // CPM on the whole grading
  double density = 0.0, low = 0.0, high = 0.0;  // the whole grading's estimate and band
  double simulated_fraction = 0.0;  // of the whole grading's volume, at the finest cut
  double particle_density = 0.0;    // kg/m3, the scenario's material.density (bulk density and voids)
  // A band wider than 0.04 (as wide as the differences between blends) is no estimate.
  [[nodiscard]] bool trustworthy() const { return high - low <= 0.04; }
};

// The least-squares line through (x_k, y_k): intercept, slope and the intercept's standard
// error, from the scatter about the line (none for two points) and from the points' own
// standard errors `y_error` (the intercept is a linear combination of the y_k; empty: none),
// added in quadrature. InputError for fewer than two points or equal x.
struct LineFit {
  double intercept = 0.0, slope = 0.0, intercept_standard_error = 0.0;
};
LineFit fit_line(const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& y_error = {});

// The volume fraction of a graded scenario's whole grading (of its blend, for a coarse/fine mix)
// that its cut-offs leave out.
double left_out_fraction(const GradedParticles& graded);
// The key of the cut-off a whole-grading series varies: the finest grading's d_min.
// Refuses cut-offs at or below the smallest sieve of the finest grading (clamped there, they
// would all simulate the same uncut bed), naming them and the sieve.
// `texts`: the cut-offs as the user typed them (empty: none).
void check_cut_offs(const GradedParticles& graded, std::span<const double> cuts, std::span<const std::string> texts);
std::string cut_off_key(const GradedParticles& graded);
// "key=cut", every digit kept: the override that sets a cut-off.
std::string cut_off_assignment(const std::string& key, double cut);
// `base` with that override, quoted in messages as "--cut-offs <the cut as typed>" (the
// text of `texts` at the cut's place in `cut_offs`; without texts, the cut in metres).
ScenarioOverrides with_cut_off(ScenarioOverrides base, const std::string& key, double cut,
                               const std::vector<double>& cut_offs, const std::vector<std::string>& texts);
// CPM's parameters for a whole-grading estimate of `whole`: a calibration file given, else the
// scenario's models.calibration, else the defaults for its protocol.
ModelParameters whole_grading_parameters(const Scenario& whole, const std::optional<std::filesystem::path>& calibration);
// A cut-off point from its scenario (left out, CPM) and its densities over seeds.
CutOffPoint cut_off_point(const Scenario& at_cut, const ModelParameters& parameters, double cut_off,
                          std::vector<double> density, std::size_t spheres);

// The fit: the residuals of `points` (any order) as a line in the volume left out, carried to
// nothing left out and added to CPM on the whole grading of `whole` (a scenario that samples a
// grading, as every point's does). InputError for fewer than three points.
WholeGradingEstimate fit_whole_grading(const Scenario& whole, const ModelParameters& parameters,
                                       std::vector<CutOffPoint> points);

// Simulates the series and fits it.
WholeGradingEstimate estimate_whole_grading(const WholeGradingOptions& options, std::ostream& log);
nlohmann::json to_json(const WholeGradingEstimate& estimate);
std::string describe(const WholeGradingEstimate& estimate);
// The density against the volume left out: the simulated points (mean +- se over seeds), CPM on
// each simulated distribution, the fitted model (CPM + the residual line) and its value for the
// whole grading with the band, and a measured density at the whole grading when given.
std::string whole_grading_svg(const WholeGradingEstimate& estimate, std::optional<double> measured = std::nullopt,
                              const std::string& title = {});
// That figure as a Plot, for its data (plot_csv) beside the SVG.
Plot whole_grading_plot(const WholeGradingEstimate& estimate, std::optional<double> measured = std::nullopt,
                        const std::string& title = {});

}  // namespace aggpack
