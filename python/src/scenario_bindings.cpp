// aggpack.Scenario: a scenario from a file, from TOML text or from a dict of the same keys,
// with the CLI's --set overrides and --seed, validated as `aggpack check` validates it.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cstdint>
#include <filesystem>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "aggpack/io/scenario.hpp"
#include "aggpack/run/run.hpp"
#include "bindings.hpp"
#include "python_bed.hpp"
#include "python_scenario.hpp"

namespace aggpack::python {
namespace {

ScenarioOverrides overrides_of(const std::vector<std::string>& set, std::optional<std::uint64_t> seed) {
  ScenarioOverrides overrides;
  overrides.set = set;
  overrides.seed = seed;
  return overrides;
}

// A dict's value as TOML: tables, arrays (of tables too), strings, numbers and booleans.
// `depth`: of the tables and arrays around it, bounded as toml++ bounds a file's (a dict nested
// deeper, or one holding itself, would otherwise recurse until the stack is gone).
toml::array toml_array(const py::handle& list, const std::string& key, int depth);
toml::table toml_table(const py::dict& dict, const std::string& key, int depth);

constexpr int kMaxDictDepth = TOML_MAX_NESTED_VALUES;  // 256, toml++'s bound on a file's nesting

// The key at which a dict is nested too deep: its first parts, then how deep it goes.
[[noreturn]] void too_deep(const std::string& key) {
  const std::string shown = key.size() > 60 ? key.substr(0, 60) + "..." : key;
  throw InputError(fmt::format("scenario dict: {}: nested deeper than {} levels of dicts and lists (TOML's bound, as "
                               "toml++ reads a file; a dict that holds itself never ends): a scenario's keys are a "
                               "few levels deep",
                               shown, kMaxDictDepth));
}

// numpy's scalars (np.int64, np.float64, np.bool_, np.str_) as the Python values they hold.
bool is_numpy_scalar(const py::handle& value) {
  const py::object generic = py::module_::import("numpy").attr("generic");
  return py::isinstance(value, generic);
}

std::int64_t toml_integer(const py::handle& value, const std::string& key) {
  try {
    return value.cast<std::int64_t>();
  } catch (const py::cast_error&) {
    throw InputError("scenario dict: " + key + ": " + py::str(value).cast<std::string>() +
                     " is beyond TOML's 64-bit integers");
  }
}

template <class Put>
void put_value(const py::handle& value, const std::string& key, int depth, Put&& put) {
  if (is_numpy_scalar(value)) put_value(value.attr("item")(), key, depth, std::forward<Put>(put));
  else if (py::isinstance<py::bool_>(value)) put(value.cast<bool>());
  else if (py::isinstance<py::int_>(value)) put(toml_integer(value, key));
  else if (py::isinstance<py::float_>(value)) put(value.cast<double>());
  else if (py::isinstance<py::str>(value)) put(value.cast<std::string>());
  else if (py::isinstance<py::dict>(value)) put(toml_table(value.cast<py::dict>(), key, depth + 1));
  else if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) put(toml_array(value, key, depth + 1));
  else
    throw InputError("scenario dict: " + key + ": expected a dict, list, str, number or bool, not " +
                     py::str(py::type::of(value).attr("__name__")).cast<std::string>());
}

toml::table toml_table(const py::dict& dict, const std::string& key, int depth) {
  if (depth > kMaxDictDepth) too_deep(key);
  toml::table table;
  for (const auto& [name, value] : dict) {
    if (!py::isinstance<py::str>(name)) throw InputError("scenario dict: " + key + ": every key must be a str");
    const std::string k = name.cast<std::string>();
    const std::string path = key.empty() ? k : key + "." + k;
    if (value.is_none()) continue;  // None: the key is not given
    put_value(value, path, depth, [&](auto&& v) { table.insert_or_assign(k, std::forward<decltype(v)>(v)); });
  }
  return table;
}

toml::array toml_array(const py::handle& list, const std::string& key, int depth) {
  if (depth > kMaxDictDepth) too_deep(key);
  toml::array array;
  std::size_t i = 0;
  for (const auto& item : list) {
    put_value(item, key + "[" + std::to_string(i++) + "]", depth,
              [&](auto&& v) { array.push_back(std::forward<decltype(v)>(v)); });
  }
  return array;
}

}  // namespace

PyScenario PyScenario::from_text(std::string text, const std::filesystem::path& file, const std::vector<std::string>& set,
                                 std::optional<std::uint64_t> seed) {
  PyScenario s;
  s.text = std::move(text);
  s.file = file;
  s.overrides = overrides_of(set, seed);
  s.parsed = parse_scenario(s.text, s.file, s.overrides);
  return s;
}

PyScenario PyScenario::with(const std::vector<std::string>& set, std::optional<std::uint64_t> seed) const {
  std::vector<std::string> all = overrides.set;
  all.insert(all.end(), set.begin(), set.end());
  return from_text(text, file, all, seed ? seed : overrides.seed);
}

std::optional<std::uint64_t> seed_of(const py::object& seed) {
  if (seed.is_none()) return std::nullopt;
  constexpr std::int64_t kMax = std::numeric_limits<std::int64_t>::max();  // the file's seed range
  const auto refuse = [&] {
    return InputError(fmt::format("seed={}: expected an integer from 0 to {}", py::repr(seed).cast<std::string>(), kMax));
  };
  // An int, or what stands for one (numpy's integers); not a bool, a float or a str.
  if (py::isinstance<py::bool_>(seed) || !py::hasattr(seed, "__index__")) throw refuse();
  const auto value = py::reinterpret_steal<py::object>(PyNumber_Index(seed.ptr()));
  if (!value) throw py::error_already_set();
  const auto below = [&](const py::object& a, const py::object& b) {
    const int less = PyObject_RichCompareBool(a.ptr(), b.ptr(), Py_LT);
    if (less < 0) throw py::error_already_set();
    return less == 1;
  };
  if (below(value, py::int_(0)) || below(py::int_(kMax), value)) throw refuse();
  return value.cast<std::uint64_t>();
}

std::string toml_text(const py::dict& dict) {
  std::ostringstream out;
  out << toml_table(dict, "", 0);
  return out.str() + "\n";
}

FileAndOverrides scenario_file_of(const py::object& scenario, const std::vector<std::string>& set,
                                  const char* function) {
  if (!py::isinstance<PyScenario>(scenario)) {
    FileAndOverrides given{scenario.cast<std::filesystem::path>(), {}};
    given.overrides.set = set;
    return given;
  }
  const auto& s = scenario.cast<const PyScenario&>();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(s.file, ec) || read_scenario_text(s.file) != s.text)
    throw InputError(fmt::format("{}: the scenario '{}' was not read from its file {}; {} reads a scenario file: write "
                                 "scenario.text to a file and give its path",
                                 function, s.parsed.title, s.file.string(), function));
  FileAndOverrides read{s.file, s.overrides};  // its --set and its seed
  read.overrides.set.insert(read.overrides.set.end(), set.begin(), set.end());
  return read;
}

namespace {

// A scenario pickled as what makes it: its text, its file and its overrides, read again when
// unpickled (multiprocessing hands scenarios to its workers so).
py::tuple scenario_state(const PyScenario& s) {
  return py::make_tuple(s.text, s.file.string(), s.overrides.set,
                        s.overrides.seed ? py::cast(*s.overrides.seed) : py::none());
}

PyScenario scenario_from_state(const py::tuple& state) {
  if (state.size() != 4) throw InputError("aggpack.Scenario: a pickled state of 4 items was expected");
  return PyScenario::from_text(state[0].cast<std::string>(), state[1].cast<std::string>(),
                               state[2].cast<std::vector<std::string>>(), seed_of(state[3]));
}

}  // namespace

void bind_scenario(py::module_& m) {
  py::class_<PyScenario>(m, "Scenario", R"doc(A scenario: the container, the particles, the protocol and the outputs of a run.

Made from a file (Scenario.from_file), from TOML text (Scenario.from_toml) or from a dict of
the same keys (Scenario.from_dict); the keys are the scenario file's (README, "Scenario
reference"). `set` takes the CLI's --set assignments ("dynamics.max_time=0.5"), `seed` its
--seed. Bad input raises aggpack.InputError with the CLI's message (the file, the key, what is
wrong and what is expected).)doc")
      .def_static(
          "from_file",
          [](const std::filesystem::path& path, const std::vector<std::string>& set, const py::object& seed) {
            return PyScenario::from_text(read_scenario_text(path), path, set, seed_of(seed));
          },
          py::arg("path"), py::kw_only(), py::arg("set") = std::vector<std::string>{}, py::arg("seed") = py::none(),
          "Reads a scenario file (relative paths in it are taken from its folder).")
      .def_static("from_toml",
                  [](std::string text, const std::filesystem::path& name, const std::vector<std::string>& set,
                     const py::object& seed) { return PyScenario::from_text(std::move(text), name, set, seed_of(seed)); },
                  py::arg("text"), py::kw_only(),
                  py::arg("name") = std::filesystem::path("scenario.toml"), py::arg("set") = std::vector<std::string>{},
                  py::arg("seed") = py::none(),
                  "A scenario from TOML text. `name` is the file it is said to be in messages; relative paths in it "
                  "are taken from the current folder (or from `name`'s folder, if it has one).")
      .def_static(
          "from_dict",
          [](const py::dict& dict, const std::filesystem::path& name, const std::vector<std::string>& set,
             const py::object& seed) { return PyScenario::from_text(toml_text(dict), name, set, seed_of(seed)); },
          py::arg("scenario"), py::kw_only(), py::arg("name") = std::filesystem::path("scenario.toml"),
          py::arg("set") = std::vector<std::string>{}, py::arg("seed") = py::none(),
          "A scenario from a dict of the scenario file's keys (nested dicts for its tables, a list of dicts for "
          "[[protocol]]; None leaves a key out). Equal to the same scenario written as TOML.")
      .def("with_overrides",
           [](const PyScenario& s, const std::vector<std::string>& set, const py::object& seed) {
             return s.with(set, seed_of(seed));
           },
           py::arg("set") = std::vector<std::string>{}, py::kw_only(),
           py::arg("seed") = py::none(),
           "A copy with more --set assignments (after this one's) and, if given, another seed.")
      .def("check",
           [](const PyScenario& s, const std::shared_ptr<PyBed>& bed) {
             py::gil_scoped_release released;
             std::optional<ParticleStore> named;
             check_loaded_scenario(s.parsed, bed ? starting_bed_of(*bed, s.parsed, named) : nullptr);
           },
           py::kw_only(), py::arg("bed") = py::none(),
           "Checks what `aggpack check` checks beyond reading: the particle file (or `bed`, the aggpack.Bed that "
           "aggpack.run(scenario, bed=...) would start from), the grains' templates, the output folder and the "
           "virtual boxes. Raises InputError; returns None when all is well.")
      .def(
          "to_dict",
          [](const PyScenario& s, bool resolved) {
            return to_python(resolved ? aggpack::to_json(s.parsed) : scenario_keys(s.text, s.file, s.overrides));
          },
          py::kw_only(), py::arg("resolved") = false,
          "The scenario's keys as its file gives them, its --set assignments and seed applied: "
          "Scenario.from_dict(s.to_dict(), name=s.file) is the same scenario (`name` anchors its relative paths, as "
          "the file's folder does). With `resolved=True`: the scenario as aggpack read it, every default filled in, "
          "in SI units (summary.json's `scenario`; a record, which from_dict does not read).")
      .def_property_readonly("text", [](const PyScenario& s) { return s.text; }, "The TOML text it was read from.")
      .def_property_readonly("file", [](const PyScenario& s) { return s.file; }, "The file it is, or is said to be.")
      .def_property_readonly("overrides", [](const PyScenario& s) { return s.overrides.set; }, "Its --set assignments.")
      .def_property_readonly("seed", [](const PyScenario& s) { return s.parsed.seed; }, "The random seed of its run.")
      .def_property_readonly("title", [](const PyScenario& s) { return s.parsed.title; })
      .def(py::pickle(&scenario_state, &scenario_from_state))
      .def("__eq__", [](const PyScenario& a, const PyScenario& b) {
        return aggpack::to_json(a.parsed) == aggpack::to_json(b.parsed);
      })
      .def("__repr__", [](const PyScenario& s) {
        return "<aggpack.Scenario '" + s.parsed.title + "' from " + s.file.string() + ", seed " +
               std::to_string(s.parsed.seed) + ">";
      });
  m.def("toml_text", &toml_text, py::arg("scenario"), "The TOML text Scenario.from_dict reads for a dict.");
}

}  // namespace aggpack::python
