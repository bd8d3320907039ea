"""A study's results folder as pandas and xarray (rodend.open_results).

Reads results of schema_version 1 (attribute `unit`) and 2 (`units`, dimension scales).
"""
import json
import math
import os

import h5py
import numpy as np


_USER_BLOCK = 512
_MAGIC = b"RODEND-CHECKSUM 1\n"
_HDF5_SIGNATURE = b"\x89HDF\r\n\x1a\n"


class CorruptFile(ValueError):
    """A results file (case file or summary.h5) whose bytes are damaged; the message names it."""


def verify_checksum(path, kind="case file"):
    """Checks the checksum header of a case file or summary.h5 (docs/results.md, "Crash
    safety") before any HDF5 reader sees the file: the 512-byte user block exactly as rodend
    writes it, the size it states, the CRC-32 of the rest. True when it holds, False for a
    file without a user block (written before checksums); raises CorruptFile naming the file."""
    import re
    import zlib
    bad = f"corrupt {kind} {os.fspath(path)}: "
    with open(path, "rb") as fh:
        head = fh.read(_USER_BLOCK)
        if head[:8] == _HDF5_SIGNATURE:
            return False
        if not head.startswith(_MAGIC):
            raise CorruptFile(bad + ("empty file" if not head else
                                     'no checksum header ("RODEND-CHECKSUM") and not an HDF5 file'))
        m = re.match(rb"crc32 ([0-9a-f]{8})\nbytes ([0-9]+)\n", head[len(_MAGIC):])
        if len(head) < _USER_BLOCK or not m:
            raise CorruptFile(bad + "damaged checksum header")
        stored, size = int(m.group(1), 16), int(m.group(2))
        expected = (_MAGIC + b"crc32 %08x\nbytes %d\n" % (stored, size)).ljust(_USER_BLOCK, b"\0")
        if head != expected:
            raise CorruptFile(bad + "damaged checksum header")
        actual = os.fstat(fh.fileno()).st_size
        if actual != size:
            raise CorruptFile(bad + f"{actual} bytes, its checksum header says {size} "
                              "(truncated or extended)")
        crc = 0
        for block in iter(lambda: fh.read(1 << 20), b""):
            crc = zlib.crc32(block, crc)
    if crc != stored:
        raise CorruptFile(bad + f"content does not match its checksum (CRC-32 {crc:08x}, "
                          f"stored {stored:08x})")
    return True


def _text(v):
    if isinstance(v, (bytes, np.bytes_)):
        return v.decode("utf-8", "replace")
    return str(v)


def _units(ds):
    return _text(ds.attrs.get("units", ds.attrs.get("unit", "")))


def _long_name(ds):
    return _text(ds.attrs.get("long_name", ds.attrs.get("description", "")))


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
    """One study's results folder.

    summary    pandas.DataFrame, one row per case in grid order, the columns of summary.csv;
               .attrs["units"] and .attrs["long_names"] per column
    histories  xarray.Dataset (read on first use): every recorded signal over the study's grid
               axes (one dimension per axis, named by its key; a zip group is one dimension
               named by its first key, its other keys are coordinates along it) and time (and
               component<w> for vector signals); units and long_name as attributes. A case
               that stopped early is NaN past its end.
    study      the study document as run (study.json); provenance: the summary's provenance
    """

    def __init__(self, folder, signals=None):
        self.folder = os.fspath(folder)
        path = os.path.join(self.folder, "summary.h5")
        if not os.path.isfile(path):
            raise FileNotFoundError(f"{self.folder}: not a rodend results folder (no summary.h5)")
        self._signals = signals
        self._histories = None
        study_json = os.path.join(self.folder, "study.json")
        verify_checksum(path, "summary file")  # a damaged file never reaches HDF5
        with h5py.File(path, "r") as f:
            g = f["summary"]
            names = json.loads(_text(g.attrs["columns"]))
            cols, units, long_names = {}, {}, {}
            for n in names:
                d = g[n][()]
                if d.dtype.kind in "OS":
                    d = np.array([_text(x) for x in d], dtype=object)
                cols[n] = d
                units[n] = _units(g[n])
                long_names[n] = _long_name(g[n])
            self.provenance = json.loads(_text(f.attrs.get("provenance_json", "{}")) or "{}")
            self.schema_version = int(f.attrs.get("schema_version", 1))
            source = _text(f.attrs.get("study_json", "")) or None
        import pandas as pd
        self.summary = pd.DataFrame(cols, columns=names)
        self.summary.attrs["units"] = units
        self.summary.attrs["long_names"] = long_names
        if os.path.isfile(study_json):
            with open(study_json, encoding="utf-8") as fh:
                self.study = json.load(fh)
        else:
            self.study = json.loads(source) if source else {}

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

    def case_file(self, case_id):
        return os.path.join(self.folder, "cases", f"{case_id}.h5")

    @property
    def histories(self):
        if self._histories is None:
            self._histories = self._read_histories()
        return self._histories

    def _read_histories(self):
        import xarray as xr
        s = self.summary
        axes = self.grid_axes()
        shape = tuple(size for _, _, size in axes)
        if int(np.prod(shape, dtype=np.int64)) != len(s):
            # not a plain product of the axes: one dimension over the cases
            axes = [("case_index", ["case_index"], len(s))]
            shape = (len(s),)
        grid_dims = tuple(name for name, _, _ in axes)

        per_case, units, long_names = [], {}, {}
        for cid in s["case_id"]:
            path = self.case_file(cid)
            data = {}
            if not os.path.isfile(path):
                # reported, never shown as NaN histories of a case the summary lists
                raise FileNotFoundError(f"{path}: the case file of case {cid} (a row of "
                                        f"{self.folder}/summary.h5) is missing")
            verify_checksum(path, "case file")  # a damaged file never reaches HDF5
            with h5py.File(path, "r") as f:
                held = _text(f.attrs.get("case_id", ""))
                if held != cid:
                    raise CorruptFile(f"{path}: holds case {held}, not {cid} (a case file "
                                      "copied or moved under another case's name)")
                g = f["signals"]
                wanted = list(g) if self._signals is None else \
                    ["time"] + [n for n in self._signals if n != "time"]
                for n in wanted:
                    if n in g:
                        data[n] = g[n][()]
                        units.setdefault(n, _units(g[n]))
                        long_names.setdefault(n, _long_name(g[n]))
            per_case.append(data)

        times = [c["time"] for c in per_case if "time" in c]
        longest = max(times, key=len) if times else np.zeros(0)
        shared = all(np.array_equal(t, longest[:len(t)]) for t in times)
        nt = len(longest)
        time_dim = "time" if shared else "sample"

        names = sorted({n for c in per_case for n in c if n != "time"})
        variables = {}
        for n in names:
            width = next(c[n].shape[1] for c in per_case if n in c and c[n].ndim == 2) \
                if any(n in c and c[n].ndim == 2 for c in per_case) else None
            full = np.full(shape + (nt,) + ((width,) if width else ()), np.nan)
            flat = full.reshape((-1,) + full.shape[len(shape):])
            for i, c in enumerate(per_case):
                if n in c:
                    flat[i, :len(c[n])] = c[n]
            dims = grid_dims + (time_dim,) + ((f"component{width}",) if width else ())
            variables[n] = (dims, full, {"units": units[n], "long_name": long_names[n]})

        coords = {}
        for pos, (name, keys, size) in enumerate(axes):
            # the values along this axis: the rows where every other axis is at its first value
            stride = int(np.prod(shape[pos + 1:], dtype=np.int64))
            rows = [k * stride for k in range(size)]
            for key in keys:
                if key not in s:
                    continue
                col = s[key].to_numpy()[rows]
                coords[key] = (name, col, {"units": s.attrs["units"].get(key, ""),
                                           "long_name": s.attrs["long_names"].get(key, key)})
        if shared:
            coords["time"] = ("time", longest, {"units": "s", "long_name": "simulation time"})
        else:
            t = np.full(shape + (nt,), np.nan)
            flat = t.reshape(-1, nt)
            for i, c in enumerate(per_case):
                if "time" in c:
                    flat[i, :len(c["time"])] = c["time"]
            variables["time"] = (grid_dims + ("sample",), t,
                                 {"units": "s", "long_name": "simulation time"})
        for extra in ("status", "case_id"):
            if extra in s:
                coords[extra] = (grid_dims, s[extra].to_numpy().reshape(shape))
        return xr.Dataset(variables, coords=coords,
                          attrs={"study": self.study.get("name", os.path.basename(self.folder)),
                                 "results": self.folder})


def _isnan(v):
    return isinstance(v, float) and math.isnan(v)
