#pragma once
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace aggpack {

enum class Mark { Line, Points, LineAndPoints };

struct PlotSeries {
  std::string label;
  std::vector<double> x, y;
  std::vector<double> y_error;  // half-widths of error bars; empty: none
  Mark mark = Mark::Line;
  bool dashed = false;
  std::string colour;  // empty: the next colour of the palette
};

// An axis with round tick values covering the data (decades on a log axis).
struct Axis {
  double lo = 0.0, hi = 1.0;
  bool log = false;
  std::vector<double> ticks;
};
Axis make_axis(double data_lo, double data_hi, bool log);

struct Plot {
  std::string title, x_label, y_label;
  // The CSV's column names for x and y, with their units (plot_csv): "time_s", "packing_density".
  std::string x_column = "x", y_column = "y";
  bool log_x = false;
  bool legend_at_bottom = false;  // bottom right instead of top right
  std::optional<std::pair<double, double>> x_range, y_range;  // fixed instead of fitted to the data
  std::vector<PlotSeries> series;
};

// The axes a plot will draw: fitted to every series' points (and error bars) or fixed.
std::pair<Axis, Axis> plot_axes(const Plot& plot);

// A standalone SVG (640 x 400) with axes, ticks, labels, a legend and every series. The root
// element carries data-x-range and data-y-range with the axis ends, for scripts and tests.
std::string svg_plot(const Plot& plot);

// The plot's data, to read beside its SVG: a header `series,<x_column>,<y_column>` (and
// `<y_column>_error`, the error bars' half-width, when a series has error bars), then one row
// a point, series after series as drawn, every digit of each value. A label with a comma or a
// quote is quoted (RFC 4180).
std::string plot_csv(const Plot& plot);

}  // namespace aggpack
