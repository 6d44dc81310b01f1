#pragma once
// A specimen as a voxel image: each voxel labelled by the phase at its centre (mortar,
// aggregate, ITZ; outside for a cylinder's corners), the common route to voxel meshes. Written
// as VTK ImageData (.vti, binary appended: ParaView, pycmg/pyMesoscale-style tools) and as an
// Abaqus input of C3D8 elements with one element set per phase (.inp).
#include <array>
#include <cstddef>
#include <cstdint>
#include <ostream>
#include <string_view>
#include <vector>

#include "aggpack/core/vec3.hpp"
#include "aggpack/specimen/specimen.hpp"

namespace aggpack {

enum class Phase : std::uint8_t { Mortar = 0, Aggregate = 1, Itz = 2, Outside = 255 };

// The region's bounding box in voxels of about `voxel_size` a side: each axis a whole number of
// voxels (at least one), the spacing adjusted per axis so that they fill it exactly.
struct VoxelGrid {
  Vec3 origin, spacing;
  std::array<std::size_t, 3> count{};
  [[nodiscard]] double voxel_volume() const { return spacing.x * spacing.y * spacing.z; }
  [[nodiscard]] double voxels() const {
    return static_cast<double>(count[0]) * static_cast<double>(count[1]) * static_cast<double>(count[2]);
  }
  [[nodiscard]] Vec3 centre(std::size_t i, std::size_t j, std::size_t k) const;
};
[[nodiscard]] VoxelGrid voxel_grid(const SpecimenRegion& region, double voxel_size);

struct VoxelImage {
  VoxelGrid grid;
  std::vector<std::uint8_t> phase;  // x fastest, then y, then z (VTK's order)
  std::size_t mortar = 0, aggregate = 0, itz = 0;  // voxels of each phase
  [[nodiscard]] std::size_t inside() const { return mortar + aggregate + itz; }
  [[nodiscard]] double fraction(std::size_t voxels) const {
    return static_cast<double>(voxels) / static_cast<double>(inside());
  }
};

// The image of `specimen`: a voxel is aggregate if its centre lies in a kept sphere, else ITZ
// within itz_thickness of one, else mortar (outside for a centre outside a cylinder). The same
// bytes for any thread count. InputError when the grid has more than `max_voxels` voxels.
[[nodiscard]] VoxelImage voxelize(const Specimen& specimen, double voxel_size, double max_voxels);

// VTK ImageData, the phase as cell data (UInt8, appended, zlib-compressed as the .vtp is),
// `provenance` as a comment.
void write_vti(std::ostream& out, const VoxelImage& image, std::string_view provenance);
// An Abaqus input to *INCLUDE in a deck (no *Heading: the deck has its own): the nodes of the
// voxels inside the specimen, a C3D8 element per voxel, the element sets AGGREGATE, MORTAR and
// ITZ (those that have elements) and the node sets of the region's faces, XMIN, XMAX, YMIN,
// YMAX, ZMIN, ZMAX for a box (ZMIN, ZMAX for a cylinder), `provenance` as comments.
void write_abaqus_inp(std::ostream& out, const VoxelImage& image, std::string_view provenance);

}  // namespace aggpack
