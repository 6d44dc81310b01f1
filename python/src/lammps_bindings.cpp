// aggpack.export_lammps and aggpack.import_lammps: the CLI's bridge commands from Python. They
// read their scenario from its file (a checkpoint, a deck and an imported run record where it
// lies), so a Scenario made from text or a dict is refused, with what to do.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <filesystem>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/io/scenario.hpp"
#include "aggpack/run/lammps_steps.hpp"
#include "aggpack/run/run.hpp"
#include "bindings.hpp"
#include "python_scenario.hpp"

namespace aggpack::python {

void bind_lammps(py::module_& m) {
  m.def(
      "export_lammps",
      [](const py::object& scenario_or_run, const std::filesystem::path& out, bool tap, const std::vector<std::string>& set) {
        const FileAndOverrides source = scenario_file_of(scenario_or_run, set, "export_lammps");
        py::gil_scoped_release released;
        std::ostringstream log;
        return export_lammps(source.path, source.overrides, out, tap, log);
      },
      py::arg("scenario_or_run"), py::arg("out"), py::kw_only(), py::arg("tap") = false,
      py::arg("set") = std::vector<std::string>{},
      R"doc(Writes a bed and a LAMMPS deck into `out`, as `aggpack export-lammps` does; returns the step exported.

`scenario_or_run`: a scenario file's path (or a Scenario read from its file): the steps before
its first DEM step are run and that step's deck written; or a finished run's folder: its final
bed and a deck that settles it (`tap`: taps it). `set`: --set assignments. README, "Running
larger beds on many cores or a cluster".)doc");
  m.def(
      "import_lammps",
      [](const std::filesystem::path& file, const py::object& scenario, const std::filesystem::path& out,
         std::optional<std::int64_t> timestep, const std::vector<std::string>& set) {
        const FileAndOverrides source = scenario_file_of(scenario, set, "import_lammps");
        RunOptions options;
        options.quiet = true;
        options.overrides = source.overrides;
        options.overrides.output_directory = out;
        RunResult result = [&] {
          py::gil_scoped_release released;
          std::ostringstream log;
          return import_lammps(file, timestep, source.path, options, log);
        }();
        return report_of(std::move(result));
      },
      py::arg("file"), py::kw_only(), py::arg("scenario"), py::arg("out"), py::arg("timestep") = py::none(),
      py::arg("set") = std::vector<std::string>{},
      "Analyses the spheres of a LAMMPS dump (its last snapshot, or `timestep`'s) or data file in a scenario's "
      "container with its analysis settings, as `aggpack import-lammps` does, writing aggpack's outputs into `out`; "
      "returns the run's aggpack.Report.");
}

}  // namespace aggpack::python
