// The Python module `aggpack._aggpack`: the library's scenarios, runs, beds and errors
// (aggpack/__init__.py re-exports them). README, "Python".
#include <exception>
#include <string>

#include "aggpack/core/error.hpp"
#include "aggpack/core/stop_request.hpp"
#include "bindings.hpp"

PYBIND11_MODULE(_aggpack, m) {
  namespace py = pybind11;
  m.doc() = "aggpack: random packings of polydisperse spheres and grains, and the packing density of aggregates.";
  // Bad input: a ValueError with the CLI's exit-2 message.
  py::register_exception<aggpack::InputError>(m, "InputError", PyExc_ValueError);
  // A run stopped before it had a report to give (while its grains' templates were made).
  py::register_exception_translator([](std::exception_ptr raised) {
    try {
      if (raised) std::rethrow_exception(raised);
    } catch (const aggpack::Interrupted& e) {
      PyErr_SetString(PyExc_KeyboardInterrupt, (std::string("aggpack: ") + e.what() + "; nothing was written").c_str());
    }
  });
  aggpack::python::bind_scenario(m);
  aggpack::python::bind_bed(m);
  aggpack::python::bind_run(m);
  aggpack::python::bind_analysis(m);
  aggpack::python::bind_models(m);
  aggpack::python::bind_lammps(m);
}
