"""Running from Python: one case in memory (run_case), a study as `rodend run` does
(run_study), a study as `rodend run --dry-run` resolves it (load_study), and the catalogues
(schema, scenes, parameters, signal_catalogue). Everything goes through the compiled module
(rodend/extension.py), the same C++ loader and runner as the `rodend` command.
"""
import errno
import json
import numbers
import os
import signal
import sys
import tempfile

from . import naming
from .extension import get as _extension

def schema():
    """The JSON Schema (draft 2020-12) of study files, as a dict (`rodend schema`)."""
    return json.loads(_extension().schema())


def scenes():
    """The scene names (`rodend scenes`)."""
    return list(_extension().scenes())


def parameters(scene):
    """A scene's default parameters: {dotted path: {value, unit, source, note}}. An unknown
    scene raises UnknownName naming the nearest scenes."""
    _check_scene(scene)
    return _extension().parameters(scene)


def _check_scene(scene):
    if not isinstance(scene, str):
        raise TypeError(f"scene: expected a scene name (str), got {type(scene).__name__}")
    naming.check_names("scene", [scene], scenes(), "(see rodend.scenes())")


def signal_catalogue():
    """[(name, unit, width, description)] of every signal (`rodend signals`)."""
    return list(_extension().signal_catalogue())


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
        # an unknown name raises UnknownName (a KeyError) naming the nearest ones
        for key, kind in (("signals", "signal"), ("units", "signal"), ("long_names", "signal"),
                          ("metrics", "metric"), ("metric_units", "metric")):
            if isinstance(d.get(key), dict):
                setattr(self, key, naming.Names(d[key], kind))

    def to_xarray(self):
        """The histories as an xarray.Dataset over time (vector components labelled: x, y, z
        or the catalogue's names), CF attributes (short long_name, the sentence in
        description)."""
        t = self.signals.get("time")
        data, coords = {}, {}
        for name, v in self.signals.items():
            if name == "time":
                continue
            dims = ("time",)
            if v.ndim == 2:
                cdim, labels = naming.components(name, v.shape[1])
                dims += (cdim,)
                coords[cdim] = (cdim, labels)
            data[name] = (dims, v, naming.attrs(name, self.units[name], self.long_names[name]))
        if t is not None:
            coords["time"] = ("time", t, naming.attrs("time", "s", self.long_names["time"]))
        return naming.dataset(data, coords=coords,
                          attrs={"Conventions": naming.CONVENTIONS, "case_id": self.case_id,
                                 "status": self.status})

    def __repr__(self):
        return (f"<rodend.Case {self.case_id} {self.status}, {len(self.signals)} signals, "
                f"t_reached {self.t_reached_s} s>")


def run_case(scene, parameters=None, *, time=None, integrator=None, signals=None, health=None,
             metrics=None, write=None):
    """Runs one case in memory and returns a Case (histories as numpy arrays, metrics as a
    dict). Nothing touches the disk unless `write` names a case file to write (.h5, the same
    file `rodend run` writes).

    scene: a scene name (rodend.scenes()); parameters: overrides of its defaults, by dotted key
    path or nested dicts (numbers may be numpy scalars, lists numpy arrays); time: {"end": s,
    "sample_interval": s} (default: end 0.1 s sampled every 1e-4 s); integrator, signals,
    health, metrics: as the study keys of the same names. Raises InputError (a ValueError) with
    the command line's message for a bad input, UnknownName for an unknown scene or signal,
    TypeError for an argument of the wrong type.
    """
    _check_scene(scene)
    doc = {"name": "run_case", "scene": scene,
           "time": time if time is not None else {"end": 0.1, "sample_interval": 1e-4}}
    for key, value in (("parameters", parameters), ("time", time), ("integrator", integrator),
                       ("health", health), ("metrics", metrics)):
        _check_type(key, value, dict, "a dict")
        if value is not None:
            doc[key] = value
    if signals is not None:
        doc["signals"] = _signal_names(signals)
    if write is not None:
        _check_type("write", write, (str, os.PathLike), "a path")
    return Case(_extension().run_case(_json(doc), "run_case()", "" if write is None else os.fspath(write)))


def load_study(study, *, results_root="results", set=None):
    """A study as `rodend run --dry-run` resolves it: name, scene, output_dir, axis_keys,
    source (the document with the overrides), cases [{case_id, case_index, coordinates}].
    `study` is a study file's path or the study itself as a dict."""
    root = _path_arg("results_root", results_root)
    with _StudyFile(study, root) as path:
        return _extension().load_study(path, root, _overrides(set))


def run_study(study, *, threads=1, results_root="results", set=None, rerun_failed=False,
              progress=False):
    """Runs a study as `rodend run` does (resume included) and returns (exit code, results
    folder): 0 when every case is ok, 1 when one failed. `study` is a study file's path or the
    study itself as a dict (written to a temporary file in the results root for the run, then
    removed; the results folder's study.json keeps it). `set` is {key.path: value} or a list
    of "key.path=value" strings, as `--set`; values may be numpy scalars and arrays. Messages go
    to the logger "rodend"; `progress`: False, True (a tqdm bar where tqdm is installed, else
    the progress line, on sys.stderr) or a callable taking a rodend.Progress after each case
    (rodend/progress.py). Raises FileNotFoundError for a study file that
    is not there, InputError for a bad study, TypeError naming the argument of a
    wrong type, KeyboardInterrupt on Ctrl-C once the cases in flight are written."""
    if isinstance(threads, bool) or not isinstance(threads, numbers.Integral):
        raise TypeError(f"threads: expected an integer >= 1, got {type(threads).__name__} "
                        f"{threads!r}")
    if not 1 <= threads <= 4096:  # the extension's C int would refuse 2**31 with its signature
        raise _extension().InputError(f"threads: expected an integer from 1 to 4096 (as "
                                      f"--threads), got {int(threads)}")
    if not isinstance(rerun_failed, bool) and type(rerun_failed).__name__ != "bool_":
        raise TypeError(f"rerun_failed: expected True or False, got "
                        f"{type(rerun_failed).__name__} {rerun_failed!r}")
    from .progress import Reporter
    reporter = Reporter(bool(progress) if type(progress).__name__ == "bool_" else progress)
    root = _path_arg("results_root", results_root)
    overrides = _overrides(set)
    try:
        with _StudyFile(study, root) as path:
            if isinstance(study, dict):  # the resume hint names the study.json the run keeps
                reporter.rename = (path, _kept_study_json(study, root))
            rc, folder = _extension().run_study(path, int(threads), root, overrides, bool(rerun_failed),
                                        True, reporter.message, reporter.progress)
    finally:
        reporter.close()
    if rc == 128 + signal.SIGINT:  # Ctrl-C: the cases in flight were finished and written
        raise KeyboardInterrupt(f"run_study interrupted; the complete cases are in {folder}: "
                                "run it again to resume")
    return rc, folder


def _kept_study_json(study, root):
    """Where the run of a study given as a dict keeps it: RESULTS_FOLDER/study.json."""
    out = study.get("output")
    folder = out if isinstance(out, str) else \
        out.get("directory") if isinstance(out, dict) else None
    if not isinstance(folder, str) or not folder:
        folder = os.path.join(root, study.get("name", "study"))
    return os.path.join(folder, "study.json")


def _json_default(v):
    """numpy scalars and arrays as the numbers and lists they hold (json.dumps' default)."""
    if hasattr(v, "tolist") and type(v).__module__ == "numpy":
        return v.tolist()
    if isinstance(v, os.PathLike):
        return os.fspath(v)
    raise TypeError(f"Object of type {type(v).__name__} is not JSON serializable")


def _json(value, key=""):
    """JSON text of a Python value; a value nested too deep for the json module (which
    recurses) raises InputError naming the key, as the loader does for deep study files."""
    try:
        return json.dumps(value, allow_nan=False, default=_json_default)
    except RecursionError:
        raise _extension().InputError(f"{key or 'the document'}: nested too deep (the loader takes at most 64 "
                         "levels); expected a value a study can hold") from None


def _check_type(name, value, types, what):
    if value is not None and not isinstance(value, types):
        raise TypeError(f"{name}: expected {what}, got {type(value).__name__} {value!r}")


def _path_arg(name, value):
    _check_type(name, value, (str, os.PathLike), "a path (str or os.PathLike)")
    return os.fspath(value)


def _signal_names(signals):
    if isinstance(signals, str):
        return signals  # "all", checked by the loader
    names = list(signals.tolist() if hasattr(signals, "tolist") else signals)
    for n in names:
        _check_type("signals", n, str, "signal names (str)")
    naming.check_names("signal", names, [c[0] for c in signal_catalogue()],
                       "(see rodend.signal_catalogue())")
    return names


class _StudyFile:
    """The path of a study given as a path, or of a temporary file holding a study given as a
    dict (in a fresh folder of the results root; removed on exit)."""

    def __init__(self, study, root):
        self.study, self.root, self.tmp, self.path = study, root, None, None

    def __enter__(self):
        if isinstance(self.study, dict):
            if isinstance(self.study.get("scene"), str):
                _check_scene(self.study["scene"])
            name = self.study.get("name", "study")
            _check_type("name", name, str, "a string")
            os.makedirs(self.root, exist_ok=True)
            self.tmp = tempfile.mkdtemp(prefix=".rodend-study-", dir=self.root)
            path = os.path.join(self.tmp, (name if name and "/" not in name else "study") + ".json")
            with open(path, "w", encoding="utf-8") as fh:
                fh.write(_json(self.study))
            self.path = path
            return path
        path = _path_arg("study", self.study)
        if not os.path.lexists(path):  # as open() would say, not a bad study
            raise FileNotFoundError(errno.ENOENT, "no such study file", path)
        return path

    def __exit__(self, kind, error, tb):
        if self.tmp:
            import shutil
            shutil.rmtree(self.tmp, ignore_errors=True)
            ext = sys.modules.get("rodend._rodend")
            if ext is not None and isinstance(error, ext.InputError):
                # the temporary file is gone: name the dict instead
                raise ext.InputError(str(error).replace(self.path, "<study dict>")) from None


def _overrides(s):
    if s is None:
        return []
    if isinstance(s, dict):
        for k in s:
            _check_type("set", k, str, "{key.path: value} with str keys")
        return [f"{k}={_json(v, 'set=' + k)}" for k, v in s.items()]
    if isinstance(s, str):
        raise TypeError("set: expected {key.path: value} or a list of \"key.path=value\" "
                        "strings, got one str (wrap it in a list)")
    out = list(s)
    for x in out:
        _check_type("set", x, str, 'a list of "key.path=value" strings')
    return out
