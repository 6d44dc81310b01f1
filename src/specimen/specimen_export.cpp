#include "aggpack/specimen/specimen_export.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/core/version.hpp"
#include "aggpack/io/atomic_file.hpp"
#include "aggpack/specimen/voxel_image.hpp"

namespace aggpack {

namespace {

// Voxels at most: a finer default voxel is coarsened to this, and says so.
constexpr double kDefaultVoxelBudget = 5e7;
// An Abaqus file's elements at most: some 3 GB of text.
constexpr double kInpElementLimit = 2.5e7;

void check_inside_bed(const SpecimenRegion& region, const SpecimenSource& source) {
  const Box r = region_bounds(region), b = source.bed_bounds;
  const double slack = 1e-9 * std::max({b.size().x, b.size().y, b.size().z});
  const bool inside = r.lo.x >= b.lo.x - slack && r.lo.y >= b.lo.y - slack && r.lo.z >= b.lo.z - slack &&
                      r.hi.x <= b.hi.x + slack && r.hi.y <= b.hi.y + slack && r.hi.z <= b.hi.z + slack;
  if (!inside)
    throw InputError(fmt::format("the specimen {} is not inside the bed ({}: {}, its highest particle's top as its "
                                 "top); expected a region within it",
                                 region_text(region), source.description, box_text(b)));
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

// The Gmsh geometry into `out`, its mesh sizes into report["gmsh"].
void write_gmsh_geometry(const Specimen& s, const SpecimenRequest& request, const std::vector<std::string>& formats,
                         const std::string& provenance, const std::filesystem::path& out,
                         std::vector<std::string>& written, nlohmann::json& report) {
  if (!has(formats, "geo")) return;
  const double finest = smallest_kept(s);
  const GmshMeshSizes sizes = request.mesh_sizes.value_or(
      GmshMeshSizes{finest / 4.0, finest / 2.0, request.itz_thickness > 0.0 ? request.itz_thickness : finest / 4.0});
  write_file_atomically(out / "specimen.geo", gmsh_geo(s, sizes, provenance));
  written.push_back("specimen.geo");
  report["gmsh"] = {{"mesh_size_m", {{"aggregate", sizes.aggregate}, {"mortar", sizes.mortar}, {"itz", sizes.itz}}},
                    {"elements_per_circle", sizes.elements_per_circle}};
}

// Gmsh's mesh of specimen.geo, what it holds into report["gmsh"].
void mesh_with_gmsh(const Specimen& s, const std::filesystem::path& out, nlohmann::json& report) {
  try {
    run_gmsh(out / "specimen.geo", out / "specimen.msh", out / "gmsh.log");
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

nlohmann::json export_specimen(const SpecimenSource& source, const SpecimenRequest& request,
                               const std::filesystem::path& out) {
  if (!request.region && !source.largest_virtual_box)
    throw InputError(fmt::format("{}: no virtual box to take as the specimen: give the specimen's box or cylinder",
                                 source.description));
  if (!(request.min_size >= 0.0) || !(request.itz_thickness >= 0.0) || !std::isfinite(request.itz_thickness))
    throw InputError("the minimum size and the ITZ's thickness: expected lengths of zero or more");
  if (!(request.max_voxels >= 1.0) || !std::isfinite(request.max_voxels))
    throw InputError(fmt::format("the voxel limit {}: expected a count of 1 or more", request.max_voxels));
  const SpecimenRegion region = request.region.value_or(SpecimenRegion{*source.largest_virtual_box});
  const std::vector<std::string> formats = checked_formats(request.formats);
  check_inside_bed(region, source);
  const Specimen s = cut_specimen(source.particles, {region, request.min_size, request.itz_thickness, request.gap});
  std::vector<std::string> notes = source.notes;
  if (request.gap > 0.0)
    notes.push_back(fmt::format("each kept particle's spheres shrunk by {:.4g} m (gap / 2) so that touching ones "
                                "stand {:.4g} m apart: the aggregate fraction {:.4f} as packed, {:.4f} shrunk",
                                0.5 * request.gap, request.gap,
                                cut_specimen(source.particles, {region, request.min_size, 0.0, 0.0}).aggregate_fraction(),
                                s.aggregate_fraction()));
  double voxel = request.voxel_size.value_or(smallest_kept(s) / 10.0);
  const double budget_voxel = std::cbrt(region_volume(region) / kDefaultVoxelBudget);
  if (!request.voxel_size && voxel < budget_voxel) {
    notes.push_back(fmt::format("the voxel is {:.4g} m, not {:.4g} m (a tenth of the smallest kept sphere's "
                                "diameter): at most {:.0e} voxels by default (give the voxel size for a finer one)",
                                budget_voxel, voxel, kDefaultVoxelBudget));
    voxel = budget_voxel;
  }
  const VoxelImage image = voxelize(s, voxel, request.max_voxels);
  if (has(formats, "inp") && !(static_cast<double>(image.inside()) <= kInpElementLimit))
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
    notes.push_back(fmt::format("the ITZ ({:.4g} m) is thinner than a voxel ({:.4g} m): the image holds it only where "
                                "a voxel's centre falls in it (give a voxel of the ITZ's thickness or less)",
                                request.itz_thickness, min_spacing));
  notes.push_back("a voxel is the phase at its centre; the aggregate's exact volume sums each particle's part in the "
                  "region, so spheres that overlap at a DEM contact count their overlap twice (some 1e-4 of a radius)");
  if (s.dropped_particles > 0)
    notes.push_back(fmt::format("{} particles below {:.4g} m ({:.4f} of the specimen's volume) are left to the mortar",
                                s.dropped_particles, request.min_size, s.dropped_volume / region_volume(region)));
  const std::string provenance =
      fmt::format("aggpack {} specimen: {} of {}", kVersion, region_text(region), source.description);
  nlohmann::json report = specimen_json(source, request, s, image);
  std::filesystem::create_directories(out);
  // An earlier specimen's files go: the folder never mixes two specimens.
  for (const char* name : {"specimen.vti", "specimen.inp", "specimen.geo", "specimen.msh", "gmsh.log", "specimen.json"})
    std::filesystem::remove(out / name);
  std::vector<std::string> written;
  if (has(formats, "vti")) {
    write_file_atomically(out / "specimen.vti", [&](std::ostream& o) { write_vti(o, image, provenance); });
    written.push_back("specimen.vti");
  }
  if (has(formats, "inp")) {
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
    mesh_with_gmsh(s, out, report);
    written.push_back("specimen.msh");
    write_report();
  }
  return report;
}

}  // namespace aggpack
