#pragma once
#include <optional>
#include <string>
#include <vector>

#include "aggpack/studies/campaign.hpp"

namespace aggpack {

// "Calibrate on one blend, predict the rest" over a grid of one contact parameter (a
// material's rolling friction): every blend was simulated at every grid value; one blend's
// measurement fixes the value, and the others are read off their own curves at it. The
// calibration sees that one blend's measurement and nothing else (reproduce
// --calibrated-table2; README, "Calibrating the grains by DEM").

// One blend's density (carried to its whole grading) at each value of the grid, over seeds.
struct GridCurve {
  int mix = 0;
  double fa_percent = 0.0;              // the sand's share, for the trend
  double measured = 0.0;                // the lab's density
  std::vector<double> values;           // the grid, ascending
  std::vector<SeedStatistics> density;  // at each value
};

// The density a curve gives at `value`, read as straight between grid values. InputError
// outside the grid.
double density_on_grid(const GridCurve& curve, double value);

// Where a curve meets a target density.
struct GridCrossing {
  double value = 0.0;
  // The crossings at the target -+ the larger standard error of the two grid values around it;
  // NaN when a seed count below two leaves the scatter unknown.
  double band_low = 0.0, band_high = 0.0;
  bool at_end = false;  // beyond the grid's end by less than its standard error: the end's value
  // How many times the curve meets the target; more than one: it is not monotone there, and the
  // first crossing (the lowest value) is taken.
  std::size_t crossings = 1;
};
// The first crossing of the curve with `target`, grid value by grid value. None when the target
// lies beyond both ends' densities by more than their standard errors: out of the grid's reach.
// A target beyond both ends but within the standard error of one takes that end (the nearer, if
// both).
std::optional<GridCrossing> crossing_on_grid(const GridCurve& curve, double target);

struct PredictedBlend {
  int mix = 0;
  double fa_percent = 0.0, measured = 0.0;
  double density = 0.0;                    // at the fitted value
  double band_low = 0.0, band_high = 0.0;  // at the ends of the fitted value's band (NaN: unknown)
};

// One choice of the calibration blend and what it predicts for the others.
struct LeaveOneOutChoice {
  int calibration_mix = 0;
  double fa_percent = 0.0;
  std::optional<GridCrossing> fitted;     // none: the measurement is out of the grid's reach
  std::string why_not_fitted;             // then, in words, with the grid's densities
  std::vector<PredictedBlend> predicted;  // the other blends, in the curves' order
  // Over the predicted blends (NaN when not fitted):
  double mean_absolute_error = 0.0, largest_error = 0.0;  // prediction - measurement
  double slope_per_10 = 0.0, lab_slope_per_10 = 0.0;      // against Fa %, per 10 points
};

struct LeaveOneOutStudy {
  std::vector<LeaveOneOutChoice> choices;  // one per calibration blend, in the curves' order
  // The median choice by mean absolute error among the fitted ones (the lower of two middles).
  std::optional<std::size_t> median;
  double lab_slope_per_10 = 0.0;  // over every blend
};

// Every choice of the calibration blend. InputError for fewer than three curves, or curves on
// different grids or on a grid that is not strictly ascending.
LeaveOneOutStudy leave_one_out(const std::vector<GridCurve>& curves);

}  // namespace aggpack
