"""Reading a designed study's results folder: design.json, the summary, the grid groups."""
import difflib
import json
import math
import os

import numpy as np

from .catalogue import DESIGN_METHODS, RECORD_COLUMNS

METHODS = tuple(DESIGN_METHODS)


def read_design(folder):
    """design.json of a results folder, checked: a dict with method, size, points, factors."""
    path = os.path.join(folder, "design.json")
    if not os.path.isdir(folder):
        raise FileNotFoundError(f"{folder}: no such folder (a study's results folder: "
                                "`rodend results-dir STUDY.json` names it)")
    if not os.path.isfile(path):
        raise ValueError(f"{folder}: no design.json: rodend analyze needs the results of a study "
                         f"with a sampled design (a `design` block: {', '.join(METHODS)})")
    with open(path, encoding="utf-8") as fh:
        try:
            d = json.load(fh)
        except json.JSONDecodeError as e:
            raise ValueError(f"{path}: not valid JSON ({e})") from None
    if d.get("method") not in METHODS:
        raise ValueError(f"{path}: method {d.get('method')!r}: expected one of {', '.join(METHODS)}")
    for key in ("size", "points", "factors"):
        if key not in d:
            raise ValueError(f"{path}: no {key!r}: expected size, points and factors")
    method = DESIGN_METHODS[d["method"]]
    need = ("key", "distribution") if method["distributions"] else ("key",)
    if not d["factors"] or any(k not in f for f in d["factors"] for k in need):
        raise ValueError(f"{path}: factors: expected a non-empty list of "
                         f"{{{', '.join(need)}, ...}}")
    n, dim = int(d["size"]), len(d["factors"])
    expected = n * (method["per_factor"] * dim + method["extra"])
    if int(d["points"]) != expected:
        raise ValueError(f"{path}: points {d['points']}: expected {expected} for {d['method']} "
                         f"with size {n} and {dim} factors")
    if d["method"] == "morris":
        u = np.asarray(d.get("unit_points", []), dtype=float)
        if u.shape != (expected, dim) or "delta" not in d:
            raise ValueError(f"{path}: morris: expected delta and unit_points of shape "
                             f"({expected}, {dim}), got {u.shape}")
    return d


def metric_columns(summary, design):
    """The metric columns of a summary: every numeric column that is not a field of the case
    record (sweep/case_record.def), a grid coordinate, design.sample or a factor, wherever it
    stands."""
    skip = set(RECORD_COLUMNS) | set(grid_keys(summary)) | {"design.sample"} \
        | {f["key"] for f in design["factors"]}
    return [c for c in summary.columns if c not in skip and summary[c].dtype.kind in "fiu"]


def iid_rows(design):
    """The rows that are an independent sample of the factors: the first iid_blocks x size of
    the method's catalogue line (all of a monte-carlo design, A and B of a saltelli design, none
    of a morris design)."""
    return np.arange(DESIGN_METHODS[design["method"]]["iid_blocks"] * int(design["size"]))


def grid_keys(summary):
    """The grid-key columns: between scene and design.sample, and scene itself when it takes
    more than one value (a scene axis has no column of its own: docs/studies.md)."""
    cols = list(summary.columns)
    if "design.sample" not in cols:
        raise ValueError("the summary has no column design.sample: not the results of a study "
                         "with a sampled design")
    start = cols.index("scene") + 1 if "scene" in cols else 0
    scene = ["scene"] if "scene" in cols and summary["scene"].nunique() > 1 else []
    return scene + cols[start:cols.index("design.sample")]


def choose_metrics(summary, design, metrics):
    """The metrics to analyse: the named ones (checked, nearest names on a typo) or every metric
    column with a finite value."""
    known = metric_columns(summary, design)
    if not metrics:
        chosen = [m for m in known if np.isfinite(summary[m].to_numpy(dtype=float)).any()]
        if not chosen:
            raise ValueError("no metric column has a finite value: nothing to analyse")
        return chosen
    for m in metrics:
        if m not in known:
            near = difflib.get_close_matches(m, known, n=3)
            hint = f"; nearest: {', '.join(near)}" if near else \
                f"; the metrics are: {', '.join(known)}"
            raise ValueError(f"unknown metric {m!r}{hint}")
    return list(dict.fromkeys(metrics))


def parse_thresholds(thresholds, metrics):
    """{metric: [values]} from a dict {metric: value or [values]} or strings "metric=value"."""
    out = {}
    if thresholds is None:
        return out
    items = thresholds.items() if isinstance(thresholds, dict) else \
        [_split_threshold(t) for t in thresholds]
    for m, v in items:
        if m not in metrics:
            near = difflib.get_close_matches(m, metrics, n=3)
            raise ValueError(f"threshold on {m!r}: not an analysed metric"
                             + (f"; nearest: {', '.join(near)}" if near else
                                f"; the analysed metrics are: {', '.join(metrics)}"))
        for x in (v if isinstance(v, (list, tuple)) else [v]):
            if not isinstance(x, (int, float)) or not math.isfinite(x):
                raise ValueError(f"threshold on {m}: {x!r}: expected a finite number")
            out.setdefault(m, []).append(float(x))
    return out


def _split_threshold(text):
    metric, sep, value = str(text).partition("=")
    try:
        if not sep or not metric.strip():
            raise ValueError
        return metric.strip(), float(value)
    except ValueError:
        raise ValueError(f"threshold {text!r}: expected METRIC=VALUE, e.g. "
                         "max_contact_force=2000") from None


def groups(summary, design):
    """[(grid coordinates {key: value}, rows sorted by design.sample)], one per grid point,
    in case order; each group holds exactly the design's points."""
    keys = grid_keys(summary)
    s = summary.sort_values("case_index", kind="stable") if "case_index" in summary else summary
    by = keys[0] if len(keys) == 1 else keys
    parts = [({}, s)] if not keys else \
        [(dict(zip(keys, k if isinstance(k, tuple) else (k,))), g)
         for k, g in s.groupby(by, sort=False)]
    out, points = [], int(design["points"])
    for coords, g in parts:
        g = g.sort_values("design.sample", kind="stable")
        if not np.array_equal(g["design.sample"].to_numpy(), np.arange(points)):
            where = f" at {coords}" if coords else ""
            raise ValueError(f"the summary{where} has {len(g)} rows whose design.sample is not "
                             f"0..{points - 1}: expected one row per design point")
        out.append((coords, g.reset_index(drop=True)))
    return out


def factor_matrix(rows, design):
    """The factor values used (one column per factor key), as a float array (points, d)."""
    keys = [f["key"] for f in design["factors"]]
    missing = [k for k in keys if k not in rows]
    if missing:
        raise ValueError(f"the summary has no column for the factor(s) {', '.join(missing)}")
    return rows[keys].to_numpy(dtype=float)


def ok_mask(rows):
    """True for the rows whose case is ok (no status column: every row)."""
    if "status" not in rows:
        return np.ones(len(rows), dtype=bool)
    return (rows["status"].astype(str) == "ok").to_numpy()
