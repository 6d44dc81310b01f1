#include "aggpack/report/svg_plot.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "aggpack/core/text.hpp"
#include "aggpack/core/xml_text.hpp"

namespace aggpack {

namespace {

constexpr double kWidth = 640, kHeight = 400;
constexpr double kLeft = 70, kRight = 20, kTop = 36, kBottom = 52;
constexpr std::array<const char*, 8> kPalette{"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e",
                                              "#9467bd", "#8c564b", "#e377c2", "#17becf"};

// Decimals enough to tell the ticks apart exactly: a step of 0.0025 needs four (0.7075,
// 0.7100, ...), not the three its order of magnitude suggests.
int tick_decimals(double step) {
  for (int decimals = 0; decimals < 15; ++decimals) {
    const double scaled = step * std::pow(10.0, decimals);
    if (std::abs(scaled - std::round(scaled)) < 1e-6 * std::max(1.0, scaled)) return decimals;
  }
  return 15;
}

std::string tick_label(double v, const Axis& axis) {
  if (axis.log) return fmt::format("{:g}", v);
  const double step = axis.ticks.size() > 1 ? axis.ticks[1] - axis.ticks[0] : 1.0;
  return fmt::format("{:.{}f}", v, tick_decimals(step));
}

struct Rect {
  double x, y, w, h;
  [[nodiscard]] bool contains(double px, double py, double margin) const {
    return px >= x - margin && px <= x + w + margin && py >= y - margin && py <= y + h + margin;
  }
};


// `text` in lines of at most `width` characters, broken at spaces (a longer word stands alone).
std::vector<std::string> wrapped(const std::string& text, std::size_t width) {
  std::vector<std::string> lines(1);
  std::istringstream words(text);
  for (std::string word; words >> word;) {
    if (!lines.back().empty() && display_width(lines.back()) + 1 + display_width(word) > width)
      lines.emplace_back();
    lines.back() += (lines.back().empty() ? "" : " ") + word;
  }
  return lines;
}

}  // namespace

Axis make_axis(double data_lo, double data_hi, bool log) {
  if (!(data_lo <= data_hi) || !std::isfinite(data_lo) || !std::isfinite(data_hi))
    throw std::invalid_argument("make_axis: the data range must be finite and ordered");
  Axis axis;
  axis.log = log;
  if (log) {
    if (data_lo <= 0.0) throw std::invalid_argument("make_axis: a log axis needs positive data");
    const double lo_exp = std::floor(std::log10(data_lo) + 1e-9), hi_exp = std::ceil(std::log10(data_hi) - 1e-9);
    axis.lo = std::pow(10.0, lo_exp);
    axis.hi = std::pow(10.0, std::max(hi_exp, lo_exp + 1));
    const bool few_decades = std::log10(axis.hi / axis.lo) <= 2.5;
    for (double decade = axis.lo; decade <= axis.hi * (1 + 1e-9); decade *= 10.0)
      for (const double m : {1.0, 2.0, 5.0})
        if ((m == 1.0 || few_decades) && decade * m <= axis.hi * (1 + 1e-9)) axis.ticks.push_back(decade * m);
    return axis;
  }
  if (data_hi - data_lo < 1e-12 * std::max(1.0, std::abs(data_hi))) {
    const double pad = std::max(0.05 * std::abs(data_hi), 1e-3);
    data_lo -= pad;
    data_hi += pad;
  }
  const double raw_step = (data_hi - data_lo) / 5.0;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw_step)));
  double step = magnitude;
  for (const double m : {1.0, 2.0, 2.5, 5.0, 10.0})
    if (m * magnitude >= raw_step) {
      step = m * magnitude;
      break;
    }
  axis.lo = std::floor(data_lo / step + 1e-9) * step;
  axis.hi = std::ceil(data_hi / step - 1e-9) * step;
  for (double t = axis.lo; t <= axis.hi + 1e-9 * step; t += step) axis.ticks.push_back(std::abs(t) < 1e-12 * step ? 0.0 : t);
  return axis;
}

std::pair<Axis, Axis> plot_axes(const Plot& plot) {
  double x_lo = std::numeric_limits<double>::infinity(), x_hi = -x_lo, y_lo = x_lo, y_hi = -x_lo;
  for (const PlotSeries& s : plot.series)
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      const double e = i < s.y_error.size() && std::isfinite(s.y_error[i]) ? s.y_error[i] : 0.0;
      x_lo = std::min(x_lo, s.x[i]);
      x_hi = std::max(x_hi, s.x[i]);
      y_lo = std::min(y_lo, s.y[i] - e);
      y_hi = std::max(y_hi, s.y[i] + e);
    }
  if (!std::isfinite(x_lo)) x_lo = 0, x_hi = 1, y_lo = 0, y_hi = 1;
  if (plot.x_range) std::tie(x_lo, x_hi) = *plot.x_range;
  if (plot.y_range) std::tie(y_lo, y_hi) = *plot.y_range;
  Axis x = make_axis(x_lo, x_hi, plot.log_x), y = make_axis(y_lo, y_hi, false);
  // A fixed range is drawn as given, not rounded outwards.
  if (plot.x_range && !plot.log_x) {
    x.lo = x_lo, x.hi = x_hi;
    std::erase_if(x.ticks, [&](double t) { return t < x_lo - 1e-12 || t > x_hi + 1e-12; });
  }
  if (plot.y_range) {
    y.lo = y_lo, y.hi = y_hi;
    std::erase_if(y.ticks, [&](double t) { return t < y_lo - 1e-12 || t > y_hi + 1e-12; });
  }
  return {x, y};
}

namespace {

// The plot area (inside the margins) and where a data point falls on it, in pixels.
struct PlotArea {
  PlotArea(Axis x, Axis y) : x_axis(std::move(x)), y_axis(std::move(y)) {}
  Axis x_axis, y_axis;
  double w = kWidth - kLeft - kRight, h = kHeight - kTop - kBottom;

  [[nodiscard]] double px(double x) const {
    const double t = x_axis.log ? std::log10(x / x_axis.lo) / std::log10(x_axis.hi / x_axis.lo)
                                : (x - x_axis.lo) / (x_axis.hi - x_axis.lo);
    return kLeft + t * w;
  }
  [[nodiscard]] double py(double y) const { return kTop + (1.0 - (y - y_axis.lo) / (y_axis.hi - y_axis.lo)) * h; }
  [[nodiscard]] bool inside(double x, double y) const {
    return std::isfinite(x) && std::isfinite(y) && (!x_axis.log || x > 0) && x >= x_axis.lo - 1e-12 &&
           x <= x_axis.hi + 1e-12 && y >= y_axis.lo - 1e-12 && y <= y_axis.hi + 1e-12;
  }
};

// The title, the grid lines with their tick labels, the frame and the axis labels.
std::string frame_svg(const Plot& plot, const PlotArea& a) {
  std::string svg = fmt::format("<text x=\"{}\" y=\"22\" text-anchor=\"middle\" font-size=\"14\">{}</text>\n",
                                kLeft + a.w / 2, xml_escape(plot.title));
  for (const double t : a.x_axis.ticks)
    svg += fmt::format("<line x1=\"{0:.2f}\" y1=\"{1}\" x2=\"{0:.2f}\" y2=\"{2}\" stroke=\"#ddd\"/>"
                       "<text x=\"{0:.2f}\" y=\"{3}\" text-anchor=\"middle\">{4}</text>\n",
                       a.px(t), kTop, kTop + a.h, kTop + a.h + 16, tick_label(t, a.x_axis));
  for (const double t : a.y_axis.ticks)
    svg += fmt::format("<line x1=\"{0}\" y1=\"{1:.2f}\" x2=\"{2}\" y2=\"{1:.2f}\" stroke=\"#ddd\"/>"
                       "<text x=\"{3}\" y=\"{4:.2f}\" text-anchor=\"end\">{5}</text>\n",
                       kLeft, a.py(t), kLeft + a.w, kLeft - 6, a.py(t) + 4, tick_label(t, a.y_axis));
  svg += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"black\"/>\n", kLeft,
                     kTop, a.w, a.h);
  svg += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n", kLeft + a.w / 2, kHeight - 12,
                     xml_escape(plot.x_label));
  svg += fmt::format("<text transform=\"translate(16 {}) rotate(-90)\" text-anchor=\"middle\">{}</text>\n",
                     kTop + a.h / 2, xml_escape(plot.y_label));
  return svg;
}

// Pixels of the points, error bars and lines drawn: the legend goes where it hides none.
using Marked = std::vector<std::pair<double, double>>;

void mark_segment(Marked& marked, double x0, double y0, double x1, double y1) {
  const int steps = std::max(1, static_cast<int>(std::hypot(x1 - x0, y1 - y0) / 3.0));
  for (int k = 0; k <= steps; ++k) marked.emplace_back(x0 + (x1 - x0) * k / steps, y0 + (y1 - y0) * k / steps);
}

// Each series' colour: its own, else the palette's next.
std::vector<std::string> series_colours(const Plot& plot) {
  std::vector<std::string> colours;
  std::size_t next_colour = 0;
  for (const PlotSeries& s : plot.series)
    colours.push_back(s.colour.empty() ? kPalette[next_colour++ % kPalette.size()] : s.colour);
  return colours;
}

// One series as an SVG group (its line, error bars and points), remembering the pixels it marks.
std::string series_svg(const PlotSeries& s, const std::string& colour, const PlotArea& a, Marked& marked) {
  const std::string dash = s.dashed ? " stroke-dasharray=\"6 4\"" : "";
  std::string svg = fmt::format("<g class=\"series\" data-label=\"{}\">\n", xml_escape(s.label));
  if (s.mark != Mark::Points) {
    std::string points;
    std::optional<std::pair<double, double>> previous;
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!a.inside(s.x[i], s.y[i])) continue;
      const double x = a.px(s.x[i]), y = a.py(s.y[i]);
      points += fmt::format("{:.2f},{:.2f} ", x, y);
      if (previous) mark_segment(marked, previous->first, previous->second, x, y);
      marked.emplace_back(x, y);
      previous = {x, y};
    }
    svg += fmt::format("<polyline fill=\"none\" stroke=\"{}\" stroke-width=\"1.8\"{} points=\"{}\"/>\n", colour,
                       dash, points);
  }
  for (std::size_t i = 0; i < s.x.size(); ++i) {
    if (!a.inside(s.x[i], s.y[i])) continue;
    if (i < s.y_error.size() && s.y_error[i] > 0) {
      const double lo = std::max(a.y_axis.lo, s.y[i] - s.y_error[i]), hi = std::min(a.y_axis.hi, s.y[i] + s.y_error[i]);
      svg += fmt::format("<path d=\"M{0:.2f} {1:.2f}V{2:.2f}M{3:.2f} {1:.2f}h8M{3:.2f} {2:.2f}h8\" stroke=\"{4}\"/>\n",
                         a.px(s.x[i]), a.py(lo), a.py(hi), a.px(s.x[i]) - 4, colour);
      mark_segment(marked, a.px(s.x[i]) - 4, a.py(lo), a.px(s.x[i]) + 4, a.py(hi));
    }
    if (s.mark != Mark::Line) {
      svg += fmt::format("<circle cx=\"{:.2f}\" cy=\"{:.2f}\" r=\"3.5\" fill=\"{}\"/>\n", a.px(s.x[i]), a.py(s.y[i]),
                         colour);
      marked.emplace_back(a.px(s.x[i]), a.py(s.y[i]));
    }
  }
  return svg + "</g>\n";
}

// The legend's labels, each in lines that keep the legend inside the plot area (a long one
// ran past the plot and covered the y axis): its width at about 6.6 px per character at 12 px.
constexpr double kPixelsPerCharacter = 6.6, kLegendPadding = 44;
struct LegendLabels {
  std::vector<std::vector<std::string>> lines;  // per series, none for an unlabelled one
  std::size_t line_count = 0, longest = 0;      // longest: in characters
};
LegendLabels legend_labels(const Plot& plot, const PlotArea& a) {
  const auto max_characters = static_cast<std::size_t>((a.w - 12 - kLegendPadding) / kPixelsPerCharacter);
  LegendLabels labels;
  for (const PlotSeries& s : plot.series) {
    labels.lines.push_back(s.label.empty() ? std::vector<std::string>{} : wrapped(s.label, max_characters));
    labels.line_count += labels.lines.back().size();
    for (const std::string& line : labels.lines.back()) labels.longest = std::max(labels.longest, display_width(line));
  }
  return labels;
}

// The legend's box, sized to its labels: in the first corner of the plot area where it covers
// nothing drawn, else below the plot, where the picture grows to `height` to hold it.
Rect legend_box(const Plot& plot, const PlotArea& a, const LegendLabels& labels, const Marked& marked,
                double& height) {
  const double legend_w = kLegendPadding + kPixelsPerCharacter * static_cast<double>(labels.longest),
               legend_h = 8 + 16 * static_cast<double>(labels.line_count);
  const double left = kLeft + 6, right = kLeft + a.w - legend_w - 6, top = kTop + 6,
               bottom = kTop + a.h - legend_h - 6;
  std::vector<Rect> corners = {{right, top, legend_w, legend_h}, {left, top, legend_w, legend_h},
                               {right, bottom, legend_w, legend_h}, {left, bottom, legend_w, legend_h}};
  if (plot.legend_at_bottom) std::rotate(corners.begin(), corners.begin() + 2, corners.end());
  constexpr double kClearance = 4.0;  // px: the radius of a point, and a little air
  for (const Rect& corner : corners)
    if (std::none_of(marked.begin(), marked.end(),
                     [&](const auto& m) { return corner.contains(m.first, m.second, kClearance); }))
      return corner;
  // Outside: below the x-axis label.
  height = kHeight + legend_h + 4;
  return Rect{kLeft, kHeight - 4, legend_w, legend_h};
}

// The legend in its box: each labelled series' mark and its label's lines.
std::string legend_svg(const Plot& plot, const std::vector<std::string>& colours, const LegendLabels& labels,
                       const Rect& place) {
  std::string legend;
  if (labels.line_count > 0)
    legend = fmt::format("<rect class=\"legend\" x=\"{:.1f}\" y=\"{:.1f}\" width=\"{:.1f}\" height=\"{:.1f}\" "
                         "fill=\"white\" fill-opacity=\"0.9\" stroke=\"#999\"/>\n",
                         place.x, place.y, place.w, place.h);
  const double legend_x = place.x;
  double legend_y = place.y + 14;
  for (std::size_t k = 0; k < plot.series.size(); ++k) {
    const PlotSeries& s = plot.series[k];
    if (s.label.empty()) continue;
    const std::string& colour = colours[k];
    const std::string dash = s.dashed ? " stroke-dasharray=\"6 4\"" : "";
    if (s.mark == Mark::Points)
      legend += fmt::format("<circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"3.5\" fill=\"{}\"/>", legend_x + 19, legend_y, colour);
    else
      legend += fmt::format("<line x1=\"{0:.1f}\" y1=\"{1:.1f}\" x2=\"{2:.1f}\" y2=\"{1:.1f}\" stroke=\"{3}\" "
                            "stroke-width=\"2\"{4}/>",
                            legend_x + 8, legend_y, legend_x + 30, colour, dash);
    for (const std::string& line : labels.lines[k]) {
      legend += fmt::format("<text x=\"{:.1f}\" y=\"{:.1f}\">{}</text>\n", legend_x + 36, legend_y + 4, xml_escape(line));
      legend_y += 16;
    }
  }
  return legend;
}

}  // namespace

std::string svg_plot(const Plot& plot) {
  auto [x_axis, y_axis] = plot_axes(plot);
  const PlotArea area(std::move(x_axis), std::move(y_axis));
  // The body; the root element, whose height depends on where the legend goes, comes last.
  std::string svg = frame_svg(plot, area);
  // The series first, remembering every pixel they mark: the legend goes where it hides none.
  const std::vector<std::string> colours = series_colours(plot);
  Marked marked;
  for (std::size_t k = 0; k < plot.series.size(); ++k) svg += series_svg(plot.series[k], colours[k], area, marked);
  const LegendLabels labels = legend_labels(plot, area);
  double height = kHeight;
  const Rect place = legend_box(plot, area, labels, marked, height);
  svg += legend_svg(plot, colours, labels, place);
  return fmt::format(
             "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}\" height=\"{1}\" viewBox=\"0 0 {0} {1}\" "
             "font-family=\"sans-serif\" font-size=\"12\" data-x-range=\"{2:.9g} {3:.9g}\" "
             "data-y-range=\"{4:.9g} {5:.9g}\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n",
             kWidth, height, area.x_axis.lo, area.x_axis.hi, area.y_axis.lo, area.y_axis.hi) +
         svg + "</svg>\n";
}

std::string plot_csv(const Plot& plot) {
  const bool errors = std::any_of(plot.series.begin(), plot.series.end(),
                                  [](const PlotSeries& s) { return !s.y_error.empty(); });
  fmt::memory_buffer csv;
  auto out = std::back_inserter(csv);
  fmt::format_to(out, "series,{},{}", plot.x_column, plot.y_column);
  if (errors) fmt::format_to(out, ",{}_error", plot.y_column);
  fmt::format_to(out, "\n");
  const auto cell = [&](double v) {  // NaN: an empty cell
    if (std::isfinite(v)) fmt::format_to(out, "{}", v);
  };
  for (const PlotSeries& s : plot.series) {
    std::string label;
    if (s.label.find_first_of(",\"\n") == std::string::npos) {
      label = s.label;
    } else {
      label.push_back('"');
      for (const char c : s.label) {
        if (c == '"') label.push_back('"');
        label.push_back(c);
      }
      label.push_back('"');
    }
    for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      fmt::format_to(out, "{},", label);
      cell(s.x[i]);
      fmt::format_to(out, ",");
      cell(s.y[i]);
      if (errors) {
        fmt::format_to(out, ",");
        if (i < s.y_error.size()) cell(s.y_error[i]);
      }
      fmt::format_to(out, "\n");
    }
  }
  return fmt::to_string(csv);
}

}  // namespace aggpack
