#pragma once
// A specimen as a Gmsh geometry (.geo, the OpenCASCADE kernel): the region, the union of the
// kept spheres cut by it (aggregate), their ITZ shells less the aggregate (itz), the rest
// (mortar), each as disjoint pieces glued (BooleanFragments) so that all share their faces, with the physical groups
// "aggregate", "mortar" and "itz" and a mesh size per phase; and, where Debian's `gmsh` is
// installed, the tetrahedral mesh it makes of it (.msh, format 2.2).
#include <filesystem>
#include <string>
#include <string_view>

#include "aggpack/specimen/specimen.hpp"

namespace aggpack {

struct GmshMeshSizes {
  double aggregate = 0.0, mortar = 0.0, itz = 0.0;  // m: the elements' size in each phase
  int elements_per_circle = 40;  // at least this many elements around a curved face (by curvature)
};

[[nodiscard]] std::string gmsh_geo(const Specimen& specimen, const GmshMeshSizes& sizes, std::string_view provenance);

// Whether `gmsh` is on PATH.
[[nodiscard]] bool gmsh_available();
// Meshes `geo` in 3-D into `msh` (one thread: the same mesh every time), Gmsh's output in `log`.
// InputError naming the log when Gmsh fails or writes no mesh.
void run_gmsh(const std::filesystem::path& geo, const std::filesystem::path& msh, const std::filesystem::path& log);

}  // namespace aggpack
