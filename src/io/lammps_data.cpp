#include "aggpack/io/lammps_data.hpp"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <numeric>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "aggpack/core/error.hpp"
#include "aggpack/core/text.hpp"

namespace aggpack {

namespace {
// Where the data file puts a body's member: at its body's centre (wrapped into a periodic box)
// plus its turned offset, so that LAMMPS, which maps it into the box itself, finds it whole
// about the centre that the bodies file gives.
Vec3 member_place(const ParticleStore& particles, const Container& container, std::size_t i) {
  const std::uint32_t b = particles.body[i];
  return container.wrapped(particles.bodies.position[b]) + rotate(particles.bodies.orientation[b], particles.body_offset[i]);
}
}  // namespace

std::string lammps_data(const ParticleStore& particles, const Container& container, std::span<const double> densities,
                        double z_top, std::span<const std::uint8_t> frozen) {
  const Box& b = container.bounds;
  for (std::size_t i = 0; i < particles.size(); ++i)
    if (particles.position[i].z + particles.radius[i] > z_top)
      throw std::invalid_argument("lammps_data: z_top is below a sphere's top");
  const bool grains = !particles.bodies.empty();
  fmt::memory_buffer out;
  auto o = std::back_inserter(out);
  const bool any_frozen = std::any_of(frozen.begin(), frozen.end(), [](std::uint8_t f) { return f != 0; });
  fmt::format_to(o, "aggpack bed for LAMMPS ({}, SI units)\n\n{} atoms\n{} atom types\n\n",
                 grains ? "atom_style hybrid sphere bond: a grain's spheres carry its molecule id, 0 a sphere's own"
                        : "atom_style sphere",
                 particles.size(), densities.size() > 1 || any_frozen ? 2 * densities.size() : 1);
  fmt::format_to(o, "{:.17g} {:.17g} xlo xhi\n{:.17g} {:.17g} ylo yhi\n{:.17g} {:.17g} zlo zhi\n\nAtoms # {}\n\n",
                 b.lo.x, b.hi.x, b.lo.y, b.hi.y, b.lo.z, z_top, grains ? "hybrid" : "sphere");
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const std::size_t material = particles.material.empty() ? 0 : particles.material[i];
    if (material >= densities.size()) throw std::invalid_argument("lammps_data: a sphere of an unknown material");
    const std::size_t type = material + 1 + (!frozen.empty() && frozen[i] ? densities.size() : 0);
    if (!grains) {
      const Vec3& p = particles.position[i];
      fmt::format_to(o, "{} {} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g}\n", i + 1, type, 2.0 * particles.radius[i],
                     densities[material], p.x, p.y, p.z);
      continue;
    }
    const bool member = particles.body[i] != kNoBody;
    const Vec3 p = member ? member_place(particles, container, i) : particles.position[i];
    fmt::format_to(o, "{} {} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {}\n", i + 1, type, p.x, p.y, p.z,
                   2.0 * particles.radius[i], densities[material], member ? particles.body[i] + 1 : 0);
  }
  const auto moving = [&](std::size_t i) {
    return i < particles.velocity.size() && (particles.velocity[i] != Vec3{} || particles.angular_velocity[i] != Vec3{});
  };
  bool any_moving = false;
  for (std::size_t i = 0; i < particles.size() && !any_moving; ++i) any_moving = moving(i);
  if (any_moving) {
    fmt::format_to(o, "\nVelocities\n\n");
    for (std::size_t i = 0; i < particles.size(); ++i) {
      const Vec3 &v = particles.velocity[i], &w = particles.angular_velocity[i];
      fmt::format_to(o, "{} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g}\n", i + 1, v.x, v.y, v.z, w.x, w.y, w.z);
    }
  }
  return fmt::to_string(out);
}

std::string lammps_rigid_bodies(const ParticleStore& particles, const Container& container) {
  const RigidBodies& bodies = particles.bodies;
  fmt::memory_buffer out;
  auto o = std::back_inserter(out);
  fmt::format_to(o, "# aggpack's grains for fix rigid/small infile (SI units): the mass, centre of mass and inertia\n"
                    "# tensor of each grain's union of spheres (not LAMMPS's sum over its spheres, which counts\n"
                    "# their overlaps twice).\n# id mass xcm ycm zcm ixx iyy izz ixy ixz iyz vxcm vycm vzcm lx ly lz "
                    "ixcm iycm izcm\n{}\n",
                 bodies.size());
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    // The inertia in space, R diag(I) R^T, and the angular momentum, that times omega.
    const RotationMatrix r = rotation_matrix(bodies.orientation[b]);
    const Vec3& moments = bodies.principal_inertia[b];
    const auto inertia = [&](const Vec3& row_a, const Vec3& row_c) {
      return row_a.x * moments.x * row_c.x + row_a.y * moments.y * row_c.y + row_a.z * moments.z * row_c.z;
    };
    const double ixx = inertia(r.x, r.x), iyy = inertia(r.y, r.y), izz = inertia(r.z, r.z), ixy = inertia(r.x, r.y),
                 ixz = inertia(r.x, r.z), iyz = inertia(r.y, r.z);
    const Vec3& w = bodies.angular_velocity[b];
    const Vec3 l{ixx * w.x + ixy * w.y + ixz * w.z, ixy * w.x + iyy * w.y + iyz * w.z,
                 ixz * w.x + iyz * w.y + izz * w.z};
    const Vec3 c = container.wrapped(bodies.position[b]), &v = bodies.velocity[b];
    fmt::format_to(o, "{} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} "
                      "{:.17g} {:.17g} {:.17g} {:.17g} {:.17g} 0 0 0\n",
                   b + 1, bodies.mass[b], c.x, c.y, c.z, ixx, iyy, izz, ixy, ixz, iyz, v.x, v.y, v.z, l.x, l.y, l.z);
  }
  return fmt::to_string(out);
}

namespace {

// The lines of a text, numbered from 1, with '\r' dropped; NUL bytes refused.
class Lines {
 public:
  Lines(std::string_view text, const std::string& name) : text_(text), name_(name) {}
  bool next(std::string_view& line) {
    if (at_ >= text_.size()) return false;
    const std::size_t end = std::min(text_.find('\n', at_), text_.size());
    line = text_.substr(at_, end - at_);
    at_ = end + 1;
    ++number_;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.find('\0') != std::string_view::npos)
      throw InputError(fmt::format("{}:{}: a NUL byte: this is not a text file", name_, number_));
    return true;
  }
  // The next line, which must exist: `expected` says what it should hold.
  std::string_view require(std::string_view expected) {
    std::string_view line;
    if (!next(line)) throw InputError(fmt::format("{}:{}: the file ends where {} should be", name_, number_ + 1, expected));
    return line;
  }
  [[nodiscard]] std::size_t number() const { return number_; }
  [[nodiscard]] const std::string& name() const { return name_; }
  [[noreturn]] void fail(std::string_view what) const {
    throw InputError(fmt::format("{}:{}: {}", name_, number_, what));
  }

 private:
  std::string_view text_;
  const std::string& name_;
  std::size_t at_ = 0, number_ = 0;
};

double number_field(const Lines& lines, const std::vector<std::string>& fields, std::size_t k, std::string_view what) {
  const auto v = parse_finite_number(fields[k]);
  if (!v) lines.fail(fmt::format("field {} ({}, \"{}\") is not a number", k + 1, what, fields[k]));
  return *v;
}

// The rows of one snapshot or Atoms section, put in id order (ids need not be 1..N).
struct AtomRow {
  std::int64_t id;
  Vec3 position;
  double radius;
};
ParticleStore store_in_id_order(std::vector<AtomRow>& rows, const std::string& name, double density) {
  std::sort(rows.begin(), rows.end(), [](const AtomRow& a, const AtomRow& b) { return a.id < b.id; });
  for (std::size_t k = 1; k < rows.size(); ++k)
    if (rows[k].id == rows[k - 1].id)
      throw InputError(fmt::format("{}: atom id {} appears twice", name, rows[k].id));
  ParticleStore store;
  store.reserve(rows.size());
  for (const AtomRow& row : rows) store.add(row.position, row.radius, density);
  return store;
}

}  // namespace

bool is_lammps_dump(std::string_view text) {
  const std::size_t start = text.find_first_not_of(" \t\r\n");
  return start != std::string_view::npos && text.substr(start).starts_with("ITEM: TIMESTEP");
}

bool is_lammps_data(std::string_view text) {
  // A header line "N atoms" before an "Atoms" line, within the file's first lines.
  bool counted = false;
  std::size_t at = text.find('\n');  // the first line is the title
  for (int k = 0; k < 64 && at < text.size(); ++k) {
    const std::size_t end = std::min(text.find('\n', at + 1), text.size());
    const std::vector<std::string> words = split_words(text.substr(at + 1, end - at - 1));
    at = end;
    if (words.size() == 2 && words[1] == "atoms" && parse_integer(words[0])) counted = true;
    if (!words.empty() && words[0] == "Atoms") return counted;
  }
  return false;
}

namespace {

// A dump's "ITEM: BOX BOUNDS" line and the three lines of bounds after it.
Box read_box_bounds(Lines& lines, double length_unit) {
  const std::string_view bounds = trim(lines.require("ITEM: BOX BOUNDS"));
  if (!bounds.starts_with("ITEM: BOX BOUNDS")) lines.fail("expected \"ITEM: BOX BOUNDS\"");
  if (bounds.find("xy") != std::string_view::npos)
    lines.fail("a triclinic box (xy xz yz): aggpack's containers are rectangular");
  Box box;
  for (int axis = 0; axis < 3; ++axis) {
    const std::vector<std::string> lo_hi = split_words(lines.require("the box bounds"));
    if (lo_hi.size() != 2) lines.fail("expected two numbers, the box's low and high bound");
    const double lo = number_field(lines, lo_hi, 0, "low bound") * length_unit;
    const double hi = number_field(lines, lo_hi, 1, "high bound") * length_unit;
    (axis == 0 ? box.lo.x : axis == 1 ? box.lo.y : box.lo.z) = lo;
    (axis == 0 ? box.hi.x : axis == 1 ? box.hi.y : box.hi.z) = hi;
  }
  return box;
}

// Where a snapshot's rows hold what the reader takes, from its "ITEM: ATOMS" line.
struct DumpColumns {
  std::vector<std::string> names;
  std::optional<std::size_t> id, radius, diameter;
  std::optional<std::size_t> pos[3];
  bool scaled = false;  // xs ys zs: fractions of the box
};
DumpColumns read_atoms_header(Lines& lines) {
  const std::string_view atoms = trim(lines.require("ITEM: ATOMS"));
  if (!atoms.starts_with("ITEM: ATOMS")) lines.fail("expected \"ITEM: ATOMS\" and the column names");
  DumpColumns c;
  c.names = split_words(atoms.substr(11));
  const std::vector<std::string>& columns = c.names;
  const auto column = [&](std::initializer_list<std::string_view> names) -> std::optional<std::size_t> {
    for (std::size_t k = 0; k < columns.size(); ++k)
      for (const std::string_view n : names)
        if (columns[k] == n) return k;
    return std::nullopt;
  };
  c.id = column({"id"});
  c.radius = column({"radius"}), c.diameter = column({"diameter"});
  // The position: the three columns of one kind; a kind's value is its own (a scaled one is a
  // fraction of the box), so columns of different kinds are refused, not read as one.
  constexpr std::array<std::array<std::string_view, 3>, 3> kinds{{{"x", "y", "z"}, {"xu", "yu", "zu"}, {"xs", "ys", "zs"}}};
  for (std::size_t kind = 0; kind < kinds.size() && !c.pos[0]; ++kind) {
    const auto x = column({kinds[kind][0]}), y = column({kinds[kind][1]}), z = column({kinds[kind][2]});
    if (!x || !y || !z) continue;
    c.pos[0] = x, c.pos[1] = y, c.pos[2] = z;
    c.scaled = kind == 2;
  }
  if (!c.pos[0]) {
    std::vector<std::string> found;
    for (const std::string& name : columns)
      for (const auto& kind : kinds)
        if (std::find(kind.begin(), kind.end(), name) != kind.end()) found.push_back(name);
    if (!found.empty())
      lines.fail(fmt::format("the position columns \"{}\" are of different kinds: expected all three of one, x y z, "
                             "xu yu zu or xs ys zs (scaled by the box)",
                             fmt::join(found, " ")));
  }
  if (!c.pos[0] || !(c.radius || c.diameter))
    lines.fail(fmt::format("the ATOMS columns \"{}\" need x y z (or xu yu zu, xs ys zs) and radius or diameter "
                           "(for example: dump 1 all custom 1000 bed.dump id type x y z radius)",
                           fmt::join(columns, " ")));
  return c;
}

// Atom row k (from 0) of a snapshot, its fields split: position, radius and id (k + 1
// when the dump has no ids).
AtomRow read_atom_row(const Lines& lines, const std::vector<std::string>& f, const DumpColumns& c, const Box& box,
                      double length_unit, std::int64_t k) {
  const std::vector<std::string>& columns = c.names;
  if (f.size() != columns.size())
    lines.fail(fmt::format("expected {} fields, as ITEM: ATOMS names, got {}", columns.size(), f.size()));
  Vec3 p;
  for (int axis = 0; axis < 3; ++axis) {
    double v = number_field(lines, f, *c.pos[axis], columns[*c.pos[axis]]);
    if (c.scaled) {
      const double lo = axis == 0 ? box.lo.x : axis == 1 ? box.lo.y : box.lo.z;
      const double hi = axis == 0 ? box.hi.x : axis == 1 ? box.hi.y : box.hi.z;
      v = lo + v * (hi - lo);
    } else {
      v *= length_unit;
    }
    (axis == 0 ? p.x : axis == 1 ? p.y : p.z) = v;
  }
  const double size = number_field(lines, f, c.radius ? *c.radius : *c.diameter, c.radius ? "radius" : "diameter");
  const double r = (c.radius ? size : 0.5 * size) * length_unit;
  if (!(r > 0.0)) lines.fail(fmt::format("the {} must be positive", c.radius ? "radius" : "diameter"));
  std::int64_t atom_id = k + 1;
  if (c.id) {
    const auto v = parse_integer(f[*c.id]);
    if (!v) lines.fail(fmt::format("the id \"{}\" is not an integer", f[*c.id]));
    atom_id = *v;
  }
  return {atom_id, p, r};
}

}  // namespace

LammpsBed parse_lammps_dump(std::string_view text, const std::string& name, double length_unit, double density,
                            std::optional<std::int64_t> timestep) {
  Lines lines(text, name);
  std::optional<LammpsBed> chosen;
  std::size_t snapshots = 0;
  std::string_view line;
  std::vector<std::int64_t> timesteps;
  while (lines.next(line)) {
    if (trim(line).empty()) continue;
    if (trim(line) != "ITEM: TIMESTEP") lines.fail(fmt::format("expected \"ITEM: TIMESTEP\", got \"{}\"", line));
    const auto step = parse_integer(trim(lines.require("the timestep")));
    if (!step) lines.fail("expected the timestep, an integer");
    timesteps.push_back(*step);
    ++snapshots;
    if (trim(lines.require("ITEM: NUMBER OF ATOMS")) != "ITEM: NUMBER OF ATOMS")
      lines.fail("expected \"ITEM: NUMBER OF ATOMS\"");
    const auto count = parse_integer(trim(lines.require("the number of atoms")));
    if (!count || *count < 0) lines.fail("expected the number of atoms, an integer >= 0");
    // Each row is at least 8 bytes: a count the text cannot hold is refused before memory.
    if (static_cast<std::uint64_t>(*count) > text.size() / 8 + 1)
      lines.fail(fmt::format("{} atoms cannot fit in a file of {} bytes", *count, text.size()));
    const Box box = read_box_bounds(lines, length_unit);
    const DumpColumns columns = read_atoms_header(lines);
    const bool wanted = !timestep || *timestep == *step;
    std::vector<AtomRow> rows;
    if (wanted) rows.reserve(static_cast<std::size_t>(*count));
    for (std::int64_t k = 0; k < *count; ++k) {
      const std::string_view row = lines.require(fmt::format("atom row {} of {}", k + 1, *count));
      if (wanted) rows.push_back(read_atom_row(lines, split_words(row), columns, box, length_unit, k));
    }
    if (!wanted) continue;
    LammpsBed bed;
    bed.particles = store_in_id_order(rows, name, density);
    bed.timestep = *step;
    bed.box = box;
    chosen = std::move(bed);
    if (timestep) break;
  }
  if (!chosen) {
    if (snapshots == 0) throw InputError(fmt::format("{}: no snapshot in the dump", name));
    throw InputError(fmt::format("{}: no snapshot of timestep {}; the dump has {} (timesteps {} to {})", name,
                                 *timestep, snapshots, timesteps.front(), timesteps.back()));
  }
  if (chosen->particles.empty()) throw InputError(fmt::format("{}: the snapshot of timestep {} has no atoms", name,
                                                              *chosen->timestep));
  chosen->snapshots = snapshots;
  return std::move(*chosen);
}

LammpsBed parse_lammps_data(std::string_view text, const std::string& name, double length_unit, double density) {
  Lines lines(text, name);
  std::string_view line;
  lines.require("the title line");
  std::optional<std::int64_t> count;
  Box box;
  bool bounds[3] = {false, false, false};
  // The header: up to the first section name (a line starting with a letter).
  while (true) {
    line = lines.require("the Atoms section");
    const std::string_view t = trim(line.substr(0, line.find('#')));
    if (t.empty()) continue;
    const std::vector<std::string> words = split_words(t);
    if (std::isalpha(static_cast<unsigned char>(t.front()))) break;
    if (words.size() == 2 && words[1] == "atoms") {
      count = parse_integer(words[0]);
      if (!count || *count < 0) lines.fail("expected the number of atoms, an integer >= 0");
      if (static_cast<std::uint64_t>(*count) > text.size() / 8 + 1)
        lines.fail(fmt::format("{} atoms cannot fit in a file of {} bytes", *count, text.size()));
    } else if (words.size() == 4 && (words[2] == "xlo" || words[2] == "ylo" || words[2] == "zlo")) {
      const int axis = words[2][0] - 'x';
      const double lo = number_field(lines, words, 0, "low bound") * length_unit;
      const double hi = number_field(lines, words, 1, "high bound") * length_unit;
      (axis == 0 ? box.lo.x : axis == 1 ? box.lo.y : box.lo.z) = lo;
      (axis == 0 ? box.hi.x : axis == 1 ? box.hi.y : box.hi.z) = hi;
      bounds[axis] = true;
    } else if (words.back() == "yz") {
      // The tilt line ("xy xz yz" its last words): a triclinic box, whatever its tilts.
      lines.fail("a triclinic box (xy xz yz): aggpack's containers are rectangular");
    }
  }
  if (!count) lines.fail("the header has no \"N atoms\" line before the first section");
  if (!bounds[0] || !bounds[1] || !bounds[2])
    lines.fail("the header needs the box: \"xlo xhi\", \"ylo yhi\" and \"zlo zhi\" lines");
  // Sections until Atoms; others (Masses, Velocities, ...) are skipped.
  while (true) {
    const std::string_view t = trim(line);
    if (t.starts_with("Atoms")) {
      const std::size_t hash = t.find('#');
      if (hash != std::string_view::npos && trim(t.substr(hash + 1)) != "sphere")
        lines.fail(fmt::format("an Atoms section of atom_style {}: aggpack reads atom_style sphere (id type diameter "
                               "density x y z)",
                               trim(t.substr(hash + 1))));
      break;
    }
    do line = lines.require("the Atoms section");
    while (trim(line).empty() || !std::isalpha(static_cast<unsigned char>(trim(line).front())));
  }
  const Vec3 period = box.hi - box.lo;
  std::vector<AtomRow> rows;
  rows.reserve(static_cast<std::size_t>(*count));
  while (static_cast<std::int64_t>(rows.size()) < *count) {
    line = lines.require(fmt::format("atom row {} of {}", rows.size() + 1, *count));
    const std::string_view t = trim(line.substr(0, line.find('#')));
    if (t.empty()) continue;
    const std::vector<std::string> f = split_words(t);
    if (f.size() != 7 && f.size() != 10)
      lines.fail(fmt::format("expected 7 fields (id type diameter density x y z) or 10 (and the image flags), got {}",
                             f.size()));
    const auto atom_id = parse_integer(f[0]);
    if (!atom_id) lines.fail(fmt::format("the id \"{}\" is not an integer", f[0]));
    const double d = number_field(lines, f, 2, "diameter") * length_unit;
    if (!(d > 0.0)) lines.fail("the diameter must be positive");
    Vec3 p{number_field(lines, f, 4, "x") * length_unit, number_field(lines, f, 5, "y") * length_unit,
           number_field(lines, f, 6, "z") * length_unit};
    if (f.size() == 10) {
      const auto ix = parse_integer(f[7]), iy = parse_integer(f[8]), iz = parse_integer(f[9]);
      if (!ix || !iy || !iz) lines.fail("the image flags must be integers");
      p += Vec3{static_cast<double>(*ix) * period.x, static_cast<double>(*iy) * period.y,
                static_cast<double>(*iz) * period.z};
    }
    rows.push_back({*atom_id, p, 0.5 * d});
  }
  if (rows.empty()) throw InputError(fmt::format("{}: no atoms in the data file", name));
  LammpsBed bed;
  bed.particles = store_in_id_order(rows, name, density);
  bed.box = box;
  return bed;
}

}  // namespace aggpack
