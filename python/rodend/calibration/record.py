"""The measured record a calibration reads: CSV or HDF5, by the profile readers' rules
(sweep/profile_file.cpp, docs/inputs.md#profiles-from-data), plus what a calibration needs
of a record: a regular time base, long enough for the test's window.

CSV: lines starting with '#' are comments; the first other line is the header, one
`name [unit]` cell per column; then one row of numbers per sample. HDF5 (told apart by its
signature): one 1-D dataset per column, each with a string attribute `units`."""
import hashlib
import math

import numpy as np

HDF5_SIGNATURE = b"\x89HDF\r\n\x1a\n"
MAX_BYTES = 256 << 20  # the profile readers' limit
# a time base is regular when every step is within this share of the median step (the
# printed decimals of a CSV time column: 1e-6 of a 1 ms step is far below any sensor jitter
# that matters and far above the rounding of 9 significant digits)
REGULAR_TOLERANCE = 1e-6


class RecordError(ValueError):
    """A record the calibration cannot use: the message names the file and the column."""


def normal_unit(u):
    """A unit as written with its product signs made alike ('N m', 'N.m', 'N·m' -> 'N*m')."""
    return u.replace("\u00b7", "*").replace(" ", "*").replace(".", "*")


def _header_cell(cell):
    cell = cell.strip()
    if cell.endswith("]") and "[" in cell:
        i = cell.rfind("[")
        return cell[:i].strip(), cell[i + 1:-1].strip()
    return cell, ""


def _check_unit(path, where, column, unit, expected):
    if not unit:
        raise RecordError(f"{path}{where}: column '{column}' states no unit; expected "
                          f"'{expected}' (a CSV header cell '{column} [{expected}]', an HDF5 "
                          "'units' attribute)")
    if normal_unit(unit) != normal_unit(expected):
        raise RecordError(f"{path}{where}: column '{column}' is in '{unit}'; expected "
                          f"'{expected}' (the unit of the model signal it is compared with)")


def _number(path, where, column, cell):
    try:
        return float(cell)
    except ValueError:
        raise RecordError(f"{path} {where}: column '{column}' holds '{cell}'; expected a "
                          "number") from None


def _read_csv(path, text, columns):
    """columns: {name: unit}. Returns ({name: array}, [where of each row])."""
    header, idx, rows, where = None, {}, [], []
    for n, line in enumerate(text.splitlines(), start=1):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        cells = [c.strip() for c in line.split(",")]
        if header is None:
            header = [_header_cell(c) for c in cells]
            names = [h[0] for h in header]
            for col, unit in columns.items():
                if col not in names:
                    raise RecordError(f"{path} line {n} (the header): has no column '{col}'; "
                                      f"its header names {', '.join(repr(x) for x in names)}")
                idx[col] = names.index(col)
                _check_unit(path, f" line {n} (the header)", col, header[idx[col]][1], unit)
            continue
        if len(cells) != len(header):
            raise RecordError(f"{path} line {n}: {len(cells)} fields; expected "
                              f"{len(header)}, as the header has")
        rows.append([_number(path, f"line {n}", c, cells[idx[c]]) for c in columns])
        where.append(f"line {n}")
    if header is None:
        raise RecordError(f"{path}: has no header; expected a first line such as "
                          "'time [s],surface_angle [rad]'")
    data = np.array(rows, dtype=float).reshape(len(rows), len(columns))
    return {c: data[:, i] for i, c in enumerate(columns)}, where


def _read_hdf5(path, columns):
    import h5py
    out = {}
    try:
        f = h5py.File(path, "r")
    except OSError:
        raise RecordError(f"{path}: cannot be opened as an HDF5 file") from None
    with f:
        for col, unit in columns.items():
            if col not in f or not isinstance(f[col], h5py.Dataset):
                raise RecordError(f"{path}: has no dataset '{col}'; expected a 1-D dataset "
                                  "with a 'units' attribute")
            d = f[col]
            if d.ndim != 1:
                raise RecordError(f"{path} dataset '{col}': is not one-dimensional; expected "
                                  "one value per sample")
            u = d.attrs.get("units", "")
            u = u.decode() if isinstance(u, bytes) else str(u)
            _check_unit(path, f" dataset '{col}'", col, u.strip(), unit)
            out[col] = np.asarray(d[()], dtype=float)
    n = {len(v) for v in out.values()}
    if len(n) > 1:
        raise RecordError(f"{path}: datasets {', '.join(repr(c) for c in out)} hold "
                          f"{', '.join(str(len(v)) for v in out.values())} values; expected "
                          "one value per time")
    return out, [f"element {i}" for i in range(n.pop() if n else 0)]


def _check_samples(path, data, where, time_column):
    for col, v in data.items():
        bad = np.flatnonzero(~np.isfinite(v))
        if len(bad):
            raise RecordError(f"{path} {where[bad[0]]}: column '{col}' holds {v[bad[0]]}; "
                              "expected finite numbers (no NaN or infinity)")
    t = data[time_column]
    back = np.flatnonzero(np.diff(t) <= 0)
    if len(back):
        i = back[0] + 1
        raise RecordError(f"{path} {where[i]}: time {t[i]:.9g} s does not come after the "
                          f"previous sample's {t[i - 1]:.9g} s; expected a strictly increasing "
                          f"time column '{time_column}' (no repeated or decreasing times)")
    if len(t) < 2:
        raise RecordError(f"{path}: holds {len(t)} sample(s); expected at least two")
    step = np.diff(t)
    h = float(np.median(step))
    off = np.flatnonzero(np.abs(step - h) > REGULAR_TOLERANCE * h + 1e-12 * abs(t[-1]))
    if len(off):
        i = off[0] + 1
        raise RecordError(f"{path} {where[i]}: time step {step[off[0]]:.9g} s from the previous "
                          f"sample; expected a regular time base (every step {h:.9g} s, the "
                          f"median, within {REGULAR_TOLERANCE:g} of it)")
    return h


def read(path, columns, time_column="time"):
    """Reads and checks the record. columns: {name: unit} of the compared columns. Returns
    {"time": array, column: array, ..., "step": s, "sha256": hex, "bytes": n}."""
    try:
        with open(path, "rb") as fh:
            raw = fh.read(MAX_BYTES + 1)
    except IsADirectoryError:
        raise RecordError(f"{path}: is not a regular file; expected a CSV or HDF5 file") \
            from None
    except OSError as e:
        raise RecordError(f"{path}: cannot open the record ({e.strerror})") from None
    if len(raw) > MAX_BYTES:
        raise RecordError(f"{path}: is larger than 256 MiB, the limit of a record file")
    wanted = {time_column: "s", **columns}
    if raw.startswith(HDF5_SIGNATURE):
        data, where = _read_hdf5(path, wanted)
    else:
        data, where = _read_csv(path, raw.decode("utf-8", errors="replace"), wanted)
    step = _check_samples(path, data, where, time_column)
    out = {c: data[c] for c in columns}
    out.update(time=data[time_column], step=step, sha256=hashlib.sha256(raw).hexdigest(),
               bytes=len(raw))
    return out


def check_covers(path, rec, start, end, time_column="time"):
    """The record must cover the window [start, end] the calibration compares."""
    t = rec["time"]
    if t[0] > start + 0.5 * rec["step"] or t[-1] < end - 0.5 * rec["step"]:
        raise RecordError(f"{path}: column '{time_column}' runs from {t[0]:.9g} s to "
                          f"{t[-1]:.9g} s; too short for the test: expected it to cover the "
                          f"compared window {start:.9g} s to {end:.9g} s")
    if not math.isfinite(start) or end <= start:
        raise RecordError(f"{path}: empty window {start} s to {end} s")
