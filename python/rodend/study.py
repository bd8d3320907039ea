"""A study's results folder as numpy arrays and case objects: the reader of the figures in plots/
(numpy and h5py only: no pandas, no xarray, no compiled module). The same files as
rodend.open_results, read by the same code (rodend/casefiles.py: checksums, the summary table,
the study document, schema 1's `unit` attribute). Imported through the package:

    from rodend import open_study
    study = open_study("results/default")          # raises NotAStudy for anything else
    study.summary["max_contact_force"]              # numpy array, one value per case (summary order)
    for case in study.cases():                      # grid order
        t, unit = case.signal("time"), case.unit("time")
        print(case.label, case.coordinates, case.parameter("contact.clearance"))
"""
import json
import math
import os

import numpy as np

from .casefiles import CaseFiles, CorruptFile, NotAStudy, _text, _units, read_summary, \
    study_document, verify_checksum
from .naming import coordinate_label, short_key

__all__ = ["open_study", "Study", "Case", "NotAStudy", "CorruptFile", "verify_checksum",
           "FEATURE_SIGNALS", "guess_features"]

# the columns of the summary that come before the grid coordinates, and the first after them
_LEADING = ("case_id", "case_index")
_AFTER_GRID = "status"

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


def _json_attr(attrs, name, default):
    try:
        return json.loads(_text(attrs.get(name, "")) or "null") or default
    except ValueError:
        return default


def _parameters(f):
    """({dotted key: value}, {dotted key: unit}) of a case file: the /parameters group's
    attributes, then parameters_json (files written before the group) for what it lacks."""
    values, units = {}, {}
    if "parameters" in f:
        for k, v in f["parameters"].attrs.items():
            if k == "units_json":
                units = _json_attr(f["parameters"].attrs, k, {})
            else:
                values[k] = _text(v) if isinstance(v, (bytes, str, np.bytes_)) else v
    for k, p in _json_attr(f.attrs, "parameters_json", {}).items():
        if isinstance(p, dict):
            values.setdefault(k, p.get("value"))
            if "unit" in p:
                units.setdefault(k, p["unit"])
    return values, units


class Case:
    """One case file (row `row` of the summary), its root attributes read at once (checked
    first: rodend.casefiles.CaseFiles), its signals on demand and kept."""

    def __init__(self, study, row):
        self.study, self.row = study, row
        self.path = study.files.path(row)
        s = study.summary
        self.id = _text(s["case_id"][row])
        self.index = int(s["case_index"][row]) if "case_index" in s else row
        self._signals = {}
        with study.files.open(row) as f:
            a = f.attrs
            self.scene = _text(a.get("scene", study.scene))
            self.status = _text(a.get("status", s["status"][row] if "status" in s else "ok"))
            self.message = _text(a.get("message", ""))
            self.coordinates = _json_attr(a, "coordinates_json", {})
            self.parameters_json = _json_attr(a, "parameters_json", {})
            self.parameters, self.parameter_units = _parameters(f)
            self.signal_names = sorted(f["signals"].keys()) if "signals" in f else []
            self._units = {n: _units(f["signals"][n]) for n in self.signal_names}
            try:
                self.features = frozenset(json.loads(_text(a["features_json"])))
            except (KeyError, ValueError, TypeError):
                self.features = guess_features(self.signal_names)

    def has_feature(self, name):
        """Whether the case's scene has a feature (core/features.def: contact, mechanism,
        actuator, wear, planar, energy_audit)."""
        return name in self.features

    def has(self, *names):
        """Whether every one of the signals is recorded."""
        return all(n in self._units for n in names)

    def unit(self, name):
        """A recorded signal's unit ('' when not recorded)."""
        return self._units.get(name, "")

    def signal(self, name):
        """The signal as a numpy array (samples,) or (samples, width); KeyError if absent."""
        return self.signals(name)[0]

    def signals(self, *names):
        """Several signals at once, read in one opening of the file; KeyError for one not
        recorded."""
        missing = [n for n in names if n not in self._signals]
        for n in missing:
            if n not in self._units:
                raise KeyError(f"signal {n} not recorded in case {self.id}")
        if missing:
            with self.study.files.open(self.row) as f:
                for n in missing:
                    self._signals[n] = f["signals"][n][()]
        return [self._signals[n] for n in names]

    def array(self, group, name):
        """Dataset group/name of the case file (wear/ball_depth, evolution/cycles, ...) as
        (numpy array, unit); KeyError if absent."""
        with self.study.files.open(self.row) as f:
            if group not in f or name not in f[group]:
                raise KeyError(f"{group}/{name} not in case {self.id}")
            d = f[group][name]
            return d[()], _units(d)

    def has_array(self, group, name):
        with self.study.files.open(self.row) as f:
            return group in f and name in f[group]

    def parameter(self, key, default=None):
        """A resolved parameter value by its dotted key (contact.clearance or
        parameters.contact.clearance)."""
        return self.parameters.get(short_key(key), default)

    def coordinate_unit(self, key):
        """The unit of a grid coordinate: the parameter's unit, else the summary column's."""
        k = short_key(key)
        if key.startswith("parameters.") and k in self.parameter_units:
            return self.parameter_units[k]
        return self.study.units.get(key, "")

    def describe(self, sep=", "):
        """A label naming the grid coordinates that vary across the study (every grid
        coordinate if none varies; the case index and id when there is no grid), parts joined
        by sep; a case that did not finish ok gets its status appended."""
        parts = []
        for key in self.study.varying_keys or self.study.grid_keys:
            value = self.coordinates.get(key, self.study.summary[key][self.row]
                                         if key in self.study.summary else None)
            parts.append(coordinate_label(key, value, self.coordinate_unit(key)))
        label = sep.join(parts) if parts else f"case {self.index} ({self.id})"
        return label if self.status == "ok" else label + f" [{self.status}]"

    @property
    def label(self):
        """The legend label: "contact.clearance = 0.1 mm" (see describe)."""
        return self.describe()

    def __repr__(self):
        return f"Case({self.index}, {self.id}, {self.label})"


def _hashable(v):
    if isinstance(v, np.ndarray):
        return tuple(v.tolist())
    if isinstance(v, float) and math.isnan(v):
        return "nan"
    return v


def _read_summary(folder):
    """read_summary of folder/summary.h5, every failure a NotAStudy naming the file."""
    path = os.path.join(folder, "summary.h5")
    if not os.path.isfile(path):
        raise NotAStudy(f"{folder}: not a rodend study results folder (no summary.h5)")
    try:
        return read_summary(path)
    except NotAStudy:
        raise
    except (OSError, KeyError, ValueError) as e:
        raise NotAStudy(f"{path}: cannot read the summary ({e})") from None


class Study:
    """A results folder: its summary read at once (summary: {column: 1-D numpy array} in
    column order, one row per case in summary order; units: {column: unit}; attrs: the root
    attributes), its case files when cases() is first called. Raises NotAStudy when there is
    no readable summary.h5."""

    def __init__(self, results_dir):
        self.path = os.path.abspath(results_dir)
        if not os.path.isdir(self.path):
            raise NotAStudy(f"{results_dir}: no such directory")
        self.summary, self.units, self.long_names, self.attrs = _read_summary(self.path)
        self.cases_dir = os.path.join(self.path, "cases")
        self.columns = list(self.summary)
        self.name = _text(self.attrs.get("study_name", os.path.basename(self.path)))
        self.study_json = study_document(self.path, self.attrs)
        doc = self.study_json if isinstance(self.study_json, dict) else {}
        self.scene = _text(doc.get("scene", "")) if isinstance(doc.get("scene"), str) else ""
        cols = self.columns  # the grid coordinate columns: between case_index and status
        start = max((cols.index(c) + 1 for c in _LEADING if c in cols), default=0)
        self.grid_keys = cols[start:cols.index(_AFTER_GRID) if _AFTER_GRID in cols else start]
        self.varying_keys = [k for k in self.grid_keys
                             if len(set(map(_hashable, self.summary[k]))) > 1]
        self.order = np.argsort(self.summary["case_index"], kind="stable") \
            if "case_index" in self.summary else np.arange(len(self.summary["case_id"]))
        self.files = CaseFiles(self.path, [_text(c) for c in self.summary["case_id"]])
        self.missing = []                       # case ids without a readable case file
        self._cases = None

    def __len__(self):
        return len(self.summary["case_id"])

    def cases(self):
        """The cases in grid order whose case file exists and reads; the others are listed in
        .missing (with the reason when the file is unreadable)."""
        if self._cases is None:
            self._cases, self.missing = [], []
            for row in self.order:
                case = self._case_or_missing(int(row))
                if case is not None:
                    self.scene = self.scene or case.scene
                    self._cases.append(case)
        return list(self._cases)

    def _case_or_missing(self, row):
        cid = self.files.case_ids[row]
        if not os.path.isfile(self.files.path(row)):
            self.missing.append(cid)
            return None
        try:
            return Case(self, row)
        except (OSError, KeyError, ValueError) as e:
            self.missing.append(f"{cid} (unreadable: {e})")
            return None

    def case(self, case_id):
        """The case of that id (its file read now); KeyError when the summary has none,
        CorruptFile or OSError when its file does not read."""
        if case_id not in self.files.case_ids:
            raise KeyError(f"{self.path}: no case {case_id} in the summary")
        return Case(self, self.files.case_ids.index(case_id))

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
        """The grid columns holding numbers, in column order."""
        return [k for k in self.grid_keys if self.summary[k].dtype.kind in "iuf"]

    def summary_unit(self, column):
        """A summary column's unit (a grid parameter's from the case files when the summary
        has none)."""
        unit = self.units.get(column, "")
        if column.startswith("parameters.") and not unit:
            for c in self.cases()[:1]:
                unit = c.coordinate_unit(column)
        return unit


def open_study(results_dir):
    """The Study at results_dir with at least one readable case file; raises NotAStudy with a
    one-line reason otherwise."""
    study = Study(results_dir)
    if not os.path.isdir(study.cases_dir):
        raise NotAStudy(f"{results_dir}: not a rodend study results folder (no cases/ folder)")
    if not study.cases():
        if not os.listdir(study.cases_dir):
            raise NotAStudy(f"{results_dir}: the cases/ folder is empty")
        raise NotAStudy(f"{results_dir}: none of the summary's cases has a readable case file")
    return study
