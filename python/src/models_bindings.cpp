// aggpack.grading and aggpack.predict: a grading (or a coarse/fine mix) described and checked,
// and the analytic packing models on a scenario's or a grading's sizes, as the CLI's
// `aggpack grading --json` and `aggpack predict --json` give them.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/core/units.hpp"
#include "aggpack/io/shape_option.hpp"
#include "aggpack/run/grading_report.hpp"
#include "aggpack/run/predictions.hpp"
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

py::object grading(const std::string& name_or_file, const std::optional<std::string>& mix, double ca_fa,
                   const std::optional<std::string>& band, const std::optional<Length>& d_min,
                   const std::optional<Length>& d_max, const std::optional<std::string>& length_unit,
                   const std::optional<std::string>& shape, std::uint64_t seed) {
  GradingQuery query;
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
  query.seed = seed;
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

}  // namespace

void bind_models(py::module_& m) {
  m.def("grading", &grading, py::arg("grading"), py::kw_only(), py::arg("mix") = py::none(), py::arg("ca_fa") = 1.0,
        py::arg("band") = py::none(), py::arg("d_min") = py::none(), py::arg("d_max") = py::none(),
        py::arg("length_unit") = py::none(), py::arg("shape") = py::none(), py::arg("seed") = 1,
        R"doc(A grading described and checked, as `aggpack grading --json` gives it (a dict).

`grading`: a shipped grading's name (`aggpack grading --list`) or a CSV sieve analysis; `mix`: a
fine grading blended with it at `ca_fa` (coarse/fine by volume); `band`: a shipped band to
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
sieve analysis; `mix`, `ca_fa`: a blend; `k`: CPM's compaction index, or `process` ("poured",
"rodded", "vibrated", "vibrated_compressed"); `beta`, `beta_fine`: residual packing densities;
`calibration`: K and beta from a file `aggpack calibrate` wrote.)doc");
}

}  // namespace aggpack::python
