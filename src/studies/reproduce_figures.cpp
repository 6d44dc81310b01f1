// aggpack reproduce: the figure set and the plot and text helpers the report's sections share.
#include "reproduce_parts.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "aggpack/io/atomic_file.hpp"

namespace aggpack::reproduction {

std::string stat_text(const SeedStatistics& s, int decimals) {
  if (s.count == 0) return "—";
  if (std::isnan(s.sd)) return fmt::format("{:.{}f}", s.mean, decimals);
  return fmt::format("{:.{}f} ± {:.{}f}", s.mean, decimals, s.sd, decimals);
}

// "1 seed", "3 seeds".
std::string counted(std::size_t n, const std::string& noun) { return fmt::format("{} {}{}", n, noun, n == 1 ? "" : "s"); }

std::string value_text(double v, int decimals) { return std::isnan(v) ? "—" : fmt::format("{:.{}f}", v, decimals); }

std::string difference_text(double ours, double reference) {
  if (std::isnan(ours) || std::isnan(reference)) return "—";
  return fmt::format("{:+.4f} ({:+.1f} %)", ours - reference, 100.0 * (ours - reference) / reference);
}

std::string FigureSet::add(const std::string& name, std::string content) {
  const std::string file = "figures/" + name;
  files_[file] = std::move(content);
  return file;
}

std::string FigureSet::add(const std::string& name, const Plot& plot) {
  data_["figures/" + fs::path(name).replace_extension(".csv").string()] = plot_csv(plot);
  return add(name, svg_plot(plot));
}

void FigureSet::write() const {
  fs::create_directories(dir_ / "figures");
  for (const auto& [file, content] : files_) write_file_atomically(dir_ / file, content);
  for (const auto& [file, content] : data_) write_file_atomically(dir_ / file, content);
}

PlotSeries reference_line(const std::string& label, double x0, double x1, double y, const std::string& colour) {
  PlotSeries s{label, {x0, x1}, {y, y}, {}, Mark::Line, true, colour};
  return s;
}

Box bed_frame(const ParticleStore& particles, const Box& container) {
  Box frame = container;
  double top = container.lo.z;
  for (std::size_t i = 0; i < particles.size(); ++i) top = std::max(top, particles.position[i].z + particles.radius[i]);
  frame.hi.z = std::min(container.hi.z, top);
  return frame;
}

double slope_per_10(const std::vector<double>& x, const std::vector<double>& y) { return 10.0 * fit_line(x, y).slope; }

}  // namespace aggpack::reproduction
