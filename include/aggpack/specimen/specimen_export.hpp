#pragma once
// `aggpack specimen`: a specimen cut from a run's final bed (or a packing file) and written for
// meso-model codes: a voxel image (.vti), an Abaqus voxel mesh (.inp), a Gmsh geometry (.geo)
// and its tetrahedral mesh (.msh, where gmsh is installed), with specimen.json saying what each
// holds against the exact volumes of the same region.
#include <filesystem>
#include <functional>
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
  std::optional<VerticalCylinder> container_wall;  // a cylindrical container's: a region lies inside it
  nlohmann::json run;                 // a run's version, scenario file and seed; null for a file
  std::vector<std::string> notes;     // what reading it chose (periodic images, a grain's size)
  // The unit its lengths are shown in beside metres ("in" for a scenario written in inches; a
  // packing file's --length-unit); empty: metres alone.
  std::string length_unit;
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

// What the caller hears while a specimen is made. `safe_point`: called before anything is
// written and every 50 ms while Gmsh meshes; what it throws stops the work there (Gmsh's group
// stopped, its partial mesh removed; the files written so far are whole, specimen.json lists
// them). `say`: a line for the user before a long or large write (the .inp's size, Gmsh's
// estimated tetrahedra).
struct SpecimenHooks {
  std::function<void()> safe_point;
  std::function<void(const std::string&)> say;
};

// Checks everything before writing (a region outside the bed, a voxel too small for
// max_voxels or wider than the specimen, memory beyond the machine's, an ITZ thicker than the
// gaps, msh without gmsh or beyond its element limit, an output folder that cannot be made:
// InputError, nothing written), then writes the files into `out` and returns specimen.json's
// content.
nlohmann::json export_specimen(const SpecimenSource& source, const SpecimenRequest& request,
                               const std::filesystem::path& out, const SpecimenHooks& hooks = {});

// The volume of each physical group's linear tetrahedra in a Gmsh mesh of format 2.2, by group
// name (InputError for a file that is not one).
[[nodiscard]] std::map<std::string, double> msh_group_volumes(const std::filesystem::path& msh);

}  // namespace aggpack
