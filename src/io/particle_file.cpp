#include "aggpack/io/particle_file.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fmt/format.h>
#include <fstream>
#include <limits>
#include <numbers>
#include <numbers>
#include <optional>
#include <vector>

#include "aggpack/core/error.hpp"
#include "aggpack/core/input_file.hpp"
#include "aggpack/core/text.hpp"
#include "aggpack/io/lammps_data.hpp"
#include "aggpack/spatial/multilevel_grid.hpp"

namespace aggpack {

namespace {
// A header name or a number cell: trimmed, quotes dropped, lower case.
std::string lower_trimmed(std::string_view text) {
  std::string s(trim(text));
  s.erase(0, s.find_first_not_of('"'));
  s.erase(s.find_last_not_of('"') + 1);
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

std::vector<std::string> split(const std::string& line, bool csv) {
  return csv ? split_csv_fields(line) : split_words(line);
}

std::optional<double> to_number(const std::string& text) { return parse_finite_number(lower_trimmed(text)); }

bool is_blank_or_comment(const std::string& line) {
  const std::string_view t = trim(line);
  return t.empty() || t.front() == '#';
}

// Where x, y, z and the size are, from a header row; nullopt when a name is missing.
struct Columns {
  std::array<std::size_t, 4> index{0, 1, 2, 3};  // x, y, z, size
  bool size_is_diameter = false;
  std::optional<std::size_t> material;  // a run of several materials' particles.csv names each sphere's
  std::optional<std::size_t> grain;     // a run with grains' particles.csv: each sphere's grain, 0 for none
};
// A column that a header names twice (x, y, z and r, radius, d, diameter all count as the
// size); the reader would otherwise take one of them silently.
std::optional<std::string> repeated_column(const std::vector<std::string>& names) {
  std::vector<std::string> seen;
  for (const auto& raw : names) {
    std::string name = lower_trimmed(raw);
    if (name.empty()) continue;
    const bool size = name == "r" || name == "radius" || name == "d" || name == "diameter";
    const std::string key = size ? "size" : name;
    if (std::find(seen.begin(), seen.end(), key) != seen.end()) return name;
    seen.push_back(key);
  }
  return std::nullopt;
}

std::optional<Columns> columns_from_header(const std::vector<std::string>& names) {
  std::array<std::optional<std::size_t>, 4> found;
  Columns c;
  for (std::size_t k = 0; k < names.size(); ++k) {
    const std::string name = lower_trimmed(names[k]);
    if (name == "x") found[0] = k;
    else if (name == "y") found[1] = k;
    else if (name == "z") found[2] = k;
    else if (name == "r" || name == "radius") found[3] = k, c.size_is_diameter = false;
    else if (name == "d" || name == "diameter") found[3] = k, c.size_is_diameter = true;
    else if (name == "material") c.material = k;
    else if (name == "grain") c.grain = k;
  }
  for (std::size_t k = 0; k < 4; ++k) {
    if (!found[k]) return std::nullopt;
    c.index[k] = *found[k];
  }
  return c;
}

// What a file's rows hold: where x, y, z and the size are, and how many fields a row may
// have. A CSV row needs at least the named columns (others are ignored); a whitespace row has
// exactly four numbers, or exactly as many fields as its header names.
struct RowLayout {
  Columns columns;
  std::size_t min_fields = 4, max_fields = 4;
  bool has_header = false;
};

// The layout that a header line (its fields, split) sets; throws when it does not name each
// of the columns once.
RowLayout layout_from_header(const std::vector<std::string>& fields, bool csv, const std::string& line,
                             const std::string& name, std::size_t line_no) {
  if (const auto twice = repeated_column(fields))
    throw InputError(fmt::format("{}:{}: the header names the column \"{}\" twice; expected each of x, y, z "
                                 "and r (or radius, d, diameter) once",
                                 name, line_no, *twice));
  const auto header = columns_from_header(fields);
  if (!header)
    throw InputError(fmt::format(
        "{}:{}: a {} particle file needs a header naming the columns x, y, z and r (or radius, d, "
        "diameter){}; got \"{}\"",
        name, line_no, csv ? "CSV" : "whitespace-separated",
        csv ? "" : ", or rows of exactly four numbers x y z r", line));
  RowLayout layout;
  layout.columns = *header;
  layout.has_header = true;
  if (csv) {
    layout.min_fields = std::max({*std::max_element(layout.columns.index.begin(), layout.columns.index.end()),
                                  layout.columns.material.value_or(0), layout.columns.grain.value_or(0)}) + 1;
    layout.max_fields = std::numeric_limits<std::size_t>::max();
  } else {
    layout.min_fields = layout.max_fields = fields.size();
  }
  return layout;
}

// Throws when a row of `count` fields does not fit the layout.
void check_field_count(std::size_t count, const RowLayout& layout, bool csv, const std::string& name,
                       std::size_t line_no) {
  if (count >= layout.min_fields && count <= layout.max_fields) return;
  if (csv)
    throw InputError(fmt::format("{}:{}: expected {} comma-separated fields per row, got {}", name,
                                 line_no, layout.min_fields, count));
  if (!layout.has_header)
    throw InputError(fmt::format(
        "{}:{}: expected exactly 4 numbers per row (x y z r), got {}{}", name, line_no, count,
        count > 4 ? "; a file with more columns (a LAMMPS dump body: id type x y z radius) needs a "
                    "header line naming them, e.g. \"id type x y z radius\""
                  : ""));
  throw InputError(fmt::format("{}:{}: expected {} fields per row, as the header names, got {}", name,
                               line_no, layout.min_fields, count));
}

// Adds the particle of a data row (its fields, split) to the store.
void add_particle(ParticleStore& store, const std::vector<std::string>& fields, const Columns& columns,
                  double length_unit, double density, const std::string& name, std::size_t line_no) {
  double v[4];
  for (std::size_t k = 0; k < 4; ++k) {
    const auto value = to_number(fields[columns.index[k]]);
    if (!value)
      throw InputError(fmt::format("{}:{}: field {} (\"{}\") is not a number", name, line_no,
                                   columns.index[k] + 1, fields[columns.index[k]]));
    v[k] = *value * length_unit;
  }
  const double r = columns.size_is_diameter ? 0.5 * v[3] : v[3];
  if (!(r > 0.0))
    throw InputError(fmt::format("{}:{}: the {} must be positive, got {}", name, line_no,
                                 columns.size_is_diameter ? "diameter" : "radius", fields[columns.index[3]]));
  store.add({v[0], v[1], v[2]}, r, density);
}
}  // namespace

PackingFile read_packing_file(const std::filesystem::path& file, double length_unit, double density,
                              std::uintmax_t max_bytes, std::optional<std::int64_t> timestep) {
  return parse_packing_text(read_input_text(file, "the particle file", max_bytes), file.string(), length_unit, density,
                            timestep);
}

ParticleStore read_particle_file(const std::filesystem::path& file, double length_unit, double density,
                                 std::uintmax_t max_bytes) {
  return read_packing_file(file, length_unit, density, max_bytes).particles;
}

ParticleStore parse_particle_text(std::string_view text, const std::string& name, double length_unit,
                                  double density) {
  return parse_packing_text(text, name, length_unit, density).particles;
}

PackingFile parse_packing_text(std::string_view text, const std::string& name, double length_unit, double density,
                               std::optional<std::int64_t> timestep) {
  if (is_lammps_dump(text)) {
    LammpsBed bed = parse_lammps_dump(text, name, length_unit, density, timestep);
    const std::string which = timestep || bed.snapshots == 1 ? "" : fmt::format(" (the last of {})", bed.snapshots);
    return {std::move(bed.particles), fmt::format("LAMMPS dump, timestep {}{}", *bed.timestep, which), {}, {}};
  }
  if (timestep)
    throw InputError(fmt::format("{}: a timestep was asked for, but the file is not a LAMMPS dump", name));
  if (is_lammps_data(text))
    return {parse_lammps_data(text, name, length_unit, density).particles, "LAMMPS data file", {}, {}};
  PackingFile file;
  ParticleStore& store = file.particles;
  std::string line;
  std::size_t line_no = 0;
  std::size_t line_start = 0;
  RowLayout layout;
  std::optional<bool> csv;
  while (line_start < text.size()) {
    const std::size_t end = std::min(text.find('\n', line_start), text.size());
    line.assign(text.substr(line_start, end - line_start));
    line_start = end + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find('\0') != std::string::npos)
      throw InputError(fmt::format("{}:{}: a NUL byte: this is not a text file", name, line_no));
    if (is_blank_or_comment(line)) continue;
    if (!csv) {
      // The first row: a header unless it is a whitespace-separated row of numbers.
      csv = line.find(',') != std::string::npos;
      const auto fields = split(line, *csv);
      const bool numeric = std::all_of(fields.begin(), fields.end(), [](const std::string& f) { return to_number(f); });
      if (*csv || !numeric) {
        layout = layout_from_header(fields, *csv, line, name, line_no);
        continue;
      }
    }
    const auto fields = split(line, *csv);
    check_field_count(fields.size(), layout, *csv, name, line_no);
    add_particle(store, fields, layout.columns, length_unit, density, name, line_no);
    if (layout.columns.material) file.materials.emplace_back(trim(fields[*layout.columns.material]));
    if (layout.columns.grain) {
      const auto grain = to_number(fields[*layout.columns.grain]);
      if (!grain || *grain < 0.0 || *grain != std::floor(*grain) || *grain > 4e9)
        throw InputError(fmt::format("{}:{}: grain \"{}\": expected a grain's number (1 up), or 0 for a sphere of "
                                     "its own",
                                     name, line_no, fields[*layout.columns.grain]));
      file.grains.push_back(static_cast<std::uint32_t>(*grain));
    }
  }
  if (store.empty()) throw InputError(fmt::format("{}: no particles in the file", name));
  file.format = csv.value_or(false) ? "CSV" : "whitespace-separated text";
  return file;
}

std::string particles_csv(const ParticleStore& particles, std::span<const std::string> material_names) {
  fmt::memory_buffer out;
  const auto o = std::back_inserter(out);
  const bool grains = !particles.bodies.empty();
  fmt::format_to(o, "id,x,y,z,r{}{}\n", grains ? ",grain" : "", material_names.empty() ? "" : ",material");
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const Vec3& p = particles.position[i];
    fmt::format_to(o, "{},{},{},{},{}", i + 1, p.x, p.y, p.z, particles.radius[i]);
    if (grains) fmt::format_to(o, ",{}", particles.body[i] == kNoBody ? 0 : std::size_t{particles.body[i]} + 1);
    if (!material_names.empty()) fmt::format_to(o, ",{}", material_names[particles.material.at(i)]);
    fmt::format_to(o, "\n");
  }
  return fmt::to_string(out);
}

std::string grains_csv(const ParticleStore& particles, std::span<const GrainMeasure> measures,
                       std::span<const SieveInterval> sieves, std::span<const int> coordination) {
  fmt::memory_buffer out;
  const auto o = std::back_inserter(out);
  fmt::format_to(o, "id,x,y,z,qw,qx,qy,qz,volume_diameter,length,width,thickness,mass,template,first_sphere,spheres,"
                    "sieve_retained,sieve_passing,coordination\n");
  const auto cell = [](double v) { return std::isnan(v) ? std::string() : fmt::format("{}", v); };
  const RigidBodies& b = particles.bodies;
  for (std::size_t k = 0; k < b.size(); ++k) {
    const Vec3& c = b.position[k];
    const Quaternion& q = b.orientation[k];
    const GrainMeasure& m = measures[k];
    const SieveInterval interval = k < sieves.size() ? sieves[k] : SieveInterval{};
    fmt::format_to(o, "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", k + 1, c.x, c.y, c.z, q.w, q.x,
                   q.y, q.z, std::cbrt(6.0 * b.volume[k] / std::numbers::pi), m.length, m.width, m.thickness,
                   b.mass[k], b.shape[k] + 1, b.first_member[k] + 1, b.member_count[k], cell(interval.retained),
                   cell(interval.passing), coordination[k]);
  }
  return fmt::to_string(out);
}

}  // namespace aggpack

namespace aggpack {

std::string supports_csv(std::span<const Supports> supports) {
  // Each support in two typed columns, so that a table reader takes each column as one type:
  // its kind (a word) and, for a sphere, that sphere's id (0 for anything else).
  const auto kind = [](SupportId id) {
    return id == kNoSupport ? std::string("none") : is_particle(id) ? std::string("sphere") : support_name(id);
  };
  const auto sphere_id = [](SupportId id) { return is_particle(id) ? static_cast<std::uint64_t>(id) + 1 : 0; };
  fmt::memory_buffer out;
  fmt::format_to(std::back_inserter(out),
                 "id,support_1_kind,support_1_id,support_2_kind,support_2_id,support_3_kind,support_3_id\n");
  for (std::size_t i = 0; i < supports.size(); ++i) {
    const auto& ids = supports[i].ids;
    fmt::format_to(std::back_inserter(out), "{},{},{},{},{},{},{}\n", i + 1, kind(ids[0]), sphere_id(ids[0]),
                   kind(ids[1]), sphere_id(ids[1]), kind(ids[2]), sphere_id(ids[2]));
  }
  return fmt::to_string(out);
}

PairOverlap check_particle_overlaps(const ParticleStore& particles, const Container& container, double tolerance,
                                    bool soft_contacts, const std::string& file, double max_grid_cells) {
  PairOverlap worst;
  if (particles.size() < 2) return worst;
  double solid = 0.0;
  for (const double r : particles.radius) solid += 4.0 / 3.0 * std::numbers::pi * r * r * r;
  const double cells = MultilevelGrid::cells_needed(container, particles.radius, std::max(solid / 0.6, 1e-300),
                                                    container.height());
  if (!(cells <= max_grid_cells))
    throw InputError(fmt::format("{}: the spheres span {} but are at most {:.4g} m in radius: a neighbour grid over "
                                 "them would need {:.3g} cells, more than the limit of {:.3g} (limits.max_grid_cells); "
                                 "is a sphere far from the others, or the length unit wrong?",
                                 file, box_text(container.bounds),
                                 *std::max_element(particles.radius.begin(), particles.radius.end()), cells,
                                 max_grid_cells));
  MultilevelGrid grid(container, particles.radius, std::max(solid / 0.6, 1e-300));
  grid.reserve(particles.size());
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const Vec3& p = particles.position[i];
    const double r = particles.radius[i];
    const bool member = !particles.body.empty() && particles.body[i] != kNoBody;
    grid.for_each_near(p, r, [&](std::uint32_t j) {
      if (member && particles.body[j] == particles.body[i]) return;  // a grain's own spheres overlap
      const Vec3 d = grid.separation(particles.position[j], p);
      const double distance = std::sqrt(norm2(d));
      const double smaller = std::min(r, particles.radius[j]);
      if (distance <= 1e-9 * smaller)
        throw InputError(fmt::format("{}: particles {} and {} (data rows {} and {}) are at the same place ({:.6g}, "
                                     "{:.6g}, {:.6g}) m: coincident spheres make no packing",
                                     file, j, i, j + 1, i + 1, p.x, p.y, p.z));
      const double depth = (r + particles.radius[j] - distance) / smaller;
      if (depth > worst.depth_over_radius) worst = {depth, j, i};
    });
    grid.insert(static_cast<std::uint32_t>(i), p, r);
  }
  const double limit = soft_contacts ? 1.0 : tolerance;
  if (worst.depth_over_radius > limit) {
    const Vec3& a = particles.position[worst.i];
    const Vec3& b = particles.position[worst.j];
    throw InputError(fmt::format(
        "{}: particles {} and {} (data rows {} and {}, at ({:.6g}, {:.6g}, {:.6g}) and ({:.6g}, {:.6g}, {:.6g}) m, "
        "radii {:.6g} and {:.6g} m) overlap by {:.3g} of the smaller radius{}; {}",
        file, worst.i, worst.j, worst.i + 1, worst.j + 1, a.x, a.y, a.z, b.x, b.y, b.z, particles.radius[worst.i],
        particles.radius[worst.j], worst.depth_over_radius,
        soft_contacts ? ": one centre is inside the other sphere" : "",
        soft_contacts ? "expected spheres that at most touch or press into each other"
                      : fmt::format("expected at most {:g} (particles.overlap_tolerance; set particles.soft_contacts "
                                    "= true, or --soft-contacts, for a bed from a soft-contact DEM)",
                                    tolerance)));
  }
  return worst;
}

}  // namespace aggpack
