"""rodend from Python: run a case or a study, read a study's results as pandas and xarray.

    import rodend
    case = rodend.run_case("gravity-drop", {"contact.clearance": 2e-4},
                           time={"end": 0.1, "sample_interval": 1e-4})
    case.signals["eccentricity"]          # numpy array, one value per sample
    case.metrics["first_impact_peak_force"], case.metric_units["first_impact_peak_force"]

    rc, folder = rodend.run_study("studies/default.json", threads=2)
    res = rodend.open_results(folder)
    res.summary                           # pandas.DataFrame, one row per case (summary.csv)
    res.histories                         # xarray.Dataset: dims = the grid axes and time

Everything runs through the same C++ loader and runner as the `rodend` command: a bad input
raises rodend.InputError (a ValueError) with the command line's message, naming the file, the
key path and what was expected. Nothing is written to disk unless asked (`run_case(...,
write=path)`; `run_study` writes its results folder as `rodend run` does).

The compiled part (rodend._rodend) is built by `bash scripts/main.sh` (or setup.sh) into
<repo>/build/python/; this package finds it there, or in $RODEND_BUILD_DIR/python (a build
directory of another name), or next to itself.
"""
import glob
import importlib.util
import json
import numbers
import os
import sys

__all__ = ["InputError", "run_case", "run_study", "load_study", "open_results", "Case",
           "Results", "schema", "scenes", "parameters", "signal_catalogue"]


def _load_extension():
    here = os.path.dirname(os.path.abspath(__file__))
    repo = os.path.dirname(os.path.dirname(here))
    places = []
    if os.environ.get("RODEND_BUILD_DIR"):
        b = os.environ["RODEND_BUILD_DIR"]
        places.append(os.path.join(b if os.path.isabs(b) else os.path.join(repo, b), "python"))
    places += [here, os.path.join(repo, "build", "python")]
    for place in places:
        for path in sorted(glob.glob(os.path.join(place, "_rodend*.so"))):
            spec = importlib.util.spec_from_file_location("rodend._rodend", path)
            module = importlib.util.module_from_spec(spec)
            try:
                spec.loader.exec_module(module)
            except ImportError:
                continue  # built for another Python
            sys.modules["rodend._rodend"] = module
            return module
    raise ImportError(
        "rodend: the compiled module _rodend was not found in " + ", ".join(places) +
        ": build it with `bash scripts/setup.sh` (needs pybind11-dev), or set RODEND_BUILD_DIR "
        "to the build directory")


_ext = _load_extension()
InputError = _ext.InputError
__version__ = _ext.__version__
SCHEMA_VERSION = _ext.schema_version


def schema():
    """The JSON Schema (draft 2020-12) of study files, as a dict (`rodend schema`)."""
    return json.loads(_ext.schema())


def scenes():
    """The scene names (`rodend scenes`)."""
    return list(_ext.scenes())


def parameters(scene):
    """A scene's default parameters: {dotted path: {value, unit, source, note}}."""
    return _ext.parameters(scene)


def signal_catalogue():
    """[(name, unit, width, description)] of every signal (`rodend signals`)."""
    return list(_ext.signal_catalogue())


class Case:
    """What run_case returns: the record, histories and metrics of one case.

    signals: {name: numpy array (samples,) or (samples, width)}; units, long_names: {name: str}
    metrics: {name: float} (NaN when not applicable); metric_units: {name: str}
    status, message, t_reached_s, steps_accepted, rhs_calls, ... : the summary's columns
    parameters: every resolved parameter {path: {value, unit, source, ...}}
    arrays: {"group/name": {values, units, long_name, dims}} (wear maps, wear evolution)
    """

    def __init__(self, d):
        self.__dict__.update(d)

    def to_xarray(self):
        """The histories as an xarray.Dataset over time (and component<w> for vectors)."""
        import xarray as xr
        t = self.signals.get("time")
        data = {}
        for name, v in self.signals.items():
            if name == "time":
                continue
            dims = ("time",) if v.ndim == 1 else ("time", f"component{v.shape[1]}")
            data[name] = (dims, v, {"units": self.units[name], "long_name": self.long_names[name]})
        coords = {}
        if t is not None:
            coords["time"] = ("time", t, {"units": "s", "long_name": self.long_names["time"]})
        return xr.Dataset(data, coords=coords,
                          attrs={"case_id": self.case_id, "status": self.status})

    def __repr__(self):
        return (f"<rodend.Case {self.case_id} {self.status}, {len(self.signals)} signals, "
                f"t_reached {self.t_reached_s} s>")


def run_case(scene, parameters=None, *, time=None, integrator=None, signals=None, health=None,
             metrics=None, write=None):
    """Runs one case in memory and returns a Case (histories as numpy arrays, metrics as a
    dict). Nothing touches the disk unless `write` names a case file to write (.h5, the same
    file `rodend run` writes).

    scene: a scene name (rodend.scenes()); parameters: overrides of its defaults, by dotted key
    path or nested dicts; time: {"end": s, "sample_interval": s} (default: end 0.1 s sampled
    every 1e-4 s); integrator, signals, health, metrics: as the study keys of the same names.
    Raises InputError (a ValueError) with the command line's message for a bad input.
    """
    doc = {"name": "run_case", "scene": scene,
           "time": time if time is not None else {"end": 0.1, "sample_interval": 1e-4}}
    for key, value in (("parameters", parameters), ("integrator", integrator),
                       ("signals", signals), ("health", health), ("metrics", metrics)):
        if value is not None:
            doc[key] = value
    text = _dumps(doc, "run_case()", "")
    return Case(_ext.run_case(text, "run_case()", "" if write is None else os.fspath(write)))


def load_study(path, *, results_root="results", set=None):
    """A study as `rodend run --dry-run` resolves it: name, scene, output_dir, axis_keys,
    source (the document with the overrides), cases [{case_id, case_index, coordinates}]."""
    return _ext.load_study(os.fspath(path), os.fspath(results_root), _overrides(set))


def run_study(path, *, threads=1, results_root="results", set=None, rerun_failed=False,
              progress=False):
    """Runs a study as `rodend run` does (resume included) and returns (exit code, results
    folder): 0 when every case is ok, 1 when one failed. `set` is {key.path: value} or a list
    of "key.path=value" strings, as `--set`. Raises InputError for a bad study."""
    # the command line's checks: --threads is an integer from 1 to 4096 (the range is checked
    # by the compiled part, with the command line's message)
    if isinstance(threads, bool) or not isinstance(threads, numbers.Integral):
        raise TypeError(f"run_study(): threads: expected an integer from 1 to 4096, got "
                        f"{type(threads).__name__} {threads!r}")
    for name, flag in (("rerun_failed", rerun_failed), ("progress", progress)):
        if not isinstance(flag, bool):
            raise TypeError(f"run_study(): {name}: expected True or False, got "
                            f"{type(flag).__name__} {flag!r}")
    rc, folder = _ext.run_study(os.fspath(path), int(threads), os.fspath(results_root),
                                _overrides(set), rerun_failed, progress)
    return rc, folder


def _dumps(value, origin, key):
    """JSON text of a Python value; a value nested too deep for the json module (which
    recurses) raises InputError naming the key, as the loader does for deep study files."""
    try:
        return json.dumps(value, allow_nan=False)
    except RecursionError:
        raise InputError(f"{origin}: {key or 'the document'}: nested too deep (the loader "
                         f"takes at most 64 levels); expected a value a study can hold") from None


def _overrides(s):
    if s is None:
        return []
    if isinstance(s, dict):
        return [f"{k}={_dumps(v, 'set=', k)}" for k, v in s.items()]
    return [str(x) for x in s]


def open_results(folder, signals=None):
    """The results of a study folder (results/<study>, as `rodend run` wrote it): a Results with
    .summary (pandas.DataFrame) and .histories (xarray.Dataset over the grid axes and time,
    read on first use; `signals` limits which)."""
    from . import results
    return results.Results(folder, signals=signals)


def __getattr__(name):
    if name == "Results":
        from .results import Results
        return Results
    raise AttributeError(name)
