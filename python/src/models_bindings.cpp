// aggpack.grading, aggpack.predict and aggpack.calibrate: a grading (or a coarse/fine mix)
// described and checked, the analytic packing models on a scenario's or a grading's sizes, and
// their calibration (CPM's K and beta, or a contact parameter by DEM), as the CLI's
// `aggpack grading --json`, `aggpack predict --json` and `aggpack calibrate` give them.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cmath>
#include <filesystem>
#include <optional>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/core/units.hpp"
#include "aggpack/io/atomic_file.hpp"
#include "aggpack/io/shape_option.hpp"
#include "aggpack/run/grading_report.hpp"
#include "aggpack/run/predictions.hpp"
#include "aggpack/run/preflight.hpp"
#include "aggpack/studies/calibration.hpp"
#include "aggpack/studies/dem_calibration.hpp"
#include "bindings.hpp"

namespace aggpack::python {
namespace {

// A length as a number of metres or as text with its unit ("0.1 in", "4.75 mm").
using Length = std::variant<double, std::string>;

std::optional<double> metres(const std::optional<Length>& length, const char* name) {
  if (!length) return std::nullopt;
  if (const double* m = std::get_if<double>(&*length)) {
    if (!(*m > 0.0) || !std::isfinite(*m)) throw InputError(fmt::format("{} {}: expected a positive length (m)", name, *m));
    return *m;
  }
  std::string why;
  const auto parsed = parse_length(std::get<std::string>(*length), &why);
  if (!parsed) throw InputError(fmt::format("{} {}: {}", name, std::get<std::string>(*length), why));
  return parsed;
}

py::object grading(const std::string& name_or_file, const std::optional<std::string>& mix,
                   const std::optional<double>& ca_fa, const std::optional<std::string>& band,
                   const std::optional<Length>& d_min, const std::optional<Length>& d_max,
                   const std::optional<std::string>& length_unit, const std::optional<std::string>& shape,
                   const py::object& seed) {
  GradingQuery query;
  query.named = OptionStyle::Keyword;
  query.grading = name_or_file;
  query.fine = mix;
  query.ca_fa = ca_fa;
  query.band = band;
  query.d_min = metres(d_min, "d_min");
  query.d_max = metres(d_max, "d_max");
  if (length_unit) {
    const auto factor = metres_per_unit(*length_unit);
    if (!factor)
      throw InputError(fmt::format("length_unit {}: unknown unit; expected m, cm, mm, um, in, ft or yd", *length_unit));
    query.length_unit = static_cast<double>(*factor);
  }
  if (shape) query.shape = read_shape_option(*shape, "shape");
  query.seed = seed_of(seed).value_or(1);
  // The templates of `shape` can take minutes: Python's Ctrl-C is honoured between two of them.
  query.watch.progress = [](std::size_t, std::size_t) {
    py::gil_scoped_acquire held;
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
  };
  nlohmann::json j;
  {
    py::gil_scoped_release released;
    j = to_json(describe_grading(query));
  }
  return to_python(j);
}

py::object predict_densities(const std::string& input, const std::optional<std::string>& mix,
                             const std::optional<double>& ca_fa, const std::optional<double>& k,
                             const std::optional<std::string>& process, const std::optional<double>& beta,
                             const std::optional<double>& beta_fine,
                             const std::optional<std::filesystem::path>& calibration, const std::vector<std::string>& set) {
  PredictRequest request;
  request.named = OptionStyle::Keyword;
  request.input = input;
  request.fine = mix;
  request.ca_fa = ca_fa;
  request.compaction_index = k;
  request.process = process;
  request.beta = beta;
  request.beta_fine = beta_fine;
  request.calibration = calibration;
  request.overrides.set = set;
  nlohmann::json j;
  {
    py::gil_scoped_release released;
    j = to_json(predict(request));
  }
  return to_python(j);
}

struct DemFit {
  std::optional<double> measured;
  std::vector<std::string> fit, materials;
  bool shared = false;
  std::optional<std::vector<double>> range;
  int max_runs = 6;
};

py::object calibrate_models(const py::object& scenario, const std::optional<std::filesystem::path>& out, int seeds,
                            int threads, const std::vector<std::string>& set, bool dem, const DemFit& by_dem) {
  check_thread_count(threads, OptionStyle::Keyword);
  const FileAndOverrides source = scenario_file_of(scenario, set, "calibrate");
  if (!dem && (by_dem.measured || !by_dem.fit.empty() || !by_dem.materials.empty() || by_dem.shared || by_dem.range))
    throw InputError("calibrate: measured, fit, materials, shared and range apply to a DEM calibration: give dem=True");
  if (dem && !by_dem.measured)
    throw InputError("calibrate: dem=True needs measured=, the measured packing density of the scenario's bed, "
                     "which the fit reproduces");
  if (out) {  // as the CLI's --out: a file's name in a folder that can be written, before any run
    if (std::filesystem::is_directory(*out))
      throw InputError(fmt::format("calibrate: out={}: a folder; expected the calibration file's name", out->string()));
    check_output_directory(out->has_parent_path() ? out->parent_path() : ".", true);
  }
  nlohmann::json j;
  bool converged = true;
  {
    py::gil_scoped_release released;
    std::ostringstream log;  // quiet: nothing goes there
    CalibrationOptions runs;
    runs.scenario = source.path;
    runs.overrides = source.overrides;
    runs.seeds = seeds;
    runs.threads = threads;
    runs.quiet = true;
    if (dem) {
      DemCalibrationOptions d;
      d.runs = runs;
      d.measured = *by_dem.measured;
      if (!by_dem.fit.empty()) d.fit = by_dem.fit;
      d.materials = by_dem.materials;
      d.shared = by_dem.shared;
      d.range = by_dem.range;
      d.max_evaluations = by_dem.max_runs;
      const DemCalibration c = calibrate_dem(d, log);
      converged = c.search.converged;
      j = to_json(c);
    } else {
      j = to_json(calibrate(runs, log));
    }
    if (out) write_file_atomically(*out, j.dump(1) + "\n");
  }
  // The value is an interpolation the runs did not confirm (warnings as errors: that error).
  if (!converged &&
      PyErr_WarnEx(PyExc_RuntimeWarning,
                   "aggpack.calibrate: NOT CONVERGED: no value's seed mean came within its standard error of the "
                   "measurement; the value is interpolated between the last two (raise max_runs)",
                   1) < 0)
    throw py::error_already_set();
  return to_python(j);
}

}  // namespace

void bind_models(py::module_& m) {
  m.def("grading", &grading, py::arg("grading"), py::kw_only(), py::arg("mix") = py::none(),
        py::arg("ca_fa") = py::none(), py::arg("band") = py::none(), py::arg("d_min") = py::none(),
        py::arg("d_max") = py::none(), py::arg("length_unit") = py::none(), py::arg("shape") = py::none(),
        py::arg("seed") = 1,
        R"doc(A grading described and checked, as `aggpack grading --json` gives it (a dict).

`grading`: a shipped grading's name (`aggpack grading --list`) or a CSV sieve analysis; `mix`: a
fine grading blended with it at `ca_fa` (coarse/fine by volume; the two go together, `ca_fa`
has no default); `band`: a shipped band to
check against; `d_min`, `d_max`: cut-offs, in m or as text with a unit ("0.1 in");
`length_unit`: of a bare `opening` column in a file; `shape`: a component's shape table as
text ('family="angular", flakiness_index=18'), whose generated grains are measured beside the
target, drawn with `seed`.)doc");
  m.def("predict", &predict_densities, py::arg("input"), py::kw_only(), py::arg("mix") = py::none(),
        py::arg("ca_fa") = py::none(), py::arg("k") = py::none(), py::arg("process") = py::none(),
        py::arg("beta") = py::none(), py::arg("beta_fine") = py::none(), py::arg("calibration") = py::none(),
        py::arg("set") = std::vector<std::string>{},
        R"doc(The analytic packing densities (CPM, Furnas, Desmond-Weeks) of a scenario's or a grading's
sizes, as `aggpack predict --json` gives them (a dict).

`input`: a scenario file (.toml; `set` overrides it as --set), a shipped grading's name or a CSV
sieve analysis; `mix`, `ca_fa`: a blend (the two go together); `k`: CPM's compaction index, or `process` ("poured",
"rodded", "vibrated", "vibrated_compressed"); `beta`, `beta_fine`: residual packing densities;
`calibration`: K and beta from a file `aggpack calibrate` wrote.)doc");
  m.def(
      "calibrate",
      [](const py::object& scenario, const std::optional<std::filesystem::path>& out, int seeds, int threads,
         const std::vector<std::string>& set, bool dem, std::optional<double> measured,
         const std::vector<std::string>& fit, const std::vector<std::string>& materials, bool shared,
         const std::optional<std::vector<double>>& range, int max_runs) {
        return calibrate_models(scenario, out, seeds, threads, set, dem,
                                DemFit{measured, fit, materials, shared, range, max_runs});
      },
      py::arg("scenario"), py::kw_only(), py::arg("out") = py::none(), py::arg("seeds") = 3, py::arg("threads") = 0,
      py::arg("set") = std::vector<std::string>{}, py::arg("dem") = false, py::arg("measured") = py::none(),
      py::arg("fit") = std::vector<std::string>{}, py::arg("materials") = std::vector<std::string>{},
      py::arg("shared") = false, py::arg("range") = py::none(), py::arg("max_runs") = 6,
      R"doc(Calibrates the models from simulations of a scenario, as `aggpack calibrate` does, and
returns the calibration file's dict (written to `out` too, when given).

`scenario`: a scenario file's path or an aggpack.Scenario read from its file (`set` adds --set
overrides). Without `dem`: CPM's K and beta from a monosized bed and the scenario's mix, each
over `seeds` seeds (what predict(..., calibration=) and a scenario's models.calibration read).
With `dem=True`: the value of a contact parameter (`fit`: ["rolling_friction"] by default, or
["friction"]) of `materials` (default: the bed's one material; `shared`: one value for all)
for which the scenario's own protocol packs at the `measured` density, searched in `range`
[low, high] with at most `max_runs` values (a file for --calibration and
dynamics.calibration). A DEM search that did not converge warns (RuntimeWarning). The runs
release the GIL; Ctrl-C is taken once the calibration returns.)doc");
}

}  // namespace aggpack::python
