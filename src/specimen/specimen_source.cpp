// The beds a specimen is cut from: a run's folder or a packing file.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include <fmt/format.h>

#include "aggpack/analysis/density.hpp"
#include "aggpack/core/error.hpp"
#include "aggpack/core/input_file.hpp"
#include "aggpack/core/text.hpp"
#include "aggpack/io/particle_file.hpp"
#include "aggpack/io/scenario.hpp"
#include "aggpack/specimen/specimen_export.hpp"

namespace aggpack {

namespace {

nlohmann::json read_json(const std::filesystem::path& file) {
  try {
    return nlohmann::json::parse(read_input_text(file, "a run's summary"));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(fmt::format("{}: not a summary.json aggpack wrote: {}", file.string(), e.what()));
  }
}

Vec3 vec_of(const nlohmann::json& j) { return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()}; }

// grains.csv's intermediate dimension I of each grain (its "width" column), by grain number.
std::vector<double> grain_widths(const std::filesystem::path& file) {
  std::istringstream in(read_input_text(file, "the run's grains.csv"));
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = split_csv_fields(line);
  const auto width_column = std::find(header.begin(), header.end(), "width");
  const auto id_column = std::find(header.begin(), header.end(), "id");
  if (width_column == header.end() || id_column == header.end())
    throw InputError(fmt::format("{}: expected the columns id and width (a grain's I)", file.string()));
  const auto at = static_cast<std::size_t>(width_column - header.begin());
  const auto id_at = static_cast<std::size_t>(id_column - header.begin());
  std::vector<double> widths;
  for (std::size_t row = 2; std::getline(in, line); ++row) {
    if (trim(line).empty()) continue;
    const std::vector<std::string> fields = split_csv_fields(line);
    const auto width = at < fields.size() ? parse_finite_number(fields[at]) : std::nullopt;
    const auto id = id_at < fields.size() ? parse_finite_number(fields[id_at]) : std::nullopt;
    if (!width || !(*width > 0.0)) throw InputError(fmt::format("{}:{}: width: expected a positive length", file.string(), row));
    if (!id || *id != static_cast<double>(widths.size() + 1))
      throw InputError(fmt::format("{}:{}: id: expected grain {}, the grains numbered in order", file.string(), row,
                                   widths.size() + 1));
    widths.push_back(*width);
  }
  return widths;
}

// The particles of a bed: each sphere of its own, and each grain's spheres together; `sizes`:
// the grains' I, by grain number - 1.
PackedParticles particles_of(const PackingFile& file, const std::vector<double>& grain_sizes,
                             const std::string& name) {
  PackedParticles out;
  std::map<std::uint32_t, std::size_t> particle_of_grain;
  const ParticleStore& p = file.particles;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const std::uint32_t grain = file.grains.empty() ? 0 : file.grains[i];
    std::size_t particle = out.particle_size.size();
    if (grain == 0) {
      out.particle_size.push_back(2.0 * p.radius[i]);
    } else if (const auto found = particle_of_grain.find(grain); found != particle_of_grain.end()) {
      particle = found->second;
    } else {
      if (grain > grain_sizes.size())
        throw InputError(fmt::format("{}: sphere {} is of grain {}, and grains.csv lists {}", name, i + 1,
                                     grain, grain_sizes.size()));
      particle_of_grain[grain] = particle;
      out.particle_size.push_back(grain_sizes[grain - 1]);
    }
    out.spheres.push_back({p.position[i], p.radius[i]});
    out.particle_of_sphere.push_back(particle);
  }
  return out;
}

// A periodic bed's particles whole (a grain's spheres by the minimum image of its first) and,
// for each that crosses a side, its images across it.
PackedParticles with_periodic_images(const PackedParticles& bed, const Box& container) {
  const double lx = container.size().x, ly = container.size().y;
  std::vector<std::vector<MemberSphere>> members(bed.particle_size.size());
  for (std::size_t i = 0; i < bed.spheres.size(); ++i) {
    std::vector<MemberSphere>& m = members[bed.particle_of_sphere[i]];
    MemberSphere s = bed.spheres[i];
    if (!m.empty()) {
      s.centre.x -= lx * std::round((s.centre.x - m.front().centre.x) / lx);
      s.centre.y -= ly * std::round((s.centre.y - m.front().centre.y) / ly);
    }
    m.push_back(s);
  }
  PackedParticles out;
  for (std::size_t k = 0; k < members.size(); ++k) {
    double x_lo = std::numeric_limits<double>::max(), x_hi = -x_lo, y_lo = x_lo, y_hi = -x_lo;
    for (const MemberSphere& s : members[k]) {
      x_lo = std::min(x_lo, s.centre.x - s.radius), x_hi = std::max(x_hi, s.centre.x + s.radius);
      y_lo = std::min(y_lo, s.centre.y - s.radius), y_hi = std::max(y_hi, s.centre.y + s.radius);
    }
    for (const int sx : {0, -1, 1})
      for (const int sy : {0, -1, 1}) {
        const double dx = sx * lx, dy = sy * ly;
        const bool reaches_in = x_hi + dx > container.lo.x && x_lo + dx < container.hi.x &&
                                y_hi + dy > container.lo.y && y_lo + dy < container.hi.y;
        if (!reaches_in) continue;
        for (const MemberSphere& s : members[k]) {
          out.spheres.push_back({{s.centre.x + dx, s.centre.y + dy, s.centre.z}, s.radius});
          out.particle_of_sphere.push_back(out.particle_size.size());
        }
        out.particle_size.push_back(bed.particle_size[k]);
      }
  }
  return out;
}

double highest_top(const PackedParticles& p) {
  double top = -std::numeric_limits<double>::max();
  for (const MemberSphere& s : p.spheres) top = std::max(top, s.centre.z + s.radius);
  return top;
}

// The unit the run's scenario wrote its container's side in (as its console shows lengths),
// where its file is still there and reads; else none (metres alone).
std::string scenario_length_unit(const nlohmann::json& summary) {
  try {
    const std::filesystem::path file = summary.at("scenario_file").get<std::string>();
    std::error_code ec;
    if (file.empty() || !std::filesystem::is_regular_file(file, ec)) return {};
    return load_scenario(file).written_length_unit;
  } catch (const std::exception&) {  // a scenario since changed or moved: lengths in metres
    return {};
  }
}

}  // namespace

SpecimenSource read_run_folder(const std::filesystem::path& folder) {
  const std::filesystem::path summary_file = folder / "summary.json", bed_file = folder / "particles.csv";
  for (const auto& f : {summary_file, bed_file})
    if (!std::filesystem::exists(f))
      throw InputError(fmt::format("{}: a run's folder holds {}; this one has none (is it the output folder of a "
                                   "finished aggpack run?)",
                                   folder.string(), f.filename().string()));
  const nlohmann::json summary = read_json(summary_file);
  SpecimenSource source;
  try {
    const nlohmann::json& c = summary.at("container");
    source.bed_bounds = {vec_of(c.at("lo")), vec_of(c.at("hi"))};
    const bool periodic = c.at("periodic").get<bool>();
    if (c.value("shape", "box") == "cylinder") {
      const Box& b = source.bed_bounds;
      source.container_wall = VerticalCylinder{0.5 * (b.lo.x + b.hi.x), 0.5 * (b.lo.y + b.hi.y), b.lo.z, b.hi.z,
                                               0.5 * c.at("diameter_m").get<double>()};
    }
    const PackingFile file = read_packing_file(bed_file, 1.0, 1.0);
    const std::vector<double> widths = file.grains.empty() ? std::vector<double>{} : grain_widths(folder / "grains.csv");
    source.particles = particles_of(file, widths, bed_file.string());
    if (periodic) {
      source.particles = with_periodic_images(source.particles, source.bed_bounds);
      source.notes.push_back("periodic sides: a particle that crosses one counts with its image across it");
    }
    if (!widths.empty())
      source.notes.push_back("a grain's size is its intermediate dimension I (the one a sieve's opening passes, "
                             "grains.csv's width)");
    double largest = 0.0;
    if (summary.contains("density"))
      for (const nlohmann::json& b : summary.at("density").at("boxes"))
        if (b.at("side_m").get<double>() > largest) {
          largest = b.at("side_m").get<double>();
          source.largest_virtual_box = Box{vec_of(b.at("lo")), vec_of(b.at("hi"))};
        }
    source.run = {{"aggpack_version", summary.at("aggpack_version")},
                  {"scenario_file", summary.at("scenario_file")},
                  {"seed", summary.at("seed")},
                  {"folder", folder.string()}};
  } catch (const nlohmann::json::exception& e) {
    throw InputError(fmt::format("{}: not a summary.json aggpack wrote: {}", summary_file.string(), e.what()));
  }
  source.bed_bounds.hi.z = highest_top(source.particles);
  source.description = fmt::format("the final bed of the run in {}", folder.string());
  source.length_unit = scenario_length_unit(summary);
  return source;
}

SpecimenSource read_packing_source(const std::filesystem::path& file, double length_unit) {
  const PackingFile read = read_packing_file(file, length_unit, 1.0);
  if (std::any_of(read.grains.begin(), read.grains.end(), [](std::uint32_t g) { return g != 0; }))
    throw InputError(fmt::format("{}: its grain column puts spheres into grains: cut a run with grains from its "
                                 "folder (its grains.csv gives each grain's size)",
                                 file.string()));
  return spheres_source(read.particles, fmt::format("the packing file {} ({})", file.string(), read.format));
}

SpecimenSource spheres_source(const ParticleStore& spheres, std::string description) {
  if (!spheres.bodies.empty())
    throw InputError(fmt::format("{}: a bed of grains: cut it from its run's folder (its grains.csv gives each "
                                 "grain's size)",
                                 description));
  if (spheres.empty()) throw InputError(fmt::format("{}: no spheres", description));
  // Spheres that overlap deeper than a DEM contact are not separate particles (a grain's
  // members read as spheres, say): their overlaps would count twice in the aggregate. Refused
  // as `aggpack analyze` refuses them.
  try {
    (void)check_particle_overlaps(spheres, bounding_container(spheres), ParticleSource{}.overlap_tolerance, false,
                                  description, RunLimits{}.max_grid_cells);
  } catch (const InputError& e) {
    throw InputError(fmt::format("{} (a specimen's aggregate would count each overlap twice; a bed of grains is cut "
                                 "from its run's folder, whose grains.csv gives each grain's size)",
                                 e.what()));
  }
  SpecimenSource source;
  source.particles = particles_of(PackingFile{spheres, "", {}, {}}, {}, description);
  constexpr double kBig = std::numeric_limits<double>::max();
  Box b{{kBig, kBig, kBig}, {-kBig, -kBig, -kBig}};
  for (const MemberSphere& s : source.particles.spheres) {
    b.lo = {std::min(b.lo.x, s.centre.x - s.radius), std::min(b.lo.y, s.centre.y - s.radius),
            std::min(b.lo.z, s.centre.z - s.radius)};
    b.hi = {std::max(b.hi.x, s.centre.x + s.radius), std::max(b.hi.y, s.centre.y + s.radius),
            std::max(b.hi.z, s.centre.z + s.radius)};
  }
  source.bed_bounds = b;
  source.description = std::move(description);
  return source;
}

}  // namespace aggpack
