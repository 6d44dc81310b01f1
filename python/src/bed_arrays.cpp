// aggpack.Bed: a bed's spheres and grains as numpy arrays, zero-copy and read-only.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <memory>
#include <string>

#include "bindings.hpp"
#include "python_bed.hpp"

namespace aggpack::python {
namespace {

static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 is viewed as three doubles");
static_assert(sizeof(Quaternion) == 4 * sizeof(double), "Quaternion is viewed as four doubles");

// A read-only view of `count` rows of `columns` values of T at `data` (columns 0: a vector),
// whose base is the Bed: the view keeps the store alive however long it lives.
template <class T>
py::array view(const std::shared_ptr<PyBed>& bed, const T* data, std::size_t count, std::size_t columns) {
  py::object base = py::cast(bed);
  py::array a = columns == 0
                    ? py::array_t<T>({count}, {sizeof(T)}, data, base)
                    : py::array_t<T>({count, columns}, {columns * sizeof(T), sizeof(T)}, data, base);
  a.attr("setflags")(py::arg("write") = false);
  return a;
}

py::array vec3_view(const std::shared_ptr<PyBed>& bed, const std::vector<Vec3>& v) {
  return view(bed, reinterpret_cast<const double*>(v.data()), v.size(), 3);
}

// The grains' arrays: the sphere-to-grain map and each grain's pose and volume.
void add_grain_views(py::class_<PyBed, std::shared_ptr<PyBed>>& bed) {
  bed
      .def_property_readonly(
          "grains",
          [](const std::shared_ptr<PyBed>& b) -> py::object {
            if (b->store->bodies.empty()) return py::none();
            return view(b, b->store->body.data(), b->store->body.size(), 0);
          },
          "Each sphere's grain, an index into the grain arrays (aggpack.NO_GRAIN for a sphere of its own; "
          "particles.csv's grain column is this + 1, 0 for none): N uint32; None for a bed without grains.")
      .def_property_readonly(
          "grain_count", [](const PyBed& b) { return b.store->bodies.size(); }, "How many grains.")
      .def_property_readonly(
          "grain_positions",
          [](const std::shared_ptr<PyBed>& b) { return vec3_view(b, b->store->bodies.position); },
          "Each grain's centre of mass, m: G x 3 float64.")
      .def_property_readonly(
          "grain_orientations",
          [](const std::shared_ptr<PyBed>& b) {
            const auto& q = b->store->bodies.orientation;
            return view(b, reinterpret_cast<const double*>(q.data()), q.size(), 4);
          },
          "Each grain's orientation, the unit quaternion (w, x, y, z) from its body frame to space: G x 4 float64.")
      .def_property_readonly(
          "grain_volumes",
          [](const std::shared_ptr<PyBed>& b) {
            return view(b, b->store->bodies.volume.data(), b->store->bodies.size(), 0);
          },
          "Each grain's volume (its spheres' union, each point once), m^3: G float64.");
}

}  // namespace

const ParticleStore* starting_bed_of(const PyBed& bed, const Scenario& sc, std::optional<ParticleStore>& named) {
  if (bed.material_names.empty()) return bed.store.get();
  named = *bed.store;
  assign_file_materials(*named, bed.material_names, sc, bed.source);
  return &*named;
}

void bind_bed(py::module_& m) {
  m.attr("NO_GRAIN") = py::int_(kNoBody);
  py::class_<PyBed, std::shared_ptr<PyBed>> bed(m, "Bed", R"doc(A bed of spheres, and of grains when it has them.

Its arrays are numpy views of the bed as aggpack holds it, taken without a copy: read-only
(writing raises ValueError), in SI units, row i being sphere i (particles.csv's id i + 1).
A view keeps the bed alive: it stays valid after the report it came from is gone, for as long
as the view itself lives. `copy()` gives writable copies.)doc");
  bed.def("__len__", [](const PyBed& b) { return b.store->size(); })
      .def_property_readonly("count", [](const PyBed& b) { return b.store->size(); }, "How many spheres.")
      .def_property_readonly(
          "positions", [](const std::shared_ptr<PyBed>& b) { return vec3_view(b, b->store->position); },
          "Centres, m: N x 3 float64.")
      .def_property_readonly(
          "velocities", [](const std::shared_ptr<PyBed>& b) { return vec3_view(b, b->store->velocity); },
          "Velocities, m/s: N x 3 float64 (zero for a bed that no DEM moved).")
      .def_property_readonly(
          "radii", [](const std::shared_ptr<PyBed>& b) { return view(b, b->store->radius.data(), b->store->size(), 0); },
          "Radii, m: N float64.")
      .def_property_readonly(
          "masses", [](const std::shared_ptr<PyBed>& b) { return view(b, b->store->mass.data(), b->store->size(), 0); },
          "Masses, kg: N float64 (a grain's sphere: its own sphere's).")
      .def_property_readonly(
          "materials",
          [](const std::shared_ptr<PyBed>& b) { return view(b, b->store->material.data(), b->store->material.size(), 0); },
          "Each sphere's material, as an index into the scenario's materials: N uint8 (all 0 for a file's bed "
          "whose material column names them: see material_names).")
      .def_property_readonly(
          "material_names",
          [](const PyBed& b) -> py::object {
            if (b.material_names.empty()) return py::none();
            return py::cast(b.material_names);
          },
          "A file's material column, each sphere's material by name (a run from the bed takes the scenario's "
          "materials of those names); None for a bed without one.")
      .def_property_readonly(
          "layers",
          [](const std::shared_ptr<PyBed>& b) { return view(b, b->store->layer.data(), b->store->layer.size(), 0); },
          "Each sphere's part of a layered protocol (0 for one pass): N uint32.")
      .def(
          "copy",
          [](const std::shared_ptr<PyBed>& b) {
            py::dict copies;
            for (const char* name : {"positions", "velocities", "radii", "masses", "materials", "layers"})
              copies[name] = py::cast(b).attr(name).attr("copy")();
            if (!b->store->bodies.empty())
              for (const char* name : {"grains", "grain_positions", "grain_orientations", "grain_volumes"})
                copies[name] = py::cast(b).attr(name).attr("copy")();
            return copies;
          },
          "Writable copies of every array, by name, as a dict.")
      .def_property_readonly("source", [](const PyBed& b) { return b.source; },
                             "What the bed is: a file's path, \"the run's bed\", \"the bed from arrays\".")
      .def_property_readonly("format", [](const PyBed& b) { return b.format; },
                             "A file's format as read (\"CSV\", \"LAMMPS dump, timestep 1000 (the last of 3)\"); "
                             "empty for a bed of no file.")
      .def("__repr__", [](const PyBed& b) {
        return "<aggpack.Bed of " + std::to_string(b.store->size()) + " spheres" +
               (b.store->bodies.empty() ? std::string() : ", " + std::to_string(b.store->bodies.size()) + " grains") +
               ">";
      });
  add_grain_views(bed);
}

}  // namespace aggpack::python
