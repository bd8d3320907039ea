// rodend._rodend: the C++ side of the Python module (python/rodend/__init__.py is the API).
// Everything goes through the same loader, runner and results code as the command line, so a
// bad input raises rodend.InputError with the CLI's message (file, key path, what was
// expected), and results are the same bits.
//
// Threads: the GIL is released around every call into rodend's C++ (loading, running,
// writing), which never calls back into Python; what pybind11 initialises lazily under a C++
// static guard while holding the GIL (numpy's API table, which imports numpy) is initialised at
// import instead, so two threads making their first calls at once cannot deadlock (one in the
// guard holding the GIL, the other inside it waiting for the GIL).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <filesystem>
#include <memory>
#include <mutex>
#include <sstream>

#include "core/scene.hpp"
#include "sweep/case_observer.hpp"
#include "sweep/results.hpp"
#include "sweep/runner.hpp"
#include "sweep/schema.hpp"
#include "sweep/stop_signals.hpp"
#include "sweep/study.hpp"

namespace py = pybind11;
using namespace rodend;

namespace {

/// A std::vector<double> handed to numpy without a copy (the capsule owns it).
py::array_t<double> to_numpy(std::vector<double>&& v, std::vector<py::ssize_t> shape) {
  auto* owned = new std::vector<double>(std::move(v));
  py::capsule free_when_done(owned, [](void* p) { delete static_cast<std::vector<double>*>(p); });
  return py::array_t<double>(shape, owned->data(), free_when_done);
}

/// Python objects from JSON (via the json module: exact, and nothing hand-converted).
py::object from_json(const Json& j) {
  return py::module_::import("json").attr("loads")(j.dump());
}

/// One field of the case record as a Python value (sweep/case_record.def): str, int, float;
/// json and features fields as their stored text (as in the case file).
py::object record_value(const record_text& v) {
  return py::str(v);
}
py::object record_value(record_integer v) {
  return py::int_(v);
}
py::object record_value(record_real v) {
  return py::float_(v);
}
template <class T>
py::object record_value(const T& v) {
  return py::str(record_field_text(v));
}

py::dict record_dict(const CaseRecord& r) {
  py::dict d;
  for_each_record_field(r, [&](const RecordFieldSpec& f, const auto& v) {
    d[py::str(std::string(f.name))] = record_value(v);
  });
  py::dict metrics, units;
  const auto cat = metric_catalogue();
  for (std::size_t i = 0; i < cat.size() && i < r.metrics.size(); ++i) {
    metrics[py::str(std::string(cat[i].name))] = r.metrics[i];
    units[py::str(std::string(cat[i].name))] = std::string(cat[i].unit);
  }
  d["metrics"] = metrics;
  d["metric_units"] = units;
  return d;
}

/// The checks of run_case's `write` path, before anything runs: no NUL byte (the C library would
/// cut the name there), and nothing under that name but a case file rodend wrote (its checksum
/// holds): never a device, a directory, a link or a file of someone else's. The file itself is
/// written as every results file (a fresh temporary file, then a rename).
void check_write_path(const std::string& write, const std::string& origin) {
  if (write.find('\0') != std::string::npos)
    throw InputError("write", "the path contains a NUL byte; expected a file name", origin);
  const std::filesystem::path path(write);
  std::error_code ec;
  const auto st = std::filesystem::symlink_status(path, ec);
  if (st.type() == std::filesystem::file_type::not_found) return;
  if (ec) throw InputError("write", write + ": " + ec.message(), origin);
  if (st.type() != std::filesystem::file_type::regular)
    throw InputError("write",
                     write +
                         " exists and is not a regular file (a device, a directory or a "
                         "link); expected a new file or a case file rodend wrote",
                     origin);
  bool ours = false;
  try {
    ours = verify_case_file(path);
  } catch (const std::exception&) {
    ours = false;
  }
  if (!ours)
    throw InputError("write",
                     write +
                         " exists and is not a case file rodend wrote; rodend never "
                         "overwrites files it did not create: expected a new file name",
                     origin);
}

/// The histories of a case run, into run_case's dictionary: the signals as numpy arrays (no
/// copy) with their units and long names, and the other arrays by "group/name".
void add_histories(py::dict& out, History& h) {
  py::dict signals, units, names;
  for (std::size_t i = 0; i < h.signals.size(); ++i) {
    const SignalSpec& s = signal_spec(h.signals[i]);
    std::vector<py::ssize_t> shape{static_cast<py::ssize_t>(h.samples)};
    if (s.width > 1) shape.push_back(s.width);
    const py::str name(std::string(s.name));
    signals[name] = to_numpy(std::move(h.values[i]), shape);
    units[name] = std::string(s.unit);
    names[name] = std::string(s.description);
  }
  py::dict arrays;
  for (CaseArray& a : h.arrays) {
    std::vector<py::ssize_t> shape(a.dims.begin(), a.dims.end());
    py::dict entry;
    entry["values"] = to_numpy(std::move(a.values), shape);
    entry["units"] = a.unit;
    entry["long_name"] = a.description;
    entry["dims"] = a.dim_names;
    arrays[py::str(a.group + "/" + a.name)] = entry;
  }
  out["signals"] = signals;
  out["units"] = units;
  out["long_names"] = names;
  out["arrays"] = arrays;
}

/// Runs the one case of a study document; histories as numpy arrays. Writes its case file to
/// `write` when given (the same file `rodend run` writes).
py::dict py_run_case(const std::string& doc_text, const std::string& origin,
                     const std::string& write) {
  History h;
  CaseRecord rec;
  Json parameters, canonical;
  bool interrupted = false;
  {
    py::gil_scoped_release release;  // C++ only: loading, running, writing
    Json doc;
    try {
      doc = Json::parse(doc_text);
    } catch (const Json::exception& e) {
      throw InputError("", std::string("not JSON: ") + e.what(), origin);
    }
    const Study study = parse_study(doc, origin);
    if (study.cases.size() != 1)
      throw InputError("grid",
                       "run_case runs one case; this has " + std::to_string(study.cases.size()) +
                           " (use run_study for a grid)",
                       origin);
    const CaseSpec& spec = study.cases.front();
    if (!write.empty()) check_write_path(write, origin);
    try {
      // SIGINT while the case runs with the interpreter lock released (Python's own handler
      // would only set a flag that nothing reads until the case ends): the case stops at its
      // next sample and run_case raises KeyboardInterrupt
      const StopSignalScope interrupt(StopSignalScope::Kind::one_case);
      rec = rodend::run_case(spec, h);
    } catch (const CaseInterrupted&) {
      interrupted = true;  // nothing of the case is kept, nothing written
    }
    if (!interrupted && !write.empty()) write_case_file(write, spec, rec, h, provenance(study));
    parameters = spec.parameters.leaves();
    canonical = spec.canonical();
  }
  if (interrupted) {
    PyErr_SetString(PyExc_KeyboardInterrupt, "run_case interrupted: nothing was written");
    throw py::error_already_set();
  }
  py::dict out = record_dict(rec);
  add_histories(out, h);
  out["parameters"] = from_json(parameters);
  out["case"] = from_json(canonical);
  return out;
}

/// Loads a study (with --set overrides) as the CLI does: what it would run, where.
py::dict py_load_study(const std::string& path, const std::string& results_root,
                       const std::vector<std::string>& overrides) {
  const Study s = [&] {
    py::gil_scoped_release release;
    return load_study(path, results_root, overrides);
  }();
  py::dict d;
  d["name"] = s.name;
  d["scene"] = s.scene;
  d["output_dir"] = s.output_dir.string();
  d["axis_keys"] = s.axis_keys;
  d["source"] = from_json(s.source);
  // the sampled design as design.json records it (None without one)
  d["design"] = s.design ? py::object(from_json(s.design->to_json(s.design_units))) : py::none();
  py::list cases;
  for (const CaseSpec& c : s.cases) {
    py::dict e;
    e["case_id"] = c.id;
    e["case_index"] = c.index;
    e["coordinates"] = from_json(c.coordinates);
    cases.append(e);
  }
  d["cases"] = cases;
  return d;
}

/// A run's messages and progress handed to Python callables (RunEvents), called with the
/// interpreter lock taken, from the worker threads too. The first exception a callable raises
/// stops the calls; run_study raises it when the run has ended.
class PyEvents {
 public:
  PyEvents(py::object message, py::object progress)
      : message_(std::move(message)), progress_(std::move(progress)) {}

  RunEvents events() {
    RunEvents e;
    if (!message_.is_none()) e.message = [this](const std::string& text) { call(message_, text); };
    if (!progress_.is_none())
      e.progress = [this](long done, long total, long failed, double elapsed, double eta) {
        call(progress_, done, total, failed, elapsed, eta);
      };
    return e;
  }
  /// After the run, with the lock held: the callable's exception, if one raised.
  void raise_if_failed() {
    if (error_) throw *error_;
  }

 private:
  template <class... Args>
  void call(const py::object& f, Args... args) {
    const py::gil_scoped_acquire gil;
    if (error_) return;
    try {
      f(args...);
    } catch (py::error_already_set& e) {
      error_ = std::make_unique<py::error_already_set>(std::move(e));
    }
  }
  py::object message_, progress_;
  std::unique_ptr<py::error_already_set> error_;  // guarded by the interpreter lock
};

/// Runs a study as `rodend run` does (resume, results files); returns (exit code, results dir).
/// on_message(text) and on_progress(done, total, failed, elapsed_s, eta_s): None for stderr.
py::tuple py_run_study(const std::string& path, int threads, const std::string& results_root,
                       const std::vector<std::string>& overrides, bool rerun_failed, bool progress,
                       py::object on_message, py::object on_progress) {
  // as --threads (CLI::Range(1, 4096)): libgomp crashes on a team of 100,000
  if (threads < 1 || threads > 4096)
    throw InputError(
        "threads",
        "expected an integer from 1 to 4096 (as --threads), got " + std::to_string(threads), path);
  PyEvents callbacks(std::move(on_message), std::move(on_progress));
  RunOptions opt;
  opt.threads = threads;
  opt.rerun_failed = rerun_failed;
  opt.progress = progress;
  opt.overrides = overrides;
  opt.events = callbacks.events();
  int rc = 0;
  std::string folder;
  {
    py::gil_scoped_release release;
    const Study study = load_study(path, results_root, overrides);
    folder = study.output_dir.string();
    rc = rodend::run_study(study, opt);
  }
  callbacks.raise_if_failed();
  return py::make_tuple(rc, folder);
}

}  // namespace

PYBIND11_MODULE(_rodend, m) {
  m.doc() = "rodend C++ core (use the rodend package)";
  static py::exception<InputError> input_error(m, "InputError", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      input_error(e.what());
    }
  });
  // numpy's API table (pybind11 fills it on first use, under a static guard, importing numpy)
  // and rodend's catalogues: initialised now, once, under the import lock
  (void)py::array_t<double>(0);
  (void)scene_catalogue();
  (void)metric_catalogue();
  (void)signal_catalogue();
  m.attr("__version__") = RODEND_VERSION;
  m.attr("git_revision") = RODEND_GIT_REVISION;
  m.attr("schema_version") = kResultsSchemaVersion;
  m.def("run_case", &py_run_case, py::arg("doc"), py::arg("origin"), py::arg("write") = "");
  m.def("load_study", &py_load_study, py::arg("path"), py::arg("results_root") = "results",
        py::arg("overrides") = std::vector<std::string>{});
  m.def("run_study", &py_run_study, py::arg("path"), py::arg("threads"), py::arg("results_root"),
        py::arg("overrides"), py::arg("rerun_failed"), py::arg("progress"),
        py::arg("on_message") = py::none(), py::arg("on_progress") = py::none());
  m.def("schema", [] { return study_schema().dump(); });
  m.def("scenes", [] {
    std::vector<std::string> names;
    for (const auto& s : scene_catalogue()) names.emplace_back(s.name);
    return names;
  });
  m.def("parameters", [](const std::string& scene) {
    return from_json(ParameterSet::defaults_for(scene).leaves());
  });
  m.def("signal_catalogue", [] {
    py::list out;
    for (const auto& s : signal_catalogue())
      out.append(py::make_tuple(std::string(s.name), std::string(s.unit), s.width,
                                std::string(s.description)));
    return out;
  });
}
