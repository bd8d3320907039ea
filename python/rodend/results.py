"""A study's results folder as pandas and xarray (rodend.open_results).

Reads results of schema_version 1 (attribute `unit`) and 2 (`units`, dimension scales). Opening
reads summary.h5 and study.json only; the case files are read when their histories are accessed
(rodend/lazy.py), one at a time. The files on disk are the stable layout of docs/results.md;
what is returned adds the study's grid as dimensions, labelled components and CF attributes
(rodend/naming.py).
"""
import json
import os

import numpy as np

from . import naming
from .casefiles import (CaseFiles, CorruptFile, _long_name, _text, _units, read_summary,
                        study_document, verify_checksum)

__all__ = ["open_results", "Results", "CorruptFile", "verify_checksum"]

# names the Datasets use besides the grid's: a grid key's coordinate name avoids them
_RESERVED = {"time", "sample", "status", "case_id", "case_index", "component3", "euler_321",
             "joint", "chamber"}


def _axis_size(entry):
    """Number of values of one grid axis entry of a study document (values, linspace,
    logspace: the count is given, nothing is expanded here)."""
    if "values" in entry:
        return len(entry["values"])
    for form in ("linspace", "logspace"):
        if form in entry:
            return int(entry[form][2])
    raise ValueError(f"grid axis without values: {entry}")


class Results:
    """One study's results folder. Opening it reads summary.h5 and study.json, no case file.

    summary          pandas.DataFrame, one row per case in grid order, the columns of
                     summary.csv; .attrs["units"] and .attrs["long_names"] per column
    summary_dataset  the same table as an xarray.Dataset over the study's dimensions()
    histories        xarray.Dataset, lazy: every recorded signal over dimensions() and time
                     (and the component dimension of a vector); a case file is read when its
                     values are accessed. A case that stopped early is NaN past its end.
    case(which)      one case's histories, its grid values as scalar coordinates
    study            the study document as run (study.json); provenance: the summary's
    """

    def __init__(self, folder, signals=None):
        self.folder = os.fspath(folder)
        path = os.path.join(self.folder, "summary.h5")
        if not os.path.isfile(path):
            raise FileNotFoundError(f"{self.folder}: not a rodend results folder (no summary.h5)")
        cols, units, long_names, attrs = read_summary(path)  # its checksum first
        self.provenance = json.loads(_text(attrs.get("provenance_json", "{}")) or "{}")
        self.schema_version = int(attrs.get("schema_version", 1))
        import pandas as pd
        self.summary = pd.DataFrame(cols, columns=list(cols))
        self.summary.attrs["units"] = units
        self.summary.attrs["long_names"] = long_names
        self.study = study_document(self.folder, attrs)
        ids = self.summary["case_id"] if "case_id" in self.summary else []
        self._files = CaseFiles(self.folder, ids)
        self._recorded_signals = None
        self._names = None
        self._histories = None
        self._signals = None if signals is None else self._check_signals(signals)

    def __repr__(self):
        return f"<rodend.Results {self.folder}: {len(self.summary)} cases>"

    # ---------------------------------------------------------------------------------------
    def grid_axes(self):
        """[(dimension name, [keys], size)] of the study's grid, in axis order."""
        axes = []
        for entry in self.study.get("grid", []):
            if "zip" in entry:
                keys = [m["key"] for m in entry["zip"]]
                axes.append((keys[0], keys, _axis_size(entry["zip"][0])))
            else:
                axes.append((entry["key"], [entry["key"]], _axis_size(entry)))
        return axes

    def dimensions(self):
        """[(dimension name, [coordinate keys], size)] the cases are laid out over: the grid
        axes in order (a zip group is one dimension named by its first key, its other keys are
        coordinates along it), then `design.sample` for a sampled design (the factors' keys are
        coordinates along it); one dimension `case_index` when the cases are no such product.
        A dimension's name is its first key's coordinate name (coordinate_names: `clearance`
        for `parameters.contact.clearance`)."""
        names = self.coordinate_names()
        return [(names.get(keys[0], keys[0]), keys, size) for _, keys, size in self._axes()]

    def coordinate_names(self):
        """{grid or design key: its name in the Datasets}: the key's last part, without dots,
        longer where two would be the same (rodend.naming.coordinate_names). The Datasets keep
        each key as the coordinate's attribute `key`, and the dotted key itself as an alias
        coordinate (indexed, so `.sel({"parameters.contact.clearance": v})` still works) for
        this release only."""
        if self._names is None:
            keys = [k for _, ks, _ in self._axes() for k in ks]
            taken = set(self.summary.columns) - set(keys) | _RESERVED
            self._names = naming.coordinate_names(keys, taken)
        return self._names

    def _axes(self):
        """dimensions() by the keys' full names."""
        axes = self.grid_axes()
        n = len(self.summary)
        n_grid = int(np.prod([a[2] for a in axes], dtype=np.int64))
        design = self.study.get("design")
        if design and n_grid and n % n_grid == 0:
            keys = ["design.sample"] + [f["key"] for f in design.get("factors", [])]
            axes.append(("design.sample", keys, n // n_grid))
        product = int(np.prod([a[2] for a in axes], dtype=np.int64))
        if product != n or any(a[1][0] not in self.summary for a in axes):
            return [("case_index", ["case_index"], n)]
        return axes

    def case_file(self, case_id):
        return os.path.join(self.folder, "cases", f"{case_id}.h5")

    def _attrs(self, key):
        return naming.attrs(key, self.summary.attrs["units"].get(key, ""),
                            self.summary.attrs["long_names"].get(key, ""))

    def _dataset_attrs(self):
        return {"Conventions": naming.CONVENTIONS,
                "study": self.study.get("name", os.path.basename(self.folder)),
                "results": self.folder}

    def _axis_coords(self, axes):
        """The coordinates along each dimension: the rows where every other axis is at its
        first value; each key by its coordinate name, and by its dotted key as an alias."""
        shape = tuple(size for _, _, size in axes)
        coords = {}
        for pos, (name, keys, size) in enumerate(axes):
            rows = np.arange(size) * int(np.prod(shape[pos + 1:], dtype=np.int64))
            for key in keys:
                if key in self.summary:
                    coords.update(self._coordinate(key, name, self.summary[key].to_numpy()[rows]))
        return coords

    def _coordinate(self, key, dims, values):
        """{name: (dims, values, attrs)} of one grid or design key: its coordinate name (the
        attribute `key` the full key path) and, where that differs, the dotted key as an alias
        for this release."""
        name = self.coordinate_names().get(key, key)
        attrs = dict(self._attrs(key), key=key)
        out = {name: (dims, values, attrs)}
        if name != key:
            out[key] = (dims, values, dict(attrs, deprecated=(
                f"the dotted name of coordinate {name!r}, kept for this release only: use "
                f".sel({name}=...)")))
        return out

    def _with_aliases(self, ds, axes):
        """ds with an index on each dimension's dotted alias, so that .sel by the old name
        selects as before."""
        for name, keys, _ in axes:
            if keys[0] != name and keys[0] in ds.coords:
                ds = ds.set_xindex(keys[0])
        return ds

    @property
    def summary_dataset(self):
        """The summary as an xarray.Dataset: every column over the study's dimensions() (a
        3 x 3 grid gives a 3 x 3 table), the axis keys as coordinates."""
        axes = self.dimensions()
        shape, dims = tuple(a[2] for a in axes), tuple(a[0] for a in axes)
        coords = self._axis_coords(axes)
        keys = {k for _, ks, _ in axes for k in ks}
        data = {col: (dims, self.summary[col].to_numpy().reshape(shape), self._attrs(col))
                for col in self.summary.columns if col not in coords and col not in keys}
        return self._with_aliases(naming.dataset(data, coords=coords,
                                                 attrs=self._dataset_attrs()), axes)

    # ---------------------------------------------------------------------------------------
    def _reference_rows(self):
        """One row per scene of the study (its first ok case, else its first case); the first
        is the ok case of the longest time.end: the cases whose files tell the signals."""
        s = self.summary
        ok = (s["status"] == "ok").to_numpy() if "status" in s else np.ones(len(s), bool)
        order = np.arange(len(s))
        if "time.end" in s:
            order = np.argsort(-s["time.end"].to_numpy(float), kind="stable")
        scenes = s["scene"].to_numpy() if "scene" in s else np.zeros(len(s))
        rows = {}
        for i in list(order[ok[order]]) + list(order):
            rows.setdefault(scenes[i], int(i))
        return list(rows.values())

    def recorded_signals(self):
        """{signal: (units, description, width or None)} as the case files record them (read
        from one case file per scene)."""
        if self._recorded_signals is None:
            found = {}
            for i in self._reference_rows():
                with self._files.open(i) as f:
                    for n, d in f["signals"].items():
                        found.setdefault(n, (_units(d), _long_name(d),
                                             d.shape[1] if d.ndim == 2 else None))
            self._recorded_signals = found
        return self._recorded_signals

    def _check_signals(self, signals):
        if isinstance(signals, str):
            signals = [signals]
        try:
            signals = list(signals)
        except TypeError:
            raise TypeError(f"signals: expected a list of signal names, got "
                            f"{type(signals).__name__}") from None
        for n in signals:
            if not isinstance(n, str):
                raise TypeError(f"signals: expected signal names (str), got {n!r}")
        naming.check_names("signal", signals, self.recorded_signals(),
                           f"(not among the signals recorded in {self.folder})")
        return signals

    # ---------------------------------------------------------------------------------------
    @property
    def histories(self):
        if self._histories is None:
            from .histories import lazy_histories
            self._histories = lazy_histories(self)
        return self._histories

    def case(self, which, signals=None):
        """One case's histories as an xarray.Dataset over time, read now: `which` is a case
        id, a case index or {grid key: value}; `signals` limits which. The case's grid values
        are scalar coordinates of its signals; vector components are labelled."""
        from .histories import case_dataset
        names = self._signals if signals is None else self._check_signals(signals)
        return case_dataset(self, self._row(which), names)

    def _row(self, which):
        s = self.summary
        if isinstance(which, str):
            hits = np.flatnonzero(s["case_id"].to_numpy() == which)
            if not len(hits):
                raise naming.unknown("case id", which, s["case_id"], f"in {self.folder}")
            return int(hits[0])
        if isinstance(which, (int, np.integer)) and not isinstance(which, bool):
            hits = np.flatnonzero(s["case_index"].to_numpy() == which)
            if not len(hits):
                raise IndexError(f"case index {which}: {self.folder} has case indices "
                                 f"{s['case_index'].min()} to {s['case_index'].max()}")
            return int(hits[0])
        if isinstance(which, dict):  # by full key or by coordinate name (clearance)
            by_name = {n: k for k, n in self.coordinate_names().items()}
            which = {by_name.get(k, k): v for k, v in which.items()}
            naming.check_names("grid key", which, s.columns, f"(columns of {self.folder})")
            match = np.ones(len(s), bool)
            for k, v in which.items():
                match &= (s[k] == v).to_numpy()
            hits = np.flatnonzero(match)
            if len(hits) != 1:
                raise ValueError(f"{which}: matches {len(hits)} cases of {self.folder}, "
                                 "expected one")
            return int(hits[0])
        raise TypeError(f"which: expected a case id (str), a case index (int) or "
                        f"{{grid key: value}}, got {type(which).__name__}")


def open_results(folder, signals=None):
    """The results of a study folder (results/<study>, as `rodend run` wrote it), opened
    without reading any history: a Results with .summary (pandas.DataFrame),
    .summary_dataset (xarray.Dataset over the grid axes), .histories (xarray.Dataset over the
    grid axes and time, lazy: a case file is read when its values are accessed; `signals`
    limits which, an unknown or unrecorded name raises UnknownName naming the nearest) and
    .case(which) (one case's histories). Every file is checked before HDF5 reads it: a damaged
    summary.h5 or case file, or a case file under another case's name, raises
    rodend.CorruptFile (a ValueError) naming it; a missing case file, FileNotFoundError."""
    if not isinstance(folder, (str, os.PathLike)):
        raise TypeError(f"folder: expected a path (str or os.PathLike), got "
                        f"{type(folder).__name__} {folder!r}")
    return Results(os.fspath(folder), signals=signals)
