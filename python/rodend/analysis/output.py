"""analysis.json, bands.h5 and the table printed to stdout (drawn by table.py)."""
import json
import math
import os

import h5py
import numpy as np

from ..atomic import atomic_file


def plain(v):
    """v with numpy values as Python ones and non-finite floats as None (JSON null)."""
    if isinstance(v, dict):
        return {str(k): plain(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [plain(x) for x in v]
    if isinstance(v, np.ndarray):
        return plain(v.tolist())
    if isinstance(v, (np.integer,)):
        return int(v)
    if isinstance(v, (float, np.floating)):
        return None if not math.isfinite(float(v)) else float(v)
    return v


def write_json(folder, doc):
    path = os.path.join(folder, "analysis", "analysis.json")
    text = json.dumps(plain(doc), indent=1, allow_nan=False) + "\n"
    with atomic_file(path) as fh:  # never through a link (rodend/atomic.py)
        fh.write(text.encode("utf-8"))
    return path


def write_bands(folder, groups):
    """groups: [(grid coordinates, {signal: band})] → analysis/bands.h5: one group per grid
    point (g0, g1, ...; attribute coordinates_json), in it one group per signal with time [s],
    levels [1] and quantiles (levels × time[× component]) in the signal's units."""
    path = os.path.join(folder, "analysis", "bands.h5")
    with atomic_file(path) as fh, h5py.File(fh, "w") as f:  # never through a link
        for k, (coords, bands) in enumerate(groups):
            g = f.create_group(f"g{k}")
            g.attrs["coordinates_json"] = json.dumps(plain(coords))
            for name, b in bands.items():
                s = g.create_group(name)
                s.attrs["cases"] = b["cases"]
                s.attrs["resampled"] = b["resampled"]
                for ds, data, units in (("time", b["time"], "s"), ("levels", b["levels"], "1"),
                                        ("quantiles", b["quantiles"], b["units"])):
                    s.create_dataset(ds, data=np.asarray(data, dtype=float))
                    s[ds].attrs["units"] = units
    return path


def table(doc):
    """The spread and the ranked factors of every metric, as lines of text (table.py)."""
    from .table import table as _table
    return _table(doc)
