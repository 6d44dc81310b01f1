// aggpack.read_bed, Bed.from_arrays and aggpack.analyze: a bed made elsewhere (a file of any
// tool, numpy arrays) measured as `aggpack analyze` measures it.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/core/units.hpp"
#include "aggpack/io/particle_file.hpp"
#include "aggpack/run/analyze_bed.hpp"
#include "aggpack/specimen/specimen_export.hpp"
#include "bindings.hpp"
#include "python_bed.hpp"

namespace aggpack::python {
namespace {

using Rows = py::array_t<double, py::array::c_style | py::array::forcecast>;

double unit_of(const std::string& length_unit) {
  const auto factor = metres_per_unit(length_unit);
  if (!factor)
    throw InputError(fmt::format("length_unit {}: unknown unit; expected m, cm, mm, um, in, ft or yd", length_unit));
  return static_cast<double>(*factor);
}

std::shared_ptr<PyBed> read_bed(const std::filesystem::path& path, const std::string& length_unit,
                                std::optional<std::int64_t> timestep) {
  const double unit = unit_of(length_unit);
  PackingFile file = [&] {
    py::gil_scoped_release released;
    return read_packing_file(path, unit, 1.0, kDefaultMaxInputFileBytes, timestep);
  }();
  // A run with grains' particles.csv: its spheres are grains' members, which a Bed of spheres
  // would take for separate particles (their overlaps counted twice); refused as the CLI's
  // analyze and specimen refuse it.
  if (std::any_of(file.grains.begin(), file.grains.end(), [](std::uint32_t g) { return g != 0; }))
    throw InputError(fmt::format("{}: its grain column puts spheres into grains, and a Bed holds separate spheres; "
                                 "cut a run with grains from its folder (aggpack.specimen(folder, ...), its grains.csv "
                                 "gives each grain's size)",
                                 path.string()));
  auto store = std::make_shared<ParticleStore>(std::move(file.particles));
  return std::make_shared<PyBed>(PyBed{std::move(store), path.string(), file.format, std::move(file.materials)});
}

// Rows of `columns` finite numbers (columns 0: a vector), else InputError naming the argument.
Rows checked_rows(const py::handle& value, const char* name, std::size_t count, std::size_t columns) {
  Rows a = Rows::ensure(value);
  if (!a) throw InputError(fmt::format("{}: expected an array of numbers", name));
  const bool shape_ok = columns == 0 ? a.ndim() == 1 : a.ndim() == 2 && static_cast<std::size_t>(a.shape(1)) == columns;
  if (!shape_ok || (count != 0 && static_cast<std::size_t>(a.shape(0)) != count))
    throw InputError(fmt::format("{}: an array of shape {}; expected {}", name,
                                 py::str(py::tuple(a.attr("shape"))).cast<std::string>(),
                                 columns == 0 ? fmt::format("({},)", count ? std::to_string(count) : "N")
                                              : fmt::format("({}, {})", count ? std::to_string(count) : "N", columns)));
  const double* data = a.data();
  for (py::ssize_t k = 0; k < a.size(); ++k)
    if (!std::isfinite(data[k])) throw InputError(fmt::format("{}: entry {} is {}; expected finite numbers", name, k, data[k]));
  return a;
}

std::shared_ptr<PyBed> from_arrays(const py::handle& positions, const py::handle& radii, const py::handle& velocities,
                                   const py::handle& materials, double density) {
  const Rows p = checked_rows(positions, "positions", 0, 3);
  const auto n = static_cast<std::size_t>(p.shape(0));
  const Rows r = checked_rows(radii, "radii", n, 0);
  if (!(density > 0.0) || !std::isfinite(density))
    throw InputError(fmt::format("density {}: expected a positive number (kg/m^3)", density));
  auto store = std::make_shared<ParticleStore>();
  store->reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (!(r.data()[i] > 0.0))
      throw InputError(fmt::format("radii: entry {} is {}; expected a positive radius (m)", i, r.data()[i]));
    store->add({p.data()[3 * i], p.data()[3 * i + 1], p.data()[3 * i + 2]}, r.data()[i], density);
  }
  if (!velocities.is_none()) {
    const Rows v = checked_rows(velocities, "velocities", n, 3);
    for (std::size_t i = 0; i < n; ++i) store->velocity[i] = {v.data()[3 * i], v.data()[3 * i + 1], v.data()[3 * i + 2]};
  }
  if (!materials.is_none()) {
    const Rows m = checked_rows(materials, "materials", n, 0);
    for (std::size_t i = 0; i < n; ++i) {
      const double k = m.data()[i];
      if (!(k >= 0.0 && k < 256.0 && k == std::floor(k)))
        throw InputError(fmt::format("materials: entry {} is {}; expected a material's index, 0 to 255", i, k));
      store->material[i] = static_cast<std::uint8_t>(k);
    }
  }
  return std::make_shared<PyBed>(PyBed{std::move(store), "the bed from arrays", "", {}});
}

py::object analyze(const py::object& bed_or_path, const std::vector<double>& cubes,
                   const std::vector<std::vector<double>>& boxes, double tolerance, double overlap_tolerance,
                   bool soft_contacts, const std::string& length_unit, std::optional<std::int64_t> timestep) {
  const bool is_bed = py::isinstance<PyBed>(bed_or_path);
  const std::shared_ptr<PyBed> bed = is_bed ? bed_or_path.cast<std::shared_ptr<PyBed>>()
                                            : read_bed(bed_or_path.cast<std::filesystem::path>(), length_unit, timestep);
  const double unit = is_bed ? 1.0 : unit_of(length_unit);  // a file's bare lengths are in its unit
  BedAnalysisOptions options;
  options.tolerance = tolerance;
  options.overlap_tolerance = overlap_tolerance;
  options.soft_contacts = soft_contacts;
  for (const double side : cubes) {
    if (!(side > 0.0) || !std::isfinite(side))
      throw InputError(fmt::format("cubes: {}: expected a positive side", side));
    options.cube_sides.push_back(side * unit);
  }
  for (const auto& b : boxes) {
    if (b.size() != 6) throw InputError(fmt::format("boxes: a box of {} numbers; expected xmin, ymin, zmin, xmax, ymax, zmax", b.size()));
    options.boxes.push_back({{b[0] * unit, b[1] * unit, b[2] * unit}, {b[3] * unit, b[4] * unit, b[5] * unit}});
  }
  nlohmann::json j;
  {
    py::gil_scoped_release released;
    const BedAnalysis analysis = analyze_bed(*bed->store, options, bed->source);
    j = to_json(analysis, bed->store->size(), soft_contacts);
  }
  j["file"] = bed->source;    // as `aggpack analyze --json`: the file, or where a Bed in memory came from
  j["source"] = bed->source;  // deprecated: `file`'s former name, kept for the scripts that read it
  if (!bed->format.empty()) j["format"] = bed->format;
  return to_python(j);
}

// aggpack.specimen: the CLI's `aggpack specimen` on a run's folder, a packing file or a Bed.
py::object specimen(const py::object& source, const std::filesystem::path& out,
                    const std::optional<std::vector<double>>& box, const std::optional<std::vector<double>>& cylinder,
                    std::optional<double> voxel, double itz, double min_size, double gap,
                    const std::vector<std::string>& formats, const std::optional<std::vector<double>>& mesh_size,
                    double max_voxels, const std::string& length_unit) {
  SpecimenRequest request;
  if (box && cylinder) throw InputError("specimen: box and cylinder: give one specimen");
  if (box) {
    if (box->size() != 6) throw InputError("specimen: box: expected [xmin, ymin, zmin, xmax, ymax, zmax]");
    request.region = Box{{(*box)[0], (*box)[1], (*box)[2]}, {(*box)[3], (*box)[4], (*box)[5]}};
  }
  if (cylinder) request.region = cylinder_from(*cylinder, "specimen: cylinder (m)");
  for (const double length : {itz, min_size, gap})
    if (!(length >= 0.0) || !std::isfinite(length))
      throw InputError(fmt::format("specimen: itz, min_size and gap: {} is not a length of zero or more", length));
  request.voxel_size = voxel;
  request.itz_thickness = itz;
  request.min_size = min_size;
  request.gap = gap;
  request.formats = formats;
  request.max_voxels = max_voxels;
  if (mesh_size) request.mesh_sizes = mesh_sizes_from(*mesh_size, "specimen: mesh_size (m)");
  std::optional<SpecimenSource> bed;
  if (py::isinstance<PyBed>(source)) {
    const auto& b = source.cast<const PyBed&>();
    bed = spheres_source(*b.store, b.source);
  }
  const std::filesystem::path path = bed ? std::filesystem::path() : source.cast<std::filesystem::path>();
  nlohmann::json report;
  {
    py::gil_scoped_release released;
    if (!bed) bed = std::filesystem::is_directory(path) ? read_run_folder(path) : read_packing_source(path, unit_of(length_unit));
    // Python's Ctrl-C (Gmsh, in a process group of its own, does not see it): a
    // KeyboardInterrupt that stops Gmsh and removes its partial mesh.
    SpecimenHooks hooks;
    hooks.safe_point = [] {
      py::gil_scoped_acquire held;
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    };
    report = export_specimen(*bed, request, out, hooks);
  }
  return to_python(report);
}

}  // namespace

void bind_analysis(py::module_& m) {
  m.def("read_bed", &read_bed, py::arg("path"), py::kw_only(), py::arg("length_unit") = "m",
        py::arg("timestep") = py::none(),
        "Reads a packing file as `aggpack analyze` does (CSV with x,y,z,r or diameter, whitespace x y z r, a LAMMPS "
        "dump or data file; `timestep`: a dump's snapshot, default the last) into an aggpack.Bed of its own. A run "
        "with grains' particles.csv (its grain column) is refused: a Bed holds separate spheres; cut such a run "
        "from its folder with aggpack.specimen.");
  py::class_<PyBed, std::shared_ptr<PyBed>>(m.attr("Bed"))
      .def_static("from_arrays", &from_arrays, py::arg("positions"), py::arg("radii"), py::kw_only(),
                  py::arg("velocities") = py::none(), py::arg("materials") = py::none(), py::arg("density") = 1.0,
                  "A bed of its own from arrays: positions N x 3 and radii N, m (velocities N x 3, m/s; materials N, "
                  "each sphere's material as an index of a scenario's materials, default 0; density, kg/m^3, for "
                  "the masses: a run from the bed takes its materials' instead). The numbers are copied.");
  m.def("analyze", &analyze, py::arg("bed"), py::kw_only(), py::arg("cubes") = std::vector<double>{},
        py::arg("boxes") = std::vector<std::vector<double>>{}, py::arg("tolerance") = 1e-6,
        py::arg("overlap_tolerance") = BedAnalysisOptions{}.overlap_tolerance, py::arg("soft_contacts") = false,
        py::arg("length_unit") = "m", py::arg("timestep") = py::none(),
        R"doc(Measures a bed as `aggpack analyze --json` does and returns that dict.

`bed`: an aggpack.Bed (a run's, read_bed's, Bed.from_arrays') or a packing file's path (read
with `length_unit` and `timestep`, as read_bed). The container is the spheres' bounding box.
`cubes`: virtual cube sides, placed as in docs/method.md section 2 (none: the largest that
fits); `boxes`: explicit boxes [xmin, ymin, zmin, xmax, ymax, zmax]; for a file both are in its
`length_unit`, for a Bed in m. Overlapping spheres deeper than `overlap_tolerance` x the
smaller radius are refused unless `soft_contacts` (a soft-contact DEM's bed). Its `file`
names the packing file (for a Bed, where it came from), as the CLI's; `source`, the same, is
deprecated.)doc");
  m.def("specimen", &specimen, py::arg("source"), py::arg("out"), py::kw_only(), py::arg("box") = py::none(),
        py::arg("cylinder") = py::none(), py::arg("voxel") = py::none(), py::arg("itz") = 0.0,
        py::arg("min_size") = 0.0, py::arg("gap") = 0.0, py::arg("formats") = std::vector<std::string>{},
        py::arg("mesh_size") = py::none(), py::arg("max_voxels") = 2e8, py::arg("length_unit") = "m",
        R"doc(Cuts a concrete specimen for meso-models, as `aggpack specimen` does, writes its files into
`out` and returns specimen.json's dict (README, "Concrete specimens for meso-models").

`source`: a run's output folder (its final bed; the default specimen its largest virtual box),
a packing file (read in `length_unit`) or an aggpack.Bed of spheres. `box` [xmin, ymin, zmin,
xmax, ymax, zmax] or `cylinder` [x, y, z_lo, z_hi, radius] (vertical), in m; `voxel`: the
voxel's side (default a tenth of the smallest kept sphere's diameter); `itz`: the ITZ's
thickness; `min_size`: smaller particles are mortar; `gap`: kept particles shrunk so that
touching ones stand this far apart (Gmsh cannot mesh touching spheres); `formats`: of "vti",
"inp", "geo", "msh" (default the first three); `mesh_size`: Gmsh's [aggregate, mortar, itz].
A Bed whose spheres overlap deeper than a DEM contact is refused (as analyze() refuses it: its
overlaps would count twice); an `out` that cannot be a folder raises InputError. Ctrl-C while
Gmsh meshes raises KeyboardInterrupt, Gmsh stopped and its partial mesh removed.)doc");
}

}  // namespace aggpack::python
