"""Synthetic results folders of designed studies for test_analyze.py and bench/analyze.py:
design.json, summary.h5 (the layout rodend.open_results reads: group /summary, one dataset per
column with units and long_name, attribute columns = the JSON list of names) and summary.csv,
and optional case files with /signals/time and a signal."""
import json
import os

import h5py
import numpy as np
import openturns as ot

PI = float(np.pi)


def uniform(key, lower, upper, units="1"):
    return {"key": key, "units": units, "distribution": "uniform", "lower": lower,
            "upper": upper, "mean": (lower + upper) / 2, "std": (upper - lower) / 12 ** 0.5}


def distribution(factors):
    margs = []
    for f in factors:
        assert f["distribution"] == "uniform", "the fixtures draw uniform factors"
        margs.append(ot.Uniform(f["lower"], f["upper"]))
    return ot.ComposedDistribution(margs)


def saltelli_points(factors, n, seed):
    """N(d+2) points in ot.SobolIndicesExperiment's order (A, B, A with column i of B)."""
    ot.RandomGenerator.SetSeed(seed)
    return np.asarray(ot.SobolIndicesExperiment(distribution(factors), n).generate())


def mc_points(factors, n, seed):
    ot.RandomGenerator.SetSeed(seed)
    return np.asarray(distribution(factors).getSample(n))


def morris_unit_points(d, n, levels, seed):
    """n Morris trajectories (d + 1 points each) on the p-level grid: a random start with room
    for the step, then one factor at a time (random order) moved by ±delta."""
    rng = np.random.default_rng(seed)
    delta = levels / (2 * (levels - 1))
    grid = np.arange(levels) / (levels - 1)
    rows = []
    for _ in range(n):
        x = rng.choice(grid, size=d)
        rows.append(x.copy())
        for i in rng.permutation(d):
            x[i] = x[i] + delta if x[i] + delta <= 1 + 1e-12 else x[i] - delta
            rows.append(x.copy())
    return np.array(rows), delta


def ishigami(x, a=7.0, b=0.1):
    return np.sin(x[:, 0]) + a * np.sin(x[:, 1]) ** 2 + b * x[:, 2] ** 4 * np.sin(x[:, 0])


def write_folder(folder, design, x, metrics, status=None, grid=None, units=None, scene=None):
    """A results folder: design.json, summary.h5, summary.csv. x: (rows, d) factor values in
    case order; metrics {name: (rows,)}; status: (rows,) text (default ok); grid: {key:
    (rows,)} grid coordinates (rows = grid points × design points, sample fastest); scene:
    (rows,) scene names (a scene axis: the scene column alone, as rodend writes it)."""
    os.makedirs(os.path.join(folder, "cases"), exist_ok=True)
    rows, points = len(x), design["points"]
    with open(os.path.join(folder, "design.json"), "w") as fh:
        json.dump(design, fh, indent=1)
    with open(os.path.join(folder, "study.json"), "w") as fh:
        json.dump({"name": os.path.basename(folder), "scene": "synthetic"}, fh)
    cols = {"case_id": np.array([f"c{i:06d}" for i in range(rows)], dtype=object),
            "case_index": np.arange(rows), "scene": np.array(scene if scene is not None else ["synthetic"] * rows, dtype=object)}
    cols.update(grid or {})
    cols["design.sample"] = np.arange(rows) % points
    for j, f in enumerate(design["factors"]):
        cols[f["key"]] = x[:, j]
    cols["status"] = np.array(status if status is not None else ["ok"] * rows, dtype=object)
    cols["message"] = np.array([""] * rows, dtype=object)
    cols["finished_utc"] = np.array(["2026-01-01T00:00:00Z"] * rows, dtype=object)
    cols.update(metrics)
    units = units or {}
    with h5py.File(os.path.join(folder, "summary.h5"), "w") as f:
        g = f.create_group("summary")
        g.attrs["columns"] = json.dumps(list(cols))
        for name, v in cols.items():
            if v.dtype == object:
                g.create_dataset(name, data=v.astype(str).tolist(), dtype=h5py.string_dtype())
            else:
                g.create_dataset(name, data=v)
                g[name].attrs["units"] = units.get(name, "1")
            g[name].attrs["long_name"] = name
    import pandas as pd
    pd.DataFrame(cols).to_csv(os.path.join(folder, "summary.csv"), index=False)
    return folder


def write_case(folder, case_id, time, signals, units, compression=None):
    """A case file as rodend writes it: its case id (root attribute case_id), /signals, and the
    checksum header in its 512-byte user block (docs/results.md, "Crash safety")."""
    path = os.path.join(folder, "cases", f"{case_id}.h5")
    with h5py.File(path, "w", userblock_size=512) as f:
        f.attrs["case_id"] = case_id
        g = f.create_group("signals")
        g.create_dataset("time", data=time)
        g["time"].attrs["units"] = "s"
        for name, v in signals.items():
            g.create_dataset(name, data=v, compression=compression)
            g[name].attrs["units"] = units[name]
    with open(path, "r+b") as fh:
        fh.write(b"RODEND-CHECKSUM 1\n")
    from common import reseal
    reseal(path)
    return path
