#pragma once
// `aggpack specimen`: a specimen cut from a run's final bed (or a packing file) and written for
// meso-model codes: a voxel image (.vti), an Abaqus voxel mesh (.inp), a Gmsh geometry (.geo)
// and its tetrahedral mesh (.msh, where gmsh is installed), with specimen.json saying what each
// holds against the exact volumes of the same region.
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "aggpack/core/particle_store.hpp"
#include "aggpack/specimen/gmsh_geometry.hpp"
#include "aggpack/specimen/specimen.hpp"

namespace aggpack {

// A bed to cut from: its particles, and what is known of where it lies.
struct SpecimenSource {
  PackedParticles particles;
  std::string description;            // "the final bed of the run in out/x", "the packing file bed.csv"
  Box bed_bounds;                     // the container's sides (or the spheres' extent), floor to the highest top
  std::optional<Box> largest_virtual_box;  // a run's: the default region
  nlohmann::json run;                 // a run's version, scenario file and seed; null for a file
  std::vector<std::string> notes;     // what reading it chose (periodic images, a grain's size)
};
// A run's folder: particles.csv (its grain column), grains.csv (each grain's I) and summary.json
// (the container, the virtual boxes, the run); a periodic bed's particles that cross a side come
// with their images, each grain whole.
[[nodiscard]] SpecimenSource read_run_folder(const std::filesystem::path& folder);
// Any packing file `aggpack analyze` reads, each sphere a particle; lengths in `length_unit` m.
[[nodiscard]] SpecimenSource read_packing_source(const std::filesystem::path& file, double length_unit);
// A bed of spheres held in memory (InputError for one with grains: cut those from their run's
// folder, whose grains.csv gives each grain's size), the bed being the spheres' extent.
[[nodiscard]] SpecimenSource spheres_source(const ParticleStore& spheres, std::string description);

struct SpecimenRequest {
  std::optional<SpecimenRegion> region;  // none: the run's largest virtual box
  double min_size = 0.0, itz_thickness = 0.0, gap = 0.0;  // SpecimenOptions'
  std::optional<double> voxel_size;      // none: the smallest kept particle's size / 10
  double max_voxels = 2e8;
  std::vector<std::string> formats;      // of "vti", "inp", "geo", "msh"; empty: vti, inp, geo (and msh with gmsh)
  std::optional<GmshMeshSizes> mesh_sizes;  // none: from the smallest kept particle and the ITZ
};

// A specimen's values as numbers (the CLI's comma lists, Python's lists), checked: a vertical
// cylinder from x, y, z_lo, z_hi, radius; Gmsh's mesh sizes from aggregate[, mortar[, itz]]
// (the mortar's default twice the aggregate's, the ITZ's the aggregate's). InputError names
// `what` (the option or argument as the user gave it).
[[nodiscard]] VerticalCylinder cylinder_from(const std::vector<double>& values, const std::string& what);
[[nodiscard]] GmshMeshSizes mesh_sizes_from(const std::vector<double>& values, const std::string& what);

// Checks everything before writing (a region outside the bed, a voxel too small for
// max_voxels, an ITZ thicker than the gaps, msh without gmsh: InputError, nothing written),
// then writes the files into `out` and returns specimen.json's content.
nlohmann::json export_specimen(const SpecimenSource& source, const SpecimenRequest& request,
                               const std::filesystem::path& out);

// The volume of each physical group's linear tetrahedra in a Gmsh mesh of format 2.2, by group
// name (InputError for a file that is not one).
[[nodiscard]] std::map<std::string, double> msh_group_volumes(const std::filesystem::path& msh);

}  // namespace aggpack
