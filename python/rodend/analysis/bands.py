"""Quantile bands (5, 50, 95 %) of recorded histories over time across the ok cases.

Each case file's /signals/time and the signal are read with h5py. When every case has the same
time samples (a study's fixed sample interval) the bands are taken sample by sample; otherwise
each case is interpolated linearly onto the longest case's time samples, NaN past its own end,
and the bands at a time are over the cases that reached it. A vector signal (n, 3) gets bands
per component.
"""
import os

import h5py
import numpy as np

from .results_io import text

LEVELS = (0.05, 0.5, 0.95)


def _read(folder, case_ids, signal):
    times, values, units = [], [], None
    for cid in case_ids:
        path = os.path.join(folder, "cases", f"{cid}.h5")
        if not os.path.isfile(path):
            raise ValueError(f"history {signal}: no case file {path}")
        with h5py.File(path, "r") as f:
            g = f["signals"]
            if signal not in g:
                raise ValueError(f"history {signal!r}: not recorded in {path}; recorded: "
                                 f"{', '.join(sorted(n for n in g if n != 'time'))}")
            times.append(g["time"][()])
            values.append(g[signal][()].astype(float))
            units = units or text(g[signal].attrs.get("units", ""))
    return times, values, units


def band(folder, case_ids, signal):
    """{time, levels, quantiles (len(LEVELS), nt[, w]), cases, units} of one signal."""
    if len(case_ids) == 0:
        raise ValueError(f"history {signal}: no ok case to draw bands from")
    times, values, units = _read(folder, case_ids, signal)
    longest = max(times, key=len)
    same = all(len(t) == len(longest) and np.array_equal(t, longest) for t in times)
    shape = (len(values), len(longest)) + values[0].shape[1:]
    stack = np.full(shape, np.nan)
    for i, (t, v) in enumerate(zip(times, values)):
        if same:
            stack[i] = v
            continue
        inside = longest <= t[-1]
        cols = v.reshape(len(t), -1)
        interp = np.column_stack([np.interp(longest[inside], t, c) for c in cols.T])
        stack[i, inside] = interp.reshape((int(inside.sum()),) + v.shape[1:])
    q = np.nanquantile(stack, LEVELS, axis=0)
    return {"time": longest, "levels": list(LEVELS), "quantiles": q, "cases": len(values),
            "units": units, "resampled": not same}
