#pragma once
// A specimen as a Gmsh geometry (.geo, the OpenCASCADE kernel): the region, the union of the
// kept spheres cut by it (aggregate), their ITZ shells less the aggregate (itz), the rest
// (mortar), each as disjoint pieces glued (BooleanFragments) so that all share their faces, with the physical groups
// "aggregate", "mortar" and "itz" and a mesh size per phase; and, where Debian's `gmsh` is
// installed, the tetrahedral mesh it makes of it (.msh, format 2.2).
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include "aggpack/specimen/specimen.hpp"

namespace aggpack {

struct GmshMeshSizes {
  double aggregate = 0.0, mortar = 0.0, itz = 0.0;  // m: the elements' size in each phase
  int elements_per_circle = 40;  // at least this many elements around a curved face (by curvature)
};

[[nodiscard]] std::string gmsh_geo(const Specimen& specimen, const GmshMeshSizes& sizes, std::string_view provenance);

// `gmsh` on PATH, if it is there.
[[nodiscard]] std::optional<std::filesystem::path> gmsh_executable();
[[nodiscard]] bool gmsh_available();
// Meshes `geo` in 3-D into `msh` (one thread: the same mesh every time), Gmsh's output in `log`.
// Gmsh runs without a shell, in a process group of its own; `safe_point` is called every 50 ms
// while it meshes, and what it throws (Interrupted, Python's KeyboardInterrupt) stops Gmsh's
// group and removes its partial mesh before propagating. InputError naming the log when Gmsh
// fails or writes a mesh of no tetrahedron (the file removed: no empty mesh is left).
void run_gmsh(const std::filesystem::path& geo, const std::filesystem::path& msh, const std::filesystem::path& log,
              const std::function<void()>& safe_point = {});

}  // namespace aggpack
