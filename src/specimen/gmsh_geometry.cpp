#include "aggpack/specimen/gmsh_geometry.hpp"

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <sys/wait.h>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "aggpack/core/error.hpp"
#include "aggpack/core/overloaded.hpp"

namespace aggpack {

namespace {

// A shell word: the path in single quotes (each quote in it closed, escaped and reopened).
std::string quoted(const std::filesystem::path& path) {
  std::string out = "'";
  for (const char c : path.string()) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// The volumes `first`..`last` (tags) cut by the region (tag 1): the list `name` of disjoint
// pieces (OpenCASCADE's general fuse splits two spheres' overlap into a piece of its own, so
// no union is needed, and a union of untouched spheres would lose their tags).
void write_pieces_in_region(std::ostream& o, const char* name, std::size_t first, std::size_t last) {
  fmt::print(o, "{0}() = BooleanIntersection{{ Volume{{{1}:{2}}}; Delete; }}{{ Volume{{1}}; }};\n", name, first, last);
}

}  // namespace

std::string gmsh_geo(const Specimen& s, const GmshMeshSizes& sizes, std::string_view provenance) {
  std::ostringstream o;
  o.precision(17);
  fmt::print(o, "// {}\n// Physical volumes: 1 aggregate, 2 mortar, 3 itz. Mesh with: gmsh THIS.geo -3\n", provenance);
  o << "SetFactory(\"OpenCASCADE\");\nGeometry.OCCBooleanPreserveNumbering = 1;\nMesh.MshFileVersion = 2.2;\n";
  fmt::print(o, "Mesh.MeshSizeFromCurvature = {};\nMesh.MeshSizeMax = {:.17g};\n", sizes.elements_per_circle,
             std::max({sizes.aggregate, sizes.mortar, sizes.itz}));
  std::visit(Overloaded{[&](const Box& b) {
                          const Vec3 d = b.size();
                          fmt::print(o, "Box(1) = {{{:.17g}, {:.17g}, {:.17g}, {:.17g}, {:.17g}, {:.17g}}};\n", b.lo.x,
                                     b.lo.y, b.lo.z, d.x, d.y, d.z);
                        },
                        [&](const VerticalCylinder& c) {
                          fmt::print(o, "Cylinder(1) = {{{:.17g}, {:.17g}, {:.17g}, 0, 0, {:.17g}, {:.17g}}};\n", c.x,
                                     c.y, c.z_lo, c.z_hi - c.z_lo, c.radius);
                        }},
             s.region);
  const std::size_t n = s.spheres.size();
  const bool itz = s.itz_thickness > 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const MemberSphere& sphere = s.spheres[k];
    fmt::print(o, "Sphere({}) = {{{:.17g}, {:.17g}, {:.17g}, {:.17g}}};\n", 2 + k, sphere.centre.x, sphere.centre.y,
               sphere.centre.z, sphere.radius);
    if (itz)
      fmt::print(o, "Sphere({}) = {{{:.17g}, {:.17g}, {:.17g}, {:.17g}}};\n", 2 + n + k, sphere.centre.x,
                 sphere.centre.y, sphere.centre.z, sphere.radius + s.itz_thickness);
  }
  write_pieces_in_region(o, "aggregate", 2, 1 + n);
  if (itz) {
    write_pieces_in_region(o, "outer", 2 + n, 1 + 2 * n);
    o << "mortar() = BooleanDifference{ Volume{1}; Delete; }{ Volume{outer()}; };\n"
         "itz() = BooleanDifference{ Volume{outer()}; Delete; }{ Volume{aggregate()}; };\n"
         "BooleanFragments{ Volume{mortar(), itz(), aggregate()}; Delete; }{}\n";
  } else {
    o << "mortar() = BooleanDifference{ Volume{1}; Delete; }{ Volume{aggregate()}; };\n"
         "BooleanFragments{ Volume{mortar(), aggregate()}; Delete; }{}\n";
  }
  o << "Physical Volume(\"aggregate\", 1) = {aggregate()};\nPhysical Volume(\"mortar\", 2) = {mortar()};\n";
  if (itz) o << "Physical Volume(\"itz\", 3) = {itz()};\n";
  // Each phase's points their size; the aggregate's last, so that its faces get the aggregate's.
  fmt::print(o, "MeshSize{{ PointsOf{{ Volume{{mortar()}}; }} }} = {:.17g};\n", sizes.mortar);
  if (itz) fmt::print(o, "MeshSize{{ PointsOf{{ Volume{{itz()}}; }} }} = {:.17g};\n", sizes.itz);
  fmt::print(o, "MeshSize{{ PointsOf{{ Volume{{aggregate()}}; }} }} = {:.17g};\n", sizes.aggregate);
  return o.str();
}

bool gmsh_available() { return std::system("command -v gmsh > /dev/null 2>&1") == 0; }

void run_gmsh(const std::filesystem::path& geo, const std::filesystem::path& msh, const std::filesystem::path& log) {
  const std::string command =
      fmt::format("gmsh {} -3 -nt 1 -format msh22 -o {} > {} 2>&1", quoted(geo), quoted(msh), quoted(log));
  const int raw = std::system(command.c_str());
  const int status = raw != -1 && WIFEXITED(raw) ? WEXITSTATUS(raw) : raw;
  std::error_code ec;
  if (status == 0 && std::filesystem::is_regular_file(msh, ec)) return;
  // Gmsh's first error, where its log has one.
  std::ifstream in(log);
  std::string line, first_error;
  while (first_error.empty() && std::getline(in, line))
    if (line.find("Error") != std::string::npos) first_error = line;
  throw InputError(fmt::format("gmsh could not mesh {} (exit status {}){}; its log: {}", geo.string(), status,
                               first_error.empty() ? "" : ": " + first_error, log.string()));
}

}  // namespace aggpack
