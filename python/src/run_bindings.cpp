// aggpack.run, aggpack.resume, aggpack.write_outputs and the Report they return. The GIL is
// released while the library works; SIGINT and SIGTERM stop the run at its next safe point, as
// in the CLI, and raise KeyboardInterrupt with the partial report as its `report`.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <sstream>
#include <string>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/core/stop_request.hpp"
#include "aggpack/core/version.hpp"
#include "aggpack/io/atomic_file.hpp"
#include "aggpack/run/analyze.hpp"
#include "aggpack/run/output_folder.hpp"
#include "aggpack/run/preflight.hpp"
#include "aggpack/run/run.hpp"
#include "bindings.hpp"
#include "python_bed.hpp"
#include "python_scenario.hpp"
#include "run/report_archive.hpp"  // the library's own archive of its reports (checkpoints)

namespace aggpack {
template <class Archive>
void serialize(Archive& ar, Interruption& i) {
  ar(i.signal_number, i.where, i.steps_completed, i.steps_total, i.checkpoint);
}
}  // namespace aggpack

namespace aggpack::python {
namespace {

using Clock = std::chrono::steady_clock;

// What a run gave: its report and, for a run into a folder, the summary.json it wrote there.
struct PyReport {
  std::shared_ptr<const RunReport> report;
  std::optional<nlohmann::json> written_summary;
  std::optional<std::filesystem::path> output_directory;
  double wall_clock_s = 0.0;
  std::optional<std::string> scenario_text;  // what its scenario was read from, when the caller gave it
};

// A Report pickled (multiprocessing hands a worker's back so): its scenario as the text it was
// read from with its overrides, read again when unpickled; every other value of the run's
// report in the library's binary archive (that of checkpoints: this machine's byte order, the
// same aggpack); the sizes drawn again from the scenario's seed, as a resumed run draws them.
constexpr int kReportPickleFormat = 2;  // 2: rodding and jigging

template <class Archive>
void archive_report(Archive& ar, RunReport& r, bool& has_sizes, std::string& libraries) {
  ar(r.particles, r.deposition, raw(r.pours), r.tappings, r.dynamics, r.analyses, r.final, r.deposited, r.snapshots,
     r.snapshot_times, r.frames, r.next_frame_multiple, r.simulated_time, r.lammps_exchanges, raw(r.supports),
     r.series, r.wall_clock_s, r.largest_boundary_overlap, r.largest_pair_overlap, r.input_format,
     r.dynamics_skipped, r.interrupted, r.resumed_from, r.checkpoint_error, r.working_directory, libraries,
     r.grain_shape_component, has_sizes, r.roddings, r.jiggings);
}

// The overrides that make the report's scenario again from its text.
ScenarioOverrides overrides_of(const Scenario& sc) {
  ScenarioOverrides o;
  o.set = sc.overrides;
  o.seed = sc.seed;
  o.output_directory = sc.output.directory;
  return o;
}

py::tuple report_state(const PyReport& r) {
  const RunReport& report = *r.report;
  const Scenario& sc = report.scenario;
  // A run from a file (resume, import_lammps): its text now, if it still makes the same scenario.
  const std::string text = r.scenario_text ? *r.scenario_text : read_scenario_text(sc.file);
  if (aggpack::to_json(parse_scenario(text, sc.file, overrides_of(sc))) != aggpack::to_json(sc))
    throw InputError(fmt::format("aggpack.Report of '{}': its scenario file {} (or a file it names) has changed since "
                                 "the run, so the report cannot be pickled with the scenario it ran",
                                 sc.title, sc.file.string()));
  bool has_sizes = report.sizes.has_value();
  std::string libraries = report.grain_libraries.dump();
  std::ostringstream bytes;
  {
    cereal::BinaryOutputArchive ar(bytes);
    archive_report(ar, const_cast<RunReport&>(report), has_sizes, libraries);
  }
  return py::make_tuple(kReportPickleFormat, std::string(kVersion), text, sc.file.string(), sc.overrides, sc.seed,
                        sc.output.directory.string(), py::bytes(bytes.str()),
                        r.written_summary ? py::cast(r.written_summary->dump()) : py::none(),
                        r.output_directory ? py::cast(r.output_directory->string()) : py::none(), r.wall_clock_s);
}

PyReport report_from_state(const py::tuple& state) {
  if (state.size() != 11 || state[0].cast<int>() != kReportPickleFormat ||
      state[1].cast<std::string>() != kVersion)
    throw InputError(fmt::format("aggpack.Report: not a report pickled by this aggpack ({}): pickle a report where "
                                 "it is unpickled, with the same aggpack",
                                 kVersion));
  ScenarioOverrides overrides;
  overrides.set = state[4].cast<std::vector<std::string>>();
  overrides.seed = state[5].cast<std::uint64_t>();
  overrides.output_directory = state[6].cast<std::string>();
  const std::string bytes = state[7].cast<std::string>();
  PyReport out;
  out.scenario_text = state[2].cast<std::string>();
  out.written_summary = state[8].is_none() ? std::nullopt
                                           : std::optional(nlohmann::json::parse(state[8].cast<std::string>()));
  out.output_directory = state[9].is_none() ? std::nullopt
                                            : std::optional(std::filesystem::path(state[9].cast<std::string>()));
  out.wall_clock_s = state[10].cast<double>();
  const std::filesystem::path file = state[3].cast<std::string>();
  py::gil_scoped_release released;
  auto report = std::make_shared<RunReport>();
  report->scenario = parse_scenario(*out.scenario_text, file, overrides);
  bool has_sizes = false;
  std::string libraries;
  try {
    CheckedInputArchive ar(bytes);
    archive_report(ar, *report, has_sizes, libraries);
    if (ar.left() > 0) throw cereal::Exception(std::to_string(ar.left()) + " bytes after the report");
    report->grain_libraries = nlohmann::json::parse(libraries);
  } catch (const std::exception& e) {
    throw InputError(fmt::format("aggpack.Report: the pickled report of '{}' is damaged ({})",
                                 report->scenario.title, e.what()));
  }
  if (has_sizes) report->sizes = generate_sizes(report->scenario.particles, report->scenario.seed);
  out.report = std::move(report);
  return out;
}

std::shared_ptr<PyBed> bed_of(const std::shared_ptr<const RunReport>& owner, const ParticleStore& store) {
  return std::make_shared<PyBed>(PyBed{std::shared_ptr<const ParticleStore>(owner, &store), "the run's bed", "", {}});
}

// The one piece of global state, as in the CLI: a signal handler can reach nothing else. The
// run that SIGINT and SIGTERM stop: the one the main thread is in (a run from another thread
// is not stopped by them, as Python delivers them to the main thread only).
std::atomic<StopRequest*> g_signalled_run{nullptr};  // NOLINT(cppcoreguidelines-avoid-non-const-global-variables)
extern "C" void request_stop(int signal_number) {
  if (StopRequest* stop = g_signalled_run.load()) stop->request(signal_number);
}

bool on_main_thread() {
  const py::module_ threading = py::module_::import("threading");
  return threading.attr("current_thread")().is(threading.attr("main_thread")());
}

// While it lives, on the main thread: SIGINT and SIGTERM ask `stop`'s run to stop at its next
// safe point; then the handlers that were there (Python's, with their flags) are back. Made
// with the GIL held.
class SignalsStopTheRun {
 public:
  explicit SignalsStopTheRun(StopRequest& stop) : main_thread_(on_main_thread()) {
    if (!main_thread_) return;
    g_signalled_run.store(&stop);
    struct sigaction ours {};
    ours.sa_handler = request_stop;
    sigemptyset(&ours.sa_mask);
    sigaction(SIGINT, &ours, &old_int_);
    sigaction(SIGTERM, &ours, &old_term_);
  }
  ~SignalsStopTheRun() {
    if (!main_thread_) return;
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
    g_signalled_run.store(nullptr);
  }
  SignalsStopTheRun(const SignalsStopTheRun&) = delete;
  SignalsStopTheRun& operator=(const SignalsStopTheRun&) = delete;

 private:
  bool main_thread_;
  struct sigaction old_int_ {}, old_term_ {};
};

// The report, or for an interrupted run KeyboardInterrupt with the report of what it did (and,
// for a run into a folder, where its checkpoint is: aggpack.resume(folder) continues it).
py::object report_or_interrupt(PyReport result) {
  const auto& stop = result.report->interrupted;
  py::object report = py::cast(std::move(result));
  if (!stop) return report;
  std::string message = "aggpack: interrupted by signal " + std::to_string(stop->signal_number) + " " + stop->where +
                        " (" + std::to_string(stop->steps_completed) + " of " + std::to_string(stop->steps_total) +
                        " steps done)";
  if (stop->checkpoint && !report.attr("output_directory").is_none())
    message += "; continue with aggpack.resume(\"" + py::str(report.attr("output_directory")).cast<std::string>() +
               "\")";
  py::object error = py::module_::import("builtins").attr("KeyboardInterrupt")(message);
  error.attr("report") = report;
  PyErr_SetObject(PyExc_KeyboardInterrupt, error.ptr());
  throw py::error_already_set();
}

// The library's progress handed to a Python callable (called with the GIL taken, a few times a
// second at most) as a dict; none: silent. An exception it raises ends the run with it.
Progress progress_to(const py::object& callback) {
  if (callback.is_none()) return Progress{};
  if (!PyCallable_Check(callback.ptr())) throw py::type_error("progress: expected a callable or None");
  return Progress([callback](const ProgressUpdate& u) {
    py::gil_scoped_acquire held;
    py::dict d;
    d["run"] = u.run;
    d["stage"] = u.stage;
    d["fields"] = u.fields;
    d["done"] = u.done;
    d["seconds_left"] = u.seconds_left;
    d["seconds_left_is_bound"] = u.seconds_left_is_bound;
    callback(d);
  });
}

RunOptions options_of(int threads, const std::optional<std::string>& stop_after, bool overwrite,
                      const StopRequest& stop) {
  RunOptions options;
  options.threads = threads;
  options.stop_after = stop_after;
  options.quiet = true;
  options.stop = &stop;
  options.overwrite = overwrite;
  return options;
}

PyReport from_result(RunResult&& r) {
  PyReport out;
  out.report = std::make_shared<const RunReport>(std::move(r.report));
  out.written_summary = std::move(r.summary);
  out.output_directory = r.output_directory;
  out.wall_clock_s = r.wall_clock_s;
  return out;
}

// The library's work of one run, with its progress handed to `progress_callback`, SIGINT and
// SIGTERM stopping it, and the GIL released; its report, or KeyboardInterrupt.
py::object run_stoppably(const py::object& progress_callback,
                         const std::function<PyReport(Progress&, const StopRequest&)>& work) {
  Progress progress = progress_to(progress_callback);
  StopRequest stop;
  const SignalsStopTheRun signals(stop);
  PyReport result;
  {
    py::gil_scoped_release released;
    result = work(progress, stop);
  }
  return report_or_interrupt(std::move(result));
}

py::object run_scenario_from_python(const PyScenario& scenario, const std::optional<std::filesystem::path>& out,
                                    const std::shared_ptr<PyBed>& bed, int threads,
                                    const std::optional<std::string>& stop_after, bool overwrite,
                                    const py::object& progress_callback) {
  check_thread_count(threads, OptionStyle::Keyword);  // named as the caller gave it, not as --threads
  // A run into a folder can be resumed from its scenario file alone: a bed held in memory
  // would not be there to resume from.
  if (bed && out)
    throw InputError(fmt::format("bed= with out={}: a run from a bed in memory runs in memory (its checkpoints "
                                 "could not be resumed without the bed); run it without out=, then "
                                 "aggpack.write_outputs(report, folder)",
                                 out->string()));
  // A file's material column names each sphere's material: the scenario's of that name.
  std::optional<ParticleStore> named;
  const ParticleStore* starting_bed = bed ? starting_bed_of(*bed, scenario.parsed, named) : nullptr;
  return run_stoppably(progress_callback, [&](Progress& progress, const StopRequest& stop) {
    if (out) {
      RunOptions options = options_of(threads, stop_after, overwrite, stop);
      options.progress = &progress;
      options.overrides = scenario.overrides;
      options.overrides.output_directory = *out;
      std::ostringstream log;
      PyReport result = from_result(run_scenario_text(scenario.text, scenario.file, options, log));
      result.scenario_text = scenario.text;
      return result;
    }
    const auto t0 = Clock::now();
    RunControls controls;
    controls.threads = threads;
    controls.stop_after = stop_after;
    controls.stop = &stop;
    controls.starting_bed = starting_bed;
    RunReport report = run(scenario.parsed, controls, progress);
    report.working_directory = std::filesystem::current_path().string();  // where its relative paths lie
    PyReport result;
    result.report = std::make_shared<const RunReport>(std::move(report));
    result.wall_clock_s = std::chrono::duration<double>(Clock::now() - t0).count();
    result.scenario_text = scenario.text;
    return result;
  });
}

// summary.json's dict: the one written, or the report's own.
nlohmann::json summary_of(const PyReport& r) {
  return r.written_summary ? *r.written_summary : r.report->summary_json(0.0, r.wall_clock_s);
}

py::object interruption_of(const PyReport& r) {
  if (!r.report->interrupted) return py::none();
  const Interruption& i = *r.report->interrupted;
  py::dict d;
  d["signal"] = i.signal_number;
  d["where"] = i.where;
  d["steps_completed"] = i.steps_completed;
  d["steps_total"] = i.steps_total;
  d["checkpoint"] = i.checkpoint;
  return d;
}

void bind_report(py::module_& m) {
  py::class_<PyReport>(m, "Report", R"doc(What a run produced: its densities, beds, notes and summary.

`summary()` is the dict summary.json holds (for a run into a folder, the very one written
there). The beds (`bed`, `deposited`, `snapshots`) are aggpack.Bed objects whose arrays are
views into this report's data. A Report pickles (for multiprocessing): its scenario is read again
from the text it ran, the rest kept as it was.)doc")
      .def("summary", [](const PyReport& r) { return to_python(summary_of(r)); },
           "summary.json's dict (README, \"Output files\").")
      .def_property_readonly("density", [](const PyReport& r) { return r.report->final_density(); },
                             "The final bed's mean virtual-box density (solid fraction); NaN for an interrupted run, "
                             "which made no final analysis.")
      .def_property_readonly("analysis",
                             [](const PyReport& r) -> py::object {
                               if (r.report->interrupted) return py::none();  // no final analysis was made
                               return to_python(to_json(r.report->final));
                             },
                             "The final analysis as summary.json gives it: the density of each virtual box and their "
                             "mean, the bed's floor and surface, the coordination, the profiles; None for an "
                             "interrupted run.")
      .def_property_readonly("density_after_deposition",
                             [](const PyReport& r) { return r.report->density_after_deposition(); },
                             "The mean density after deposition (NaN when there was none).")
      .def_property_readonly("density_after_dynamics",
                             [](const PyReport& r) { return r.report->density_after_dynamics(); },
                             "The mean density after the last DEM stage (NaN when no DEM ran, or the run was "
                             "interrupted before its final analysis).")
      .def_property_readonly("notes", [](const PyReport& r) { return r.report->modelling_notes(); },
                             "Every modelling choice the results depend on, in words (summary.json's modelling_notes).")
      .def_property_readonly("predictions", [](const PyReport& r) { return to_python(to_json(r.report->predictions())); },
                             "The analytic models on the run's sizes (summary.json's predictions).")
      .def_property_readonly("wall_clock", [](const PyReport& r) { return to_python(summary_of(r)["wall_clock_s"]); },
                             "Seconds of wall clock per stage (deposition, dynamics, analysis, ...) and in all "
                             "(`total`): summary.json's wall_clock_s.")
      .def_property_readonly("simulated_time", [](const PyReport& r) { return r.report->simulated_time; },
                             "Seconds of simulated time, every DEM step's.")
      .def_property_readonly("interrupted", &interruption_of, "None, or what an interrupted run had done (a dict).")
      .def_property_readonly("output_directory", [](const PyReport& r) { return r.output_directory; },
                             "The folder a run into a folder wrote; None for a run in memory.")
      .def_property_readonly("bed", [](const PyReport& r) { return bed_of(r.report, r.report->particles); },
                             "The final bed (aggpack.Bed).")
      .def_property_readonly("deposited",
                             [](const PyReport& r) -> py::object {
                               if (!r.report->deposited) return py::none();
                               return py::cast(bed_of(r.report, *r.report->deposited));
                             },
                             "The bed after deposition, when a DEM then moved it; else None.")
      .def_property_readonly("snapshots",
                             [](const PyReport& r) {
                               py::dict d;
                               for (const auto& [name, bed] : r.report->snapshots) d[py::str(name)] = bed_of(r.report, bed);
                               return d;
                             },
                             "The beds of the snapshot steps, by name.")
      .def(py::pickle([](const PyReport& r) { return report_state(r); },
                      [](const py::tuple& state) { return report_from_state(state); }))
      .def("__repr__", [](const PyReport& r) {
        const std::string density = r.report->interrupted ? std::string("density not measured (interrupted)")
                                                          : fmt::format("density {:.4f}", r.report->final_density());
        return fmt::format("<aggpack.Report '{}': {}, {} spheres>", r.report->scenario.title, density,
                           r.report->particles.size());
      });
}

}  // namespace

py::object report_of(RunResult&& result) { return py::cast(from_result(std::move(result))); }

void bind_run(py::module_& m) {
  bind_report(m);
  m.def("run", &run_scenario_from_python, py::arg("scenario"), py::kw_only(), py::arg("out") = py::none(),
        py::arg("bed") = py::none(), py::arg("threads") = 0, py::arg("stop_after") = py::none(), py::arg("overwrite") = false,
        py::arg("progress") = py::none(),
        R"doc(Runs a scenario and returns its aggpack.Report.

With `out`, runs as `aggpack run --out OUT` does: the outputs and checkpoints in that folder
(refused if it holds files no aggpack run wrote, unless `overwrite`), the report's summary()
the summary.json written. Without, runs in memory and writes nothing (write_outputs writes the
report later). `bed`: an aggpack.Bed to start from, for a scenario whose [particles] has
from = "-" (read_bed's, Bed.from_arrays', another run's): checked as a particle file would be,
each sphere of its own material (an index of the scenario's materials; a bed all of material 0
takes particles.material); a run from a bed runs in memory. `threads`: OpenMP threads (0: all cores); the results are the same bytes for
any count. `stop_after`: end after a stage ("deposition"), as --stop-after. Ctrl-C (SIGINT) or
SIGTERM stops the run at its next safe point and raises KeyboardInterrupt, whose `report` is
what the run had done; a run into a folder leaves its checkpoint there for aggpack.resume.
`progress`: a callable given a dict a few times a second at most (what the CLI's progress line
shows: `run`, `stage`, `fields`, `done` in [0, 1], `seconds_left`, `seconds_left_is_bound`);
an exception it raises ends the run with that exception.)doc");
  m.def(
      "resume",
      [](const std::filesystem::path& folder, int threads, const py::object& progress_callback) {
        check_thread_count(threads, OptionStyle::Keyword);
        return run_stoppably(progress_callback, [&](Progress& progress, const StopRequest& stop) {
          RunOptions options = options_of(threads, std::nullopt, false, stop);
          options.progress = &progress;
          std::ostringstream log;
          return from_result(resume_run(folder, options, log));
        });
      },
      py::arg("folder"), py::kw_only(), py::arg("threads") = 0, py::arg("progress") = py::none(),
      "Continues the run whose checkpoint is in `folder`, as `aggpack resume` does: its outputs are those the run "
      "would have written uninterrupted, bit for bit.");
  m.def(
      "write_outputs",
      [](const PyReport& r, const std::filesystem::path& folder, bool overwrite) {
        nlohmann::json summary;
        {
          py::gil_scoped_release released;
          check_output_directory(folder, false);
          check_output_folder_contents(folder, overwrite);
          (void)remove_earlier_run(folder, {});  // as aggpack run: the folder never mixes two runs' files
          summary = write_outputs(*r.report, folder, r.wall_clock_s);  // summary.json records `folder`
        }
        return to_python(summary);
      },
      py::arg("report"), py::arg("folder"), py::kw_only(), py::arg("overwrite") = false,
      "Writes a report's outputs into `folder` as `aggpack run` does (particles.csv, summary.json, ...; README, "
      "\"Output files\") and returns the summary written. A folder holding files no aggpack run wrote is refused "
      "unless `overwrite`.");
  m.attr("__version__") = kVersion;
}

}  // namespace aggpack::python
