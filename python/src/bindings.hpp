// The Python module's parts, each binding one concern of the library; module.cpp puts them
// together. Bad input reaches Python as InputError (a ValueError), a stopped run as
// KeyboardInterrupt; pybind11 maps any other C++ exception to its Python kind (a
// std::invalid_argument from a bed the library cannot take: ValueError; the rest: RuntimeError).
#pragma once
#include <pybind11/pybind11.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "aggpack/run/run.hpp"

namespace aggpack::python {

namespace py = pybind11;

void bind_scenario(py::module_& m);
void bind_bed(py::module_& m);
void bind_run(py::module_& m);
void bind_analysis(py::module_& m);  // after bind_bed: it adds to Bed
void bind_models(py::module_& m);
void bind_lammps(py::module_& m);  // after bind_run: it returns Reports

// A finished run into a folder as an aggpack.Report (the GIL held).
py::object report_of(RunResult&& result);

// A scenario file and its overrides, from a path (with `set`) or from an aggpack.Scenario read
// from its file (its --set and seed, then `set`), for the calls that read a scenario file
// (`function` names the call in the InputError for a Scenario made from text or a dict).
struct FileAndOverrides {
  std::filesystem::path path;
  ScenarioOverrides overrides;
};
FileAndOverrides scenario_file_of(const py::object& scenario, const std::vector<std::string>& set,
                                  const char* function);

// A `seed=` argument: None (not given), or an int in the scenario file's range, 0 to 2^63 - 1
// (InputError otherwise, rather than pybind11's TypeError of an unsigned argument).
std::optional<std::uint64_t> seed_of(const py::object& seed);

// JSON values to Python's (dict, list, str, int, float, bool, None) and back.
py::object to_python(const nlohmann::json& value);
nlohmann::json to_json(const py::handle& value);

}  // namespace aggpack::python
