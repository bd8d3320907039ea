"""Reading a rodend study's results (layout: README "Results layout", schema_version 2;
schema 1 files, whose unit attribute was called `unit` instead of `units`, are read too).

Only numpy and h5py (Debian's, under /usr/bin/python3).

    from rodend_results import open_study
    study = open_study("results/default")          # raises NotAStudy for anything else
    study.summary["max_contact_force"]              # numpy array, one value per case, grid order
    for case in study.cases():                      # grid order
        t, unit = case.signal("time"), case.unit("time")
        print(case.label, case.coordinates, case.parameter("contact.clearance"))

Strings read back from HDF5 may be bytes or str depending on how they were written and on the
h5py version; everything here hands out str.
"""
import json
import math
import os

import h5py
import numpy as np

# the columns of the summary that come before the grid coordinates, and the first after them
_LEADING = ("case_id", "case_index")
_AFTER_GRID = "status"


def _load_casefiles():
    """The package's checksum reader (python/rodend/casefiles.py), loaded by its path: the plots
    run without the compiled module the package `rodend` loads on import."""
    import importlib.util
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "python", "rodend",
                        "casefiles.py")
    spec = importlib.util.spec_from_file_location("rodend_casefiles", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


_casefiles = _load_casefiles()
CorruptFile = _casefiles.CorruptFile
verify_checksum = _casefiles.verify_checksum


class NotAStudy(Exception):
    """The folder is not a rodend study's results folder (one-line message)."""


def text(value):
    """str from whatever h5py handed back for a string (bytes, numpy bytes or str)."""
    if isinstance(value, (bytes, np.bytes_)):
        return value.decode("utf-8", "replace")
    if isinstance(value, np.ndarray) and value.shape == ():
        return text(value[()])
    return str(value)


def unit_of(ds):
    """The unit attribute of a dataset: `units` (schema 2, CF) or `unit` (schema 1)."""
    return text(ds.attrs.get("units", ds.attrs.get("unit", "")))


def _column(ds):
    """A summary dataset as a numpy array; string columns become arrays of str."""
    data = ds[()]
    if data.dtype.kind in "OSU":
        return np.array([text(v) for v in np.atleast_1d(data)], dtype=object)
    return np.atleast_1d(data)


def load_summary(results_dir):
    """The summary table as {column: 1-D numpy array}, columns in order, one row per case in
    grid order; string columns hold str. Raises NotAStudy (see read_summary)."""
    return read_summary(results_dir)[0]


def read_summary(results_dir):
    """(columns dict {name: 1-D array} in column order, units {name: unit str}, root attrs dict).

    Raises NotAStudy when there is no readable summary.h5 with a /summary group.
    """
    path = os.path.join(results_dir, "summary.h5")
    if not os.path.isfile(path):
        raise NotAStudy(f"{results_dir}: not a rodend study results folder (no summary.h5)")
    try:
        verify_checksum(path, "summary file")  # a damaged file never reaches HDF5
        with h5py.File(path, "r") as f:
            if "summary" not in f:
                raise NotAStudy(f"{path}: no /summary group: not a rodend summary file")
            g = f["summary"]
            names = None
            if "columns" in g.attrs:
                try:
                    names = json.loads(text(g.attrs["columns"]))
                except ValueError:
                    names = None
            if not names:
                names = list(g.keys())
            columns, units = {}, {}
            for name in names:
                if name not in g:
                    continue
                columns[name] = _column(g[name])
                units[name] = unit_of(g[name])
            attrs = {k: (text(v) if isinstance(v, (bytes, str, np.bytes_)) else v)
                     for k, v in f.attrs.items()}
    except NotAStudy:
        raise
    except (OSError, KeyError, ValueError) as e:
        raise NotAStudy(f"{path}: cannot read the summary ({e})")
    if "case_id" not in columns:
        raise NotAStudy(f"{path}: no case_id column: not a rodend summary file")
    return columns, units, attrs


def format_value(value):
    """A coordinate value for a label: shortest readable form (0.0001, 5e-05, constant)."""
    if isinstance(value, (bool, np.bool_)):
        return str(bool(value)).lower()
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    if isinstance(value, (float, np.floating)):
        v = float(value)
        if math.isfinite(v) and v == int(v) and abs(v) < 1e15:
            return str(int(v))
        return f"{v:.6g}"
    if isinstance(value, (list, tuple, np.ndarray)):
        return "[" + ", ".join(format_value(v) for v in value) + "]"
    return text(value)


def short_key(key):
    """Grid key without the 'parameters.' prefix (contact.clearance)."""
    return key[len("parameters."):] if key.startswith("parameters.") else key


def unit_suffix(unit):
    """' m' for a unit worth printing, '' for none or dimensionless."""
    return "" if unit in ("", "1", "-", None) else " " + unit


# display units of plots and labels (value * factor): axes and legends say the same unit
DISPLAY_UNITS = {
    "m": ("mm", 1e3),
    "rad": ("deg", 180.0 / math.pi),
    "Pa": ("bar", 1e-5),
    "m^3/s": ("L/min", 6e4),
}


def coordinate_label(key, value, unit):
    """"contact.clearance = 0.1 mm": a coordinate in the display unit its axes use."""
    if unit in DISPLAY_UNITS and isinstance(value, (int, float, np.integer, np.floating)) \
            and not isinstance(value, (bool, np.bool_)):
        name, factor = DISPLAY_UNITS[unit]
        return f"{short_key(key)} = {format_value(float(value) * factor)} {name}"
    return f"{short_key(key)} = {format_value(value)}{unit_suffix(unit)}"


# signals that only a scene with the feature writes: the guess for case files written before
# rodend stored the scene's features (root attribute features_json)
FEATURE_SIGNALS = {"contact": "contact_force", "mechanism": "surface_angle",
                   "actuator": "actuator_command", "wear": "sliding_work",
                   "energy_audit": "energy_residual"}


def guess_features(signal_names):
    """The features of an older case file, from the signals it recorded (a study that records
    only some signals hides the others' features)."""
    names = set(signal_names)
    return frozenset(f for f, s in FEATURE_SIGNALS.items() if s in names)


class Case:
    """One case file. Signals are read on demand and kept."""

    def __init__(self, study, row, path):
        self.study = study
        self.row = row                       # row in the summary
        self.path = path
        self.id = text(study.summary["case_id"][row])
        self.index = int(study.summary["case_index"][row]) if "case_index" in study.summary else row
        self.status = text(study.summary["status"][row]) if "status" in study.summary else "ok"
        self._signals, self._units = {}, {}
        verify_checksum(path, "case file")  # a damaged file never reaches HDF5
        with h5py.File(path, "r") as f:
            a = f.attrs
            held = text(a.get("case_id", self.id))
            if held != self.id:
                raise CorruptFile(f"{path}: holds case {held}, not {self.id} (a case file "
                                  "copied or moved under another case's name)")
            self.scene = text(a.get("scene", study.scene))
            self.status = text(a.get("status", self.status))
            self.message = text(a.get("message", ""))
            self.coordinates = json.loads(text(a.get("coordinates_json", "{}")) or "{}")
            try:
                self.parameters_json = json.loads(text(a.get("parameters_json", "{}")) or "{}")
            except ValueError:
                self.parameters_json = {}
            self.parameters, self.parameter_units = {}, {}
            if "parameters" in f:
                pa = f["parameters"].attrs
                for k, v in pa.items():
                    if k == "units_json":
                        try:
                            self.parameter_units = json.loads(text(v))
                        except ValueError:
                            pass
                        continue
                    self.parameters[k] = text(v) if isinstance(v, (bytes, str, np.bytes_)) else v
            for k, p in self.parameters_json.items():   # fall-back for older files
                if isinstance(p, dict):
                    self.parameters.setdefault(k, p.get("value"))
                    if "unit" in p:
                        self.parameter_units.setdefault(k, p["unit"])
            self.signal_names = sorted(f["signals"].keys()) if "signals" in f else []
            for name in self.signal_names:
                self._units[name] = unit_of(f["signals"][name])
            try:
                self.features = frozenset(json.loads(text(a["features_json"])))
            except (KeyError, ValueError, TypeError):
                self.features = guess_features(self.signal_names)

    # --- features --------------------------------------------------------------------------
    def has_feature(self, name):
        """Whether the case's scene has a feature (core/features.def: contact, mechanism,
        actuator, wear, planar, energy_audit)."""
        return name in self.features

    # --- signals -------------------------------------------------------------------------
    def has(self, *names):
        return all(n in self._units for n in names)

    def unit(self, name):
        return self._units.get(name, "")

    def signal(self, name):
        """The signal as a numpy array (samples,) or (samples, width); KeyError if absent."""
        if name not in self._signals:
            if name not in self._units:
                raise KeyError(f"signal {name} not recorded in case {self.id}")
            with h5py.File(self.path, "r") as f:
                self._signals[name] = f["signals"][name][()]
        return self._signals[name]

    def signals(self, *names):
        """Several signals at once, read in one opening of the file."""
        missing = [n for n in names if n not in self._signals]
        if missing:
            with h5py.File(self.path, "r") as f:
                for n in missing:
                    if n not in self._units:
                        raise KeyError(f"signal {n} not recorded in case {self.id}")
                    self._signals[n] = f["signals"][n][()]
        return [self._signals[n] for n in names]

    # --- per-case arrays (wear maps, wear evolution) --------------------------------------
    def array(self, group, name):
        """Dataset group/name of the case file (wear/ball_depth, evolution/cycles, ...) as a
        numpy array with its unit: (array, unit). KeyError if absent."""
        with h5py.File(self.path, "r") as f:
            if group not in f or name not in f[group]:
                raise KeyError(f"{group}/{name} not in case {self.id}")
            d = f[group][name]
            return d[()], unit_of(d)

    def has_array(self, group, name):
        with h5py.File(self.path, "r") as f:
            return group in f and name in f[group]

    # --- parameters and labels ----------------------------------------------------------
    def parameter(self, key, default=None):
        """A resolved parameter value by its dotted key (contact.clearance)."""
        return self.parameters.get(short_key(key), default)

    def coordinate_unit(self, key):
        """Unit of a grid coordinate: the parameter's unit, else the summary column's."""
        k = short_key(key)
        if key.startswith("parameters.") and k in self.parameter_units:
            return self.parameter_units[k]
        return self.study.units.get(key, "")

    def describe(self, sep=", "):
        """Label naming the grid coordinates that vary across the study (all grid coordinates
        if none varies; the case index and id when there is no grid), parts joined by sep;
        a case that did not finish ok gets its status appended."""
        keys = self.study.varying_keys or self.study.grid_keys
        parts = []
        for key in keys:
            value = self.coordinates.get(key, self.study.summary[key][self.row]
                                         if key in self.study.summary else None)
            parts.append(coordinate_label(key, value, self.coordinate_unit(key)))
        label = sep.join(parts) if parts else f"case {self.index} ({self.id})"
        if self.status != "ok":
            label += f" [{self.status}]"
        return label

    @property
    def label(self):
        """Legend label: "contact.clearance = 0.1 mm" (see describe)."""
        return self.describe()

    def __repr__(self):
        return f"Case({self.index}, {self.id}, {self.label})"


class Study:
    def __init__(self, results_dir):
        self.path = os.path.abspath(results_dir)
        if not os.path.isdir(self.path):
            raise NotAStudy(f"{results_dir}: no such directory")
        self.summary, self.units, self.attrs = read_summary(self.path)
        self.cases_dir = os.path.join(self.path, "cases")
        if not os.path.isdir(self.cases_dir):
            raise NotAStudy(f"{results_dir}: not a rodend study results folder (no cases/ folder)")
        self.columns = list(self.summary)
        self.name = text(self.attrs.get("study_name", os.path.basename(self.path)))
        self.study_json = self._read_study_json()
        self.scene = text(self.study_json.get("scene", "")) if isinstance(self.study_json, dict) else ""
        # grid coordinate columns: between case_index and status
        cols = self.columns
        start = max((cols.index(c) + 1 for c in _LEADING if c in cols), default=0)
        stop = cols.index(_AFTER_GRID) if _AFTER_GRID in cols else start
        self.grid_keys = cols[start:stop]
        self.varying_keys = [k for k in self.grid_keys if len(set(map(_hashable, self.summary[k]))) > 1]
        self.order = np.argsort(self.summary["case_index"], kind="stable") \
            if "case_index" in self.summary else np.arange(len(self.summary["case_id"]))
        self.missing = []                       # case ids without a case file
        self._cases = None

    def _read_study_json(self):
        for source in (os.path.join(self.path, "study.json"), None):
            try:
                if source:
                    with open(source) as f:
                        return json.load(f)
                return json.loads(text(self.attrs.get("study_json", "{}")))
            except (OSError, ValueError):
                continue
        return {}

    def __len__(self):
        return len(self.summary["case_id"])

    def cases(self):
        """The cases in grid order (those whose case file exists)."""
        if self._cases is None:
            self._cases, self.missing = [], []
            for row in self.order:
                cid = text(self.summary["case_id"][row])
                path = os.path.join(self.cases_dir, cid + ".h5")
                if not os.path.isfile(path):
                    self.missing.append(cid)
                    continue
                try:
                    case = Case(self, int(row), path)
                except (OSError, KeyError, ValueError) as e:
                    self.missing.append(f"{cid} (unreadable: {e})")
                    continue
                if not self.scene:
                    self.scene = case.scene
                self._cases.append(case)
        return list(self._cases)

    @property
    def scenes(self):
        """Every scene of the study in order of first use (several when the scene is a grid
        axis: kinematic and full-system runs side by side)."""
        out = []
        for c in self.cases():
            if c.scene not in out:
                out.append(c.scene)
        return out or ([self.scene] if self.scene else [])

    def numeric_grid_keys(self):
        """Grid columns holding numbers, in column order."""
        return [k for k in self.grid_keys
                if self.summary[k].dtype.kind in "iuf"]

    def summary_unit(self, column):
        unit = self.units.get(column, "")
        if column.startswith("parameters.") and not unit:
            for c in self.cases()[:1]:
                unit = c.coordinate_unit(column)
        return unit


def _hashable(v):
    if isinstance(v, np.ndarray):
        return tuple(v.tolist())
    if isinstance(v, float) and math.isnan(v):
        return "nan"
    return v


def iter_cases(results_dir):
    """The cases of a study's results folder in grid order (Case objects: .coordinates,
    .parameters, .label, .signal(name), .unit(name))."""
    return iter(open_study(results_dir).cases())


def open_study(results_dir):
    """Study at results_dir; raises NotAStudy with a one-line reason otherwise."""
    study = Study(results_dir)
    if not study.cases():
        if not os.listdir(study.cases_dir):
            raise NotAStudy(f"{results_dir}: the cases/ folder is empty")
        raise NotAStudy(f"{results_dir}: none of the summary's cases has a readable case file")
    return study
