#include "aggpack/specimen/specimen_export.hpp"

#include <algorithm>
#include <functional>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <numbers>
#include <sstream>
#include <variant>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/core/overloaded.hpp"
#include "aggpack/core/units.hpp"
#include "aggpack/core/version.hpp"
#include "aggpack/io/atomic_file.hpp"
#include "aggpack/io/output_directory.hpp"
#include "aggpack/io/scenario.hpp"
#include "aggpack/specimen/voxel_image.hpp"

namespace aggpack {

namespace {

// Voxels at most: a finer default voxel is coarsened to this, and says so.
constexpr double kDefaultVoxelBudget = 5e7;
// An Abaqus file's elements at most: some 3 GB of text.
constexpr double kInpElementLimit = 2.5e7;
constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;
// Gmsh's tetrahedra at most (estimated_mesh_elements), and its memory per tetrahedron while it
// meshes: Debian's Gmsh 4.8, one thread, took 184 MB for 2.1e5 tetrahedra (estimated 5.5e5).
constexpr double kMaxMeshElements = 2e7;
constexpr double kGmshBytesPerElement = 900.0;

void check_inside_bed(const SpecimenRegion& region, const SpecimenSource& source) {
  const Box r = region_bounds(region), b = source.bed_bounds;
  const double slack = 1e-9 * std::max({b.size().x, b.size().y, b.size().z});
  const bool inside = r.lo.x >= b.lo.x - slack && r.lo.y >= b.lo.y - slack && r.lo.z >= b.lo.z - slack &&
                      r.hi.x <= b.hi.x + slack && r.hi.y <= b.hi.y + slack && r.hi.z <= b.hi.z + slack;
  if (!inside)
    throw InputError(fmt::format("the specimen {} is not inside the bed ({}: {}, its highest particle's top as its "
                                 "top); expected a region within it",
                                 region_text(region), source.description, box_text(b)));
  // A cylindrical container's corners hold no bed: the region's footprint within its wall.
  if (const auto& wall = source.container_wall) {
    const double reach = std::visit(
        Overloaded{[&](const Box& box) {
                     double far = 0.0;
                     for (const double x : {box.lo.x, box.hi.x})
                       for (const double y : {box.lo.y, box.hi.y})
                         far = std::max(far, std::hypot(x - wall->x, y - wall->y));
                     return far;
                   },
                   [&](const VerticalCylinder& core) {
                     return std::hypot(core.x - wall->x, core.y - wall->y) + core.radius;
                   }},
        region);
    if (reach > wall->radius + slack)
      throw InputError(fmt::format("the specimen {} is not inside the bed: it reaches {:.6g} m from the axis of the "
                                   "cylindrical container ({}), whose wall is at {:.6g} m; expected a region within it",
                                   region_text(region), reach, source.description, wall->radius));
  }
}

std::vector<std::string> checked_formats(const std::vector<std::string>& asked) {
  std::vector<std::string> formats = asked;
  if (formats.empty()) formats = {"vti", "inp", "geo"};  // msh when asked: Gmsh takes minutes
  for (const std::string& f : formats)
    if (f != "vti" && f != "inp" && f != "geo" && f != "msh")
      throw InputError(fmt::format("format \"{}\": expected vti, inp, geo or msh", f));
  const bool msh = std::find(formats.begin(), formats.end(), "msh") != formats.end();
  if (msh && !gmsh_available())
    throw InputError("format msh: gmsh is not installed (Debian package gmsh); the .geo file can be meshed elsewhere");
  if (msh && std::find(formats.begin(), formats.end(), "geo") == formats.end()) formats.push_back("geo");
  return formats;
}

// The output folder made, and an earlier specimen's files removed; any failure an InputError
// naming the folder (a path under /proc, a full disk), not the library's filesystem_error.
void prepare_specimen_folder(const std::filesystem::path& out) {
  std::error_code ec;
  std::filesystem::create_directories(out, ec);
  if (ec || !std::filesystem::is_directory(out))
    throw InputError(fmt::format("{}: cannot make the output folder: {}; expected a folder you may write",
                                 out.string(), ec ? ec.message() : std::string("it is not a folder")));
  // An earlier specimen's files go: the folder never mixes two specimens.
  for (const char* name : {"specimen.vti", "specimen.inp", "specimen.geo", "specimen.msh", "gmsh.log", "specimen.json"})
    if (std::filesystem::remove(out / name, ec); ec)
      throw InputError(fmt::format("{}: cannot remove an earlier specimen's {}: {}", out.string(), name, ec.message()));
}

// The voxel image's memory and the .inp's elements, from the grid alone, before anything is
// allocated: a byte per voxel and each plane's list of spheres; the .inp a node number (4
// bytes) per grid point; against the memory limit (80 % of this machine's memory).
void check_voxel_memory(const Specimen& s, double voxel, double max_voxels, bool inp) {
  const VoxelGrid g = voxel_grid(s.region, voxel);
  if (!(g.voxels() <= max_voxels)) return;  // voxelize refuses it, with its own message
  const double points = static_cast<double>(g.count[0] + 1) * static_cast<double>(g.count[1] + 1) *
                        static_cast<double>(g.count[2] + 1);
  double plane_lists = 0.0;  // each sphere in the list of every plane it spans
  for (const MemberSphere& sphere : s.spheres)
    plane_lists += std::min(2.0 * (sphere.radius + s.itz_thickness) / g.spacing.z + 1.0,
                            static_cast<double>(g.count[2]));
  const double bytes = g.voxels() + sizeof(std::size_t) * plane_lists + (inp ? sizeof(std::uint32_t) * points : 0.0);
  const double limit = memory_limit_bytes(RunLimits{});
  if (bytes > limit)
    throw InputError(fmt::format("voxel size {:.6g} m: {} x {} x {} = {:.3g} voxels need an estimated {:.3g} GiB{}, "
                                 "more than the memory limit of {:.3g} GiB (80 % of this machine's memory); expected a "
                                 "larger voxel (--voxel) or a lower --max-voxels",
                                 voxel, g.count[0], g.count[1], g.count[2], g.voxels(), bytes / kGiB,
                                 inp ? " with the .inp's node numbers" : "", limit / kGiB));
  // The .inp's elements are the voxels inside the region: all of a box's, about pi/4 of a
  // cylinder's bounding box.
  const double inside = g.voxels() * region_volume(s.region) / region_bounds(s.region).volume();
  if (inp && inside > 1.01 * kInpElementLimit)
    throw InputError(fmt::format("format inp: about {:.3g} voxel elements, more than {:.2g} (some 130 bytes each in "
                                 "the file); expected a larger voxel (--voxel), or the voxel image alone (--formats "
                                 "vti)",
                                 inside, kInpElementLimit));
}

// The .inp's size: each node's line (its number and three coordinates of up to 17 digits),
// each element's (its number and eight nodes'), and its number in a set.
double estimated_inp_bytes(const VoxelImage& image) {
  const double elements = static_cast<double>(image.inside());
  const double nodes = std::min(static_cast<double>(image.grid.count[0] + 1) *
                                    static_cast<double>(image.grid.count[1] + 1) *
                                    static_cast<double>(image.grid.count[2] + 1),
                                8.0 * elements);
  const double node_digits = std::floor(std::log10(std::max(nodes, 1.0))) + 1.0;
  const double element_digits = std::floor(std::log10(std::max(elements, 1.0))) + 1.0;
  return nodes * (node_digits + 3.0 * 22.0 + 1.0) + elements * (element_digits + 8.0 * (node_digits + 2.0) + 1.0) +
         elements * (element_digits + 2.0);
}

std::string bytes_text(double bytes) {
  if (bytes >= 1e9) return fmt::format("{:.1f} GB", bytes / 1e9);
  if (bytes >= 1e6) return fmt::format("{:.0f} MB", bytes / 1e6);
  return fmt::format("{:.0f} kB", std::max(bytes / 1e3, 1.0));
}

double smallest_kept(const Specimen& s) {
  double smallest = std::numeric_limits<double>::max();
  for (const MemberSphere& sphere : s.spheres) smallest = std::min(smallest, 2.0 * sphere.radius);
  return smallest;
}

bool has(const std::vector<std::string>& formats, const char* f) {
  return std::find(formats.begin(), formats.end(), f) != formats.end();
}

nlohmann::json region_json(const SpecimenRegion& region) {
  if (const Box* b = std::get_if<Box>(&region))
    return {{"shape", "box"}, {"lo", {b->lo.x, b->lo.y, b->lo.z}}, {"hi", {b->hi.x, b->hi.y, b->hi.z}}};
  const auto& c = std::get<VerticalCylinder>(region);
  return {{"shape", "cylinder"}, {"axis_x", c.x}, {"axis_y", c.y}, {"z_lo", c.z_lo}, {"z_hi", c.z_hi},
          {"radius", c.radius}};
}

GmshMeshSizes mesh_sizes_of(const Specimen& s, const SpecimenRequest& request) {
  const double finest = smallest_kept(s);
  return request.mesh_sizes.value_or(
      GmshMeshSizes{finest / 4.0, finest / 2.0, request.itz_thickness > 0.0 ? request.itz_thickness : finest / 4.0});
}

// The tetrahedra Gmsh would make, estimated from the sizes: a regular tetrahedron of side h
// fills h^3 / (6 sqrt 2), so a volume V meshed at h takes some 8.5 V / h^3 of them. Each
// sphere's aggregate at its size (the phase's, or finer by curvature: elements_per_circle
// around it) and a layer of that size in the matrix around it; the ITZ's shells at the ITZ's
// size; the rest of the mortar at the mortar's. An estimate within a factor of a few, to refuse
// a mesh far beyond a machine, not to predict Gmsh's count.
double estimated_mesh_elements(const Specimen& s, const GmshMeshSizes& sizes) {
  constexpr double kPerCube = 8.485;  // 6 sqrt 2
  const double pi = std::numbers::pi;
  const double region = region_volume(s.region);
  double elements = 0.0, near_volume = 0.0;
  for (const MemberSphere& sphere : s.spheres) {
    const double r = sphere.radius;
    const double h = std::min(sizes.aggregate, 2.0 * pi * r / sizes.elements_per_circle);
    const double ball = std::min(4.0 / 3.0 * pi * r * r * r, region);
    const double layer = std::min(4.0 * pi * r * r * h, region);
    elements += kPerCube * (ball + layer) / (h * h * h);
    near_volume += ball + layer;
    if (s.itz_thickness > 0.0) {
      const double shell = std::min(4.0 * pi * r * r * s.itz_thickness, region);
      elements += kPerCube * shell / std::pow(std::min(sizes.itz, h), 3);
      near_volume += shell;
    }
  }
  return elements + kPerCube * std::max(region - near_volume, 0.0) / std::pow(sizes.mortar, 3);
}

// Gmsh's mesh refused before any work when its estimate passes kMaxMeshElements or its memory
// the machine's limit.
void check_mesh_size(const Specimen& s, const GmshMeshSizes& sizes) {
  const double elements = estimated_mesh_elements(s, sizes);
  const double bytes = elements * kGmshBytesPerElement, limit = memory_limit_bytes(RunLimits{});
  if (elements > kMaxMeshElements || bytes > limit)
    throw InputError(fmt::format(
        "format msh: mesh sizes {:.4g} m (aggregate), {:.4g} m (mortar), {:.4g} m (ITZ) make an estimated {:.3g} "
        "tetrahedra (some {:.3g} GiB for Gmsh), more than {}; expected larger sizes (--mesh-size), fewer "
        "particles, or the geometry alone (--formats geo) meshed elsewhere",
        sizes.aggregate, sizes.mortar, sizes.itz, elements, bytes / kGiB,
        elements > kMaxMeshElements ? fmt::format("the limit of {:.0e} tetrahedra", kMaxMeshElements)
                                    : fmt::format("the memory limit of {:.3g} GiB (80 % of this machine's memory)",
                                                  limit / kGiB)));
}

// The Gmsh geometry into `out`, its mesh sizes into report["gmsh"].
void write_gmsh_geometry(const Specimen& s, const SpecimenRequest& request, const std::vector<std::string>& formats,
                         const std::string& provenance, const std::filesystem::path& out,
                         std::vector<std::string>& written, nlohmann::json& report) {
  if (!has(formats, "geo")) return;
  const GmshMeshSizes sizes = mesh_sizes_of(s, request);
  write_file_atomically(out / "specimen.geo", gmsh_geo(s, sizes, provenance));
  written.push_back("specimen.geo");
  report["gmsh"] = {{"mesh_size_m", {{"aggregate", sizes.aggregate}, {"mortar", sizes.mortar}, {"itz", sizes.itz}}},
                    {"elements_per_circle", sizes.elements_per_circle},
                    {"estimated_tetrahedra", estimated_mesh_elements(s, sizes)}};
}

// Gmsh's mesh of specimen.geo, what it holds into report["gmsh"].
void mesh_with_gmsh(const Specimen& s, const std::filesystem::path& out, nlohmann::json& report,
                    const std::function<void()>& safe_point) {
  try {
    run_gmsh(out / "specimen.geo", out / "specimen.msh", out / "gmsh.log", safe_point);
  } catch (const InputError& e) {  // most often two particles that touch at a point
    throw InputError(fmt::format("{}{}; the other files and specimen.json are written", e.what(),
                                 s.gap > 0.0 ? "" : " (particles that touch make faces Gmsh cannot mesh: give a gap)"));
  }
  const std::map<std::string, double> volumes = msh_group_volumes(out / "specimen.msh");
  double meshed = 0.0;
  for (const auto& [name, volume] : volumes) meshed += volume;
  const double aggregate = volumes.contains("aggregate") ? volumes.at("aggregate") : 0.0;
  const double region = region_volume(s.region);
  report["gmsh"]["volume_m3"] = volumes;
  report["gmsh"]["aggregate_fraction"] = aggregate / region;
  if (volumes.contains("itz")) report["gmsh"]["itz_fraction"] = volumes.at("itz") / region;
  report["gmsh"]["aggregate_fraction_minus_exact"] = aggregate / region - s.aggregate_fraction();
  report["gmsh"]["meshed_volume_over_region"] = meshed / region;
}

// specimen.json's content but the files and notes: the specimen, its exact and voxel fractions.
nlohmann::json specimen_json(const SpecimenSource& source, const SpecimenRequest& request, const Specimen& s,
                             const VoxelImage& image) {
  const SpecimenRegion& region = s.region;
  return {
      {"aggpack_version", kVersion},
      {"source", source.description},
      {"run", source.run},
      {"region", region_json(region)},
      {"min_size_m", request.min_size},
      {"itz_thickness_m", request.itz_thickness},
      {"gap_m", request.gap},
      {"particles", {{"kept", s.kept_particles}, {"spheres", s.spheres.size()}, {"dropped_below_min_size", s.dropped_particles},
                     {"left_out_by_gap", s.left_out_by_gap},
                     {"dropped_volume_fraction", s.dropped_volume / region_volume(region)}}},
      {"exact", {{"aggregate_fraction", s.aggregate_fraction()}, {"method", s.volume_method}}},
      {"voxels",
       {{"count", image.grid.count},
        {"spacing_m", {image.grid.spacing.x, image.grid.spacing.y, image.grid.spacing.z}},
        {"aggregate_fraction", image.fraction(image.aggregate)},
        {"itz_fraction", image.fraction(image.itz)},
        {"mortar_fraction", image.fraction(image.mortar)},
        {"aggregate_fraction_minus_exact", image.fraction(image.aggregate) - s.aggregate_fraction()},
        {"itz_volume_m3", static_cast<double>(image.itz) * image.grid.voxel_volume()}}}};
}

}  // namespace

std::map<std::string, double> msh_group_volumes(const std::filesystem::path& msh) {
  std::ifstream in(msh);
  std::string line;
  std::map<int, std::string> names;
  std::vector<Vec3> nodes;
  std::map<int, double> by_tag;
  while (std::getline(in, line)) {
    if (line == "$PhysicalNames") {
      int count = 0;
      in >> count;
      for (int n = 0; n < count; ++n) {
        int dim = 0, tag = 0;
        std::string name;
        in >> dim >> tag >> name;
        names[tag] = name.size() >= 2 ? name.substr(1, name.size() - 2) : name;
      }
    } else if (line == "$Nodes") {
      std::size_t count = 0;
      in >> count;
      nodes.assign(count + 1, Vec3{});
      for (std::size_t n = 0; n < count && in; ++n) {
        std::size_t id = 0;
        Vec3 p;
        in >> id >> p.x >> p.y >> p.z;
        if (id == 0 || id > count) throw InputError(fmt::format("{}: node {} of {}", msh.string(), id, count));
        nodes[id] = p;
      }
    } else if (line == "$Elements") {
      std::size_t count = 0;
      in >> count;
      std::getline(in, line);
      for (std::size_t e = 0; e < count && std::getline(in, line); ++e) {
        std::istringstream fields(line);
        int id = 0, type = 0, tags = 0, physical = 0, skipped = 0;
        fields >> id >> type >> tags >> physical;
        for (int t = 1; t < tags; ++t) fields >> skipped;
        if (type != 4) continue;  // a linear tetrahedron
        std::size_t v[4] = {};
        fields >> v[0] >> v[1] >> v[2] >> v[3];
        for (const std::size_t k : v)
          if (k == 0 || k >= nodes.size()) throw InputError(fmt::format("{}: element {}: node {}", msh.string(), id, k));
        const Vec3 a = nodes[v[1]] - nodes[v[0]], b = nodes[v[2]] - nodes[v[0]], c = nodes[v[3]] - nodes[v[0]];
        by_tag[physical] += std::abs(dot(cross(a, b), c)) / 6.0;
      }
    }
  }
  if (nodes.empty()) throw InputError(fmt::format("{}: not a Gmsh mesh of format 2.2 (no $Nodes)", msh.string()));
  std::map<std::string, double> volumes;
  for (const auto& [tag, volume] : by_tag) volumes[names.contains(tag) ? names[tag] : std::to_string(tag)] = volume;
  return volumes;
}

VerticalCylinder cylinder_from(const std::vector<double>& values, const std::string& what) {
  const bool finite = std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); });
  if (values.size() != 5 || !finite || !(values[4] > 0.0) || !(values[3] > values[2]))
    throw InputError(fmt::format("{}: expected X,Y,ZLO,ZHI,RADIUS (its vertical axis through X,Y; ZLO < ZHI; "
                                 "RADIUS > 0)",
                                 what));
  return {values[0], values[1], values[2], values[3], values[4]};
}

GmshMeshSizes mesh_sizes_from(const std::vector<double>& values, const std::string& what) {
  if (values.empty() || values.size() > 3 ||
      std::any_of(values.begin(), values.end(), [](double v) { return !(v > 0.0) || !std::isfinite(v); }))
    throw InputError(fmt::format("{}: expected AGGREGATE[,MORTAR[,ITZ]], positive lengths", what));
  return {values[0], values.size() > 1 ? values[1] : 2.0 * values[0], values.size() > 2 ? values[2] : values[0]};
}

namespace {

// A length in metres, and in the source's unit beside it.
using LengthText = std::function<std::string(double)>;

// The voxel of the image: the one asked for (no wider than the specimen), else a tenth of the
// smallest kept sphere's diameter within the default budget of voxels (said in `notes`).
double chosen_voxel(const Specimen& s, const SpecimenRegion& region, const SpecimenRequest& request,
                    std::vector<std::string>& notes, const LengthText& length) {
  const Vec3 sides = region_bounds(region).size();
  const double smallest_side = std::min({sides.x, sides.y, sides.z});
  // A voxel wider than the specimen would be rounded to one voxel across: an image of nothing.
  if (request.voxel_size && *request.voxel_size > smallest_side)
    throw InputError(fmt::format("voxel size {:.6g} m: wider than the specimen's smallest side ({:.6g} m, {}); "
                                 "expected a voxel of at most that (--voxel), a few hundredths of it for an image "
                                 "that resolves the particles",
                                 *request.voxel_size, smallest_side, region_text(region)));
  double voxel = request.voxel_size.value_or(std::min(smallest_kept(s) / 10.0, smallest_side));
  // The grid spans the region's bounding box (a cylinder's corners too): the budget is its voxels.
  double budget_voxel = std::cbrt(region_bounds(region).volume() / kDefaultVoxelBudget);
  // Each side's count is rounded to a whole number: a little coarser until they hold the budget.
  while (voxel_grid(region, budget_voxel).voxels() > kDefaultVoxelBudget) budget_voxel *= 1.001;
  if (!request.voxel_size && voxel < budget_voxel) {
    notes.push_back(fmt::format("the voxel is {}, not {} (a tenth of the smallest kept sphere's "
                                "diameter): at most {:.0e} voxels by default (give the voxel size for a finer one)",
                                length(budget_voxel), length(voxel), kDefaultVoxelBudget));
    voxel = budget_voxel;
  }
  return voxel;
}

// The image against the .inp's element limit and the ITZ against the mortar, and what the
// image holds said in `notes`.
void check_image(const VoxelImage& image, const SpecimenRequest& request, const Specimen& s,
                 const SpecimenRegion& region, std::vector<std::string>& notes, const LengthText& length) {
  const bool inp = has(checked_formats(request.formats), "inp");
  if (inp && !(static_cast<double>(image.inside()) <= kInpElementLimit))
    throw InputError(fmt::format("format inp: {:.3g} voxel elements, more than {:.2g} (some 130 bytes each in the "
                                 "file); expected a larger voxel, or the voxel image alone (vti)",
                                 static_cast<double>(image.inside()), kInpElementLimit));
  if (request.itz_thickness > 0.0 && image.itz > image.mortar)
    throw InputError(fmt::format("ITZ {:.4g} m: it takes {:.1f} % of the matrix around the aggregate, more than the "
                                 "mortar between: thicker than the gaps between the particles; expected a thinner ITZ "
                                 "(about 10 to 50 um in concrete)",
                                 request.itz_thickness,
                                 100.0 * static_cast<double>(image.itz) / static_cast<double>(image.itz + image.mortar)));
  const double min_spacing = std::min({image.grid.spacing.x, image.grid.spacing.y, image.grid.spacing.z});
  if (request.itz_thickness > 0.0 && request.itz_thickness < min_spacing)
    notes.push_back(fmt::format("the ITZ ({}) is thinner than a voxel ({}): the image holds it only where "
                                "a voxel's centre falls in it (give a voxel of the ITZ's thickness or less)",
                                length(request.itz_thickness), length(min_spacing)));
  notes.push_back("a voxel is the phase at its centre; the aggregate's exact volume sums each particle's part in the "
                  "region, so spheres that overlap at a DEM contact count their overlap twice (some 1e-4 of a radius)");
  if (s.left_out_by_gap > 0)
    notes.push_back(fmt::format("{} particles that reached into the specimen by less than gap / 2 are left out: shrunk "
                                "by the gap they no longer reach into it",
                                s.left_out_by_gap));
  if (s.dropped_particles > 0)
    notes.push_back(fmt::format("{} particles below {} ({:.4f} of the specimen's volume) are left to the mortar",
                                s.dropped_particles, length(request.min_size), s.dropped_volume / region_volume(region)));
}

}  // namespace

nlohmann::json export_specimen(const SpecimenSource& source, const SpecimenRequest& request,
                               const std::filesystem::path& out, const SpecimenHooks& hooks) {
  if (!request.region && !source.largest_virtual_box)
    throw InputError(fmt::format("{}: no virtual box to take as the specimen: give the specimen's box or cylinder",
                                 source.description));
  if (!(request.min_size >= 0.0) || !(request.itz_thickness >= 0.0) || !std::isfinite(request.itz_thickness))
    throw InputError("the minimum size and the ITZ's thickness: expected lengths of zero or more");
  if (!(request.max_voxels >= 1.0) || !std::isfinite(request.max_voxels))
    throw InputError(fmt::format("the voxel limit {}: expected a count of 1 or more", request.max_voxels));
  const SpecimenRegion region = request.region.value_or(SpecimenRegion{*source.largest_virtual_box});
  const std::vector<std::string> formats = checked_formats(request.formats);
  check_output_directory(out, false, "--out, or out= from Python");
  check_inside_bed(region, source);
  const Specimen s = cut_specimen(source.particles, {region, request.min_size, request.itz_thickness, request.gap});
  std::vector<std::string> notes = source.notes;
  // Lengths in metres, and in the scenario's (or --length-unit's) unit beside them.
  const auto per_unit = source.length_unit.empty() ? std::nullopt : metres_per_unit(source.length_unit);
  const std::string unit = per_unit && *per_unit != 1.0L ? source.length_unit : std::string();
  const LengthText length = [&](double metres) { return length_text(metres, unit); };
  if (request.gap > 0.0)
    notes.push_back(fmt::format("each kept particle's spheres shrunk by {} (gap / 2) so that touching ones "
                                "stand {} apart: the aggregate fraction {:.4f} as packed, {:.4f} shrunk",
                                length(0.5 * request.gap), length(request.gap),
                                cut_specimen(source.particles, {region, request.min_size, 0.0, 0.0}).aggregate_fraction(),
                                s.aggregate_fraction()));
  double voxel = chosen_voxel(s, region, request, notes, length);
  check_voxel_memory(s, voxel, request.max_voxels, has(formats, "inp"));
  if (has(formats, "msh")) check_mesh_size(s, mesh_sizes_of(s, request));
  const VoxelImage image = voxelize(s, voxel, request.max_voxels);
  check_image(image, request, s, region, notes, length);
  const std::string provenance =
      fmt::format("aggpack {} specimen: {} of {}", kVersion, region_text(region), source.description);
  nlohmann::json report = specimen_json(source, request, s, image);
  if (hooks.safe_point) hooks.safe_point();  // a stop during the voxels: nothing is written
  prepare_specimen_folder(out);
  std::vector<std::string> written;
  if (has(formats, "vti")) {
    write_file_atomically(out / "specimen.vti", [&](std::ostream& o) { write_vti(o, image, provenance); });
    written.push_back("specimen.vti");
  }
  if (has(formats, "inp")) {
    if (hooks.say)
      hooks.say(fmt::format("writing specimen.inp: {} elements, about {}", image.inside(),
                            bytes_text(estimated_inp_bytes(image))));
    write_file_atomically(out / "specimen.inp", [&](std::ostream& o) { write_abaqus_inp(o, image, provenance); });
    written.push_back("specimen.inp");
  }
  report["modelling_notes"] = notes;
  const auto write_report = [&] {
    report["files"] = written;
    write_file_atomically(out / "specimen.json", report.dump(1) + "\n");
  };
  // What is written stands on its own, said in specimen.json, before Gmsh meshes (minutes, and
  // it may fail on a geometry it cannot mesh).
  write_gmsh_geometry(s, request, formats, provenance, out, written, report);
  write_report();
  if (has(formats, "msh")) {
    if (hooks.say)
      hooks.say(fmt::format("meshing with Gmsh: an estimated {:.2g} tetrahedra",
                            report["gmsh"]["estimated_tetrahedra"].get<double>()));
    mesh_with_gmsh(s, out, report, hooks.safe_point);
    written.push_back("specimen.msh");
    write_report();
  }
  return report;
}

}  // namespace aggpack
