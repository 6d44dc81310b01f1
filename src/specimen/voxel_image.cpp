#include "aggpack/specimen/voxel_image.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <fmt/ranges.h>

#include "aggpack/core/error.hpp"
#include "aggpack/core/xml_text.hpp"
#include "aggpack/io/vtk_compress.hpp"

namespace aggpack {

namespace {

std::size_t index_of(const VoxelGrid& g, std::size_t i, std::size_t j, std::size_t k) {
  return i + g.count[0] * (j + g.count[1] * k);
}

// The voxel index range [first, last) whose centres lie within [lo, hi] along one axis.
std::pair<std::size_t, std::size_t> centre_range(double lo, double hi, double origin, double spacing, std::size_t n) {
  const double first = std::ceil((lo - origin) / spacing - 0.5);
  const double last = std::floor((hi - origin) / spacing - 0.5) + 1.0;
  const auto clamp = [&](double v) { return static_cast<std::size_t>(std::clamp(v, 0.0, static_cast<double>(n))); };
  return {clamp(first), clamp(last)};
}

// Labels the voxels of plane k: each kept sphere that reaches it raises a voxel's phase to ITZ
// or aggregate (aggregate wins; the order of the spheres does not matter).
void label_plane(VoxelImage& image, const Specimen& s, const std::vector<std::size_t>& spheres, std::size_t k) {
  const VoxelGrid& g = image.grid;
  const double z = g.origin.z + (static_cast<double>(k) + 0.5) * g.spacing.z;
  const double t = s.itz_thickness;
  for (const std::size_t n : spheres) {
    const MemberSphere& sphere = s.spheres[n];
    const double dz = z - sphere.centre.z, reach = sphere.radius + t;
    const double reach2 = reach * reach - dz * dz;
    if (reach2 < 0.0) continue;
    const double disc = std::sqrt(reach2), r2 = sphere.radius * sphere.radius;
    const auto [j0, j1] = centre_range(sphere.centre.y - disc, sphere.centre.y + disc, g.origin.y, g.spacing.y, g.count[1]);
    for (std::size_t j = j0; j < j1; ++j) {
      const double dy = g.origin.y + (static_cast<double>(j) + 0.5) * g.spacing.y - sphere.centre.y;
      const double row2 = reach2 - dy * dy;
      if (row2 < 0.0) continue;
      const double row = std::sqrt(row2);
      const auto [i0, i1] = centre_range(sphere.centre.x - row, sphere.centre.x + row, g.origin.x, g.spacing.x, g.count[0]);
      for (std::size_t i = i0; i < i1; ++i) {
        std::uint8_t& phase = image.phase[index_of(g, i, j, k)];
        if (phase == static_cast<std::uint8_t>(Phase::Outside) || phase == static_cast<std::uint8_t>(Phase::Aggregate))
          continue;
        const double dx = g.origin.x + (static_cast<double>(i) + 0.5) * g.spacing.x - sphere.centre.x;
        const double d2 = dx * dx + dy * dy + dz * dz;
        if (d2 <= r2) phase = static_cast<std::uint8_t>(Phase::Aggregate);
        else if (t > 0.0 && d2 <= reach * reach) phase = static_cast<std::uint8_t>(Phase::Itz);
      }
    }
  }
}

}  // namespace

Vec3 VoxelGrid::centre(std::size_t i, std::size_t j, std::size_t k) const {
  return {origin.x + (static_cast<double>(i) + 0.5) * spacing.x, origin.y + (static_cast<double>(j) + 0.5) * spacing.y,
          origin.z + (static_cast<double>(k) + 0.5) * spacing.z};
}

VoxelGrid voxel_grid(const SpecimenRegion& region, double voxel_size) {
  if (!(voxel_size > 0.0) || !std::isfinite(voxel_size))
    throw InputError(fmt::format("voxel size {}: expected a positive length", voxel_size));
  const Box b = region_bounds(region);
  const Vec3 size = b.size();
  VoxelGrid g;
  g.origin = b.lo;
  const std::array<double, 3> sides{size.x, size.y, size.z};
  std::array<double, 3> spacing{};
  for (std::size_t a = 0; a < 3; ++a) {
    const double n = std::max(1.0, std::round(sides[a] / voxel_size));
    if (n > 1e9) throw InputError(fmt::format("voxel size {:.6g} m: {:.3g} voxels along one side", voxel_size, n));
    g.count[a] = static_cast<std::size_t>(n);
    spacing[a] = sides[a] / n;
  }
  g.spacing = {spacing[0], spacing[1], spacing[2]};
  return g;
}

VoxelImage voxelize(const Specimen& s, double voxel_size, double max_voxels) {
  VoxelImage image;
  image.grid = voxel_grid(s.region, voxel_size);
  const VoxelGrid& g = image.grid;
  if (!(g.voxels() <= max_voxels))
    throw InputError(fmt::format("voxel size {:.6g} m: {} x {} x {} = {:.3g} voxels, more than the limit of {:.3g} "
                                 "(a byte each, and an Abaqus file of some 100 bytes each); expected a larger voxel",
                                 voxel_size, g.count[0], g.count[1], g.count[2], g.voxels(), max_voxels));
  image.phase.assign(static_cast<std::size_t>(g.voxels()), static_cast<std::uint8_t>(Phase::Mortar));
  if (const auto* cylinder = std::get_if<VerticalCylinder>(&s.region))
    for (std::size_t k = 0; k < g.count[2]; ++k)
      for (std::size_t j = 0; j < g.count[1]; ++j)
        for (std::size_t i = 0; i < g.count[0]; ++i)
          if (!cylinder->contains(g.centre(i, j, k)))
            image.phase[index_of(g, i, j, k)] = static_cast<std::uint8_t>(Phase::Outside);
  // Each plane's spheres: those whose reach spans its centre height.
  std::vector<std::vector<std::size_t>> by_plane(g.count[2]);
  for (std::size_t n = 0; n < s.spheres.size(); ++n) {
    const double reach = s.spheres[n].radius + s.itz_thickness, z = s.spheres[n].centre.z;
    const auto [k0, k1] = centre_range(z - reach, z + reach, g.origin.z, g.spacing.z, g.count[2]);
    for (std::size_t k = k0; k < k1; ++k) by_plane[k].push_back(n);
  }
  const auto planes = static_cast<std::ptrdiff_t>(g.count[2]);
#pragma omp parallel for schedule(dynamic)
  for (std::ptrdiff_t k = 0; k < planes; ++k)
    label_plane(image, s, by_plane[static_cast<std::size_t>(k)], static_cast<std::size_t>(k));
  for (const std::uint8_t p : image.phase) {
    image.mortar += p == static_cast<std::uint8_t>(Phase::Mortar);
    image.aggregate += p == static_cast<std::uint8_t>(Phase::Aggregate);
    image.itz += p == static_cast<std::uint8_t>(Phase::Itz);
  }
  return image;
}

void write_vti(std::ostream& out, const VoxelImage& image, std::string_view provenance) {
  const VoxelGrid& g = image.grid;
  fmt::print(out, "<?xml version=\"1.0\"?>\n<!-- {} -->\n", xml_comment_text(provenance));
  fmt::print(out, "<!-- phase: 0 mortar, 1 aggregate, 2 ITZ, 255 outside the specimen -->\n");
  // zlib-compressed as the .vtp is (VTK's own layout): an image of a few phases packs to a few
  // per cent of its byte a voxel.
  fmt::print(out,
             "<VTKFile type=\"ImageData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\" "
             "compressor=\"vtkZLibDataCompressor\">\n"
             "  <ImageData WholeExtent=\"0 {0} 0 {1} 0 {2}\" Origin=\"{3:.17g} {4:.17g} {5:.17g}\" "
             "Spacing=\"{6:.17g} {7:.17g} {8:.17g}\">\n"
             "    <Piece Extent=\"0 {0} 0 {1} 0 {2}\">\n"
             "      <CellData Scalars=\"phase\">\n"
             "        <DataArray type=\"UInt8\" Name=\"phase\" format=\"appended\" offset=\"0\"/>\n"
             "      </CellData>\n    </Piece>\n  </ImageData>\n  <AppendedData encoding=\"raw\">\n   _",
             g.count[0], g.count[1], g.count[2], g.origin.x, g.origin.y, g.origin.z, g.spacing.x, g.spacing.y,
             g.spacing.z);
  std::string packed;
  append_vtk_zlib_blocks(packed, image.phase.data(), image.phase.size());
  out.write(packed.data(), static_cast<std::streamsize>(packed.size()));
  out << "\n  </AppendedData>\n</VTKFile>\n";
}

namespace {

// The phases' element sets that have elements.
std::vector<std::pair<Phase, const char*>> phase_sets(const VoxelImage& image) {
  const std::array<std::pair<Phase, const char*>, 3> sets{
      {{Phase::Aggregate, "AGGREGATE"}, {Phase::Mortar, "MORTAR"}, {Phase::Itz, "ITZ"}}};
  std::vector<std::pair<Phase, const char*>> written;
  for (const auto& set : sets)
    if (std::find(image.phase.begin(), image.phase.end(), static_cast<std::uint8_t>(set.first)) != image.phase.end())
      written.push_back(set);
  return written;
}

// The .inp's comment lines: what it holds, its element sets and the node sets of the region's
// faces (all six of a box, the bottom and top of a cylinder). Returns whether it is a box.
bool write_inp_header(std::ostream& out, const VoxelImage& image,
                      const std::vector<std::pair<Phase, const char*>>& written_sets, std::string_view provenance) {
  const bool box = !std::any_of(image.phase.begin(), image.phase.end(),
                                [](std::uint8_t p) { return p == static_cast<std::uint8_t>(Phase::Outside); });
  std::vector<std::string> set_names;
  for (const auto& set : written_sets) set_names.emplace_back(set.second);
  // No *Heading: a part to *INCLUDE in a deck, which has its own (a second stops CalculiX).
  fmt::print(out,
             "** {}\n** A mesh to *INCLUDE in an analysis deck (no heading of its own: the deck gives one), the sections "
             "given there.\n** C3D8 voxels; element sets (one per phase): {}\n** node sets of the faces: {}\n",
             provenance, fmt::join(set_names, ", "),
             box ? "XMIN, XMAX, YMIN, YMAX, ZMIN, ZMAX (the box's faces x = xmin, ...)"
                 : "ZMIN, ZMAX (the cylinder's bottom and top)");
  return box;
}

}  // namespace

void write_abaqus_inp(std::ostream& out, const VoxelImage& image, std::string_view provenance) {
  const VoxelGrid& g = image.grid;
  const std::size_t nx = g.count[0] + 1, ny = g.count[1] + 1;
  const auto inside = [&](std::size_t v) { return image.phase[v] != static_cast<std::uint8_t>(Phase::Outside); };
  // Node numbers (1 up) of the grid points that an inside voxel uses; 0: unused. (32 bits: the
  // callers' voxel limits keep the grid far below 4e9 points.)
  std::vector<std::uint32_t> node(nx * ny * (g.count[2] + 1), 0);
  const auto point = [&](std::size_t i, std::size_t j, std::size_t k) { return i + nx * (j + ny * k); };
  for (std::size_t k = 0; k < g.count[2]; ++k)
    for (std::size_t j = 0; j < g.count[1]; ++j)
      for (std::size_t i = 0; i < g.count[0]; ++i)
        if (inside(index_of(g, i, j, k)))
          for (std::size_t c = 0; c < 8; ++c) node[point(i + (c & 1), j + ((c >> 1) & 1), k + (c >> 2))] = 1;
  const std::vector<std::pair<Phase, const char*>> written_sets = phase_sets(image);
  const bool box = write_inp_header(out, image, written_sets, provenance);
  out << "*Node\n";
  std::size_t nodes = 0;
  for (std::size_t k = 0; k <= g.count[2]; ++k)
    for (std::size_t j = 0; j < ny; ++j)
      for (std::size_t i = 0; i < nx; ++i)
        if (std::uint32_t& n = node[point(i, j, k)]; n != 0) {
          n = static_cast<std::uint32_t>(++nodes);
          fmt::print(out, "{}, {:.17g}, {:.17g}, {:.17g}\n", n, g.origin.x + static_cast<double>(i) * g.spacing.x,
                     g.origin.y + static_cast<double>(j) * g.spacing.y, g.origin.z + static_cast<double>(k) * g.spacing.z);
        }
  out << "*Element, type=C3D8\n";
  std::size_t element = 0;
  for (std::size_t k = 0; k < g.count[2]; ++k)
    for (std::size_t j = 0; j < g.count[1]; ++j)
      for (std::size_t i = 0; i < g.count[0]; ++i) {
        if (!inside(index_of(g, i, j, k))) continue;
        // The bottom face counterclockwise seen from above, then the top face: a positive volume.
        fmt::print(out, "{}, {}, {}, {}, {}, {}, {}, {}, {}\n", ++element, node[point(i, j, k)],
                   node[point(i + 1, j, k)], node[point(i + 1, j + 1, k)], node[point(i, j + 1, k)],
                   node[point(i, j, k + 1)], node[point(i + 1, j, k + 1)], node[point(i + 1, j + 1, k + 1)],
                   node[point(i, j + 1, k + 1)]);
      }
  // Each phase's elements (numbered as above: the inside voxels in order), 16 a line.
  for (const auto& [phase, name] : written_sets) {
    const auto label = static_cast<std::uint8_t>(phase);
    fmt::print(out, "*Elset, elset={}\n", name);
    std::size_t number = 0, on_line = 0;
    for (const std::uint8_t p : image.phase) {
      if (p == static_cast<std::uint8_t>(Phase::Outside)) continue;
      ++number;
      if (p != label) continue;
      fmt::print(out, "{}{}", on_line == 0 ? "" : ", ", number);
      if (++on_line == 16) out << '\n', on_line = 0;
    }
    if (on_line != 0) out << '\n';
  }
  // The faces' nodes (a load case fixes one and loads the opposite), 16 a line.
  const std::size_t nz = g.count[2] + 1;
  const auto write_face = [&](const char* name, std::size_t axis, std::size_t at) {
    fmt::print(out, "*Nset, nset={}\n", name);
    std::size_t on_line = 0;
    for (std::size_t k = 0; k < nz; ++k)
      for (std::size_t j = 0; j < ny; ++j)
        for (std::size_t i = 0; i < nx; ++i) {
          const std::array<std::size_t, 3> ijk{i, j, k};
          const std::uint32_t n = node[point(i, j, k)];
          if (n == 0 || ijk[axis] != at) continue;
          fmt::print(out, "{}{}", on_line == 0 ? "" : ", ", n);
          if (++on_line == 16) out << '\n', on_line = 0;
        }
    if (on_line != 0) out << '\n';
  };
  if (box) {
    write_face("XMIN", 0, 0), write_face("XMAX", 0, nx - 1);
    write_face("YMIN", 1, 0), write_face("YMAX", 1, ny - 1);
  }
  write_face("ZMIN", 2, 0), write_face("ZMAX", 2, nz - 1);
}

}  // namespace aggpack
