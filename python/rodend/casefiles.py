"""A study's files on disk, read once for every reader (rodend.open_results' pandas and xarray,
rodend.study's numpy for the figures of plots/): the checksum every reader checks first
(docs/results.md, "Crash safety"), the attributes' text and units (schema 1's `unit` too),
summary.h5's table, the study document, and the case files opened one at a time, each checked
the first time it is read."""
import json
import os

import h5py
import numpy as np


_USER_BLOCK = 512
_MAGIC = b"RODEND-CHECKSUM 1\n"
_HDF5_SIGNATURE = b"\x89HDF\r\n\x1a\n"


class CorruptFile(ValueError):
    """A results file (case file or summary.h5) whose bytes are damaged; the message names it."""


class NotAStudy(ValueError):
    """The folder or file is not (readable as) a rodend study's results; a one-line message
    naming it."""


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
    """str from whatever h5py hands back for a string (bytes, numpy bytes, a 0-d array or str:
    it depends on how the string was written and on the h5py version)."""
    if isinstance(v, (bytes, np.bytes_)):
        return v.decode("utf-8", "replace")
    if isinstance(v, np.ndarray) and v.shape == ():
        return _text(v[()])
    return str(v)


def _units(ds):
    return _text(ds.attrs.get("units", ds.attrs.get("unit", "")))


def _long_name(ds):
    return _text(ds.attrs.get("long_name", ds.attrs.get("description", "")))


def _column(ds):
    """A summary dataset as a 1-D numpy array; string columns become arrays of str."""
    data = np.atleast_1d(ds[()])
    if data.dtype.kind in "OSU":
        return np.array([_text(v) for v in data], dtype=object)
    return data


def _attr_value(v):
    return _text(v) if isinstance(v, (bytes, str, np.bytes_)) else v


def read_summary(path):
    """summary.h5 at `path`, its checksum checked first: (columns {name: 1-D array} in the
    order of the /summary group's `columns` attribute, one row per case, strings as str;
    units {name: str}; long_names {name: str}; the root attributes {name: value}, strings as
    str). Raises CorruptFile for damaged bytes, NotAStudy for an HDF5 file that is no rodend
    summary (no /summary group, no case_id column), OSError when HDF5 cannot read it."""
    verify_checksum(path, "summary file")  # a damaged file never reaches HDF5
    with h5py.File(path, "r") as f:
        if "summary" not in f:
            raise NotAStudy(f"{path}: no /summary group: not a rodend summary file")
        g = f["summary"]
        try:
            names = json.loads(_text(g.attrs["columns"]))
        except (KeyError, ValueError):
            names = None
        columns, units, long_names = {}, {}, {}
        for name in names or list(g.keys()):
            if name in g:
                columns[name] = _column(g[name])
                units[name], long_names[name] = _units(g[name]), _long_name(g[name])
        attrs = {k: _attr_value(v) for k, v in f.attrs.items()}
    if "case_id" not in columns:
        raise NotAStudy(f"{path}: no case_id column: not a rodend summary file")
    return columns, units, long_names, attrs


def summary_rows(folder):
    """The rows of folder/summary.h5 (its checksum checked first), one {column: value} per
    case in summary order (numbers as numpy scalars, strings as str): for scripts that walk
    the cases one by one. NotAStudy when there is no summary.h5."""
    path = os.path.join(folder, "summary.h5")
    if not os.path.isfile(path):
        raise NotAStudy(f"{folder}: not a rodend results folder (no summary.h5)")
    columns = read_summary(path)[0]
    return [{k: v[i] for k, v in columns.items()} for i in range(len(columns["case_id"]))]


def study_document(folder, attrs):
    """The study document as run: `folder`/study.json, else the summary's root attribute
    study_json (`attrs` from read_summary); {} when neither is readable."""
    try:
        with open(os.path.join(folder, "study.json"), encoding="utf-8") as fh:
            return json.load(fh)
    except (OSError, ValueError):
        pass
    try:
        return json.loads(_text(attrs.get("study_json", "")) or "{}")
    except ValueError:
        return {}


class CaseFiles:
    """The case files of a study folder, in summary order (`case_ids`), opened on demand.
    Each is checked (checksum, the case id it holds) before its first read."""

    def __init__(self, folder, case_ids):
        self.folder = folder
        self.case_ids = list(case_ids)
        self._checked = set()

    def path(self, i):
        return os.path.join(self.folder, "cases", f"{self.case_ids[i]}.h5")

    def check_present(self):
        """FileNotFoundError naming the first case file the summary lists that is missing."""
        for i in range(len(self.case_ids)):
            self._missing(i)

    def _missing(self, i):
        path = self.path(i)
        if not os.path.isfile(path):
            # reported, never shown as NaN histories of a case the summary lists
            raise FileNotFoundError(f"{path}: the case file of case {self.case_ids[i]} (a row "
                                    f"of {self.folder}/summary.h5) is missing")

    def open(self, i):
        """The h5py.File of case i (the caller closes it)."""
        self._missing(i)
        path, cid = self.path(i), self.case_ids[i]
        if i not in self._checked:
            verify_checksum(path, "case file")  # a damaged file never reaches HDF5
        f = h5py.File(path, "r")
        held = _text(f.attrs.get("case_id", ""))
        if held != cid:
            f.close()
            raise CorruptFile(f"{path}: holds case {held}, not {cid} (a case file copied or "
                              "moved under another case's name)")
        self._checked.add(i)
        return f
