"""The prognosis: the posterior carried through the wear evolution (docs/wear.md) under a
stated duty cycle, to the distribution of cycles until the axial clearance or the surface
backlash reaches a limit (docs/health-monitoring.md#prognosis).

The wear evolution itself (rodend's own loop, `wear_evolution` of a study) runs at a few
clearances: the posterior's quantiles (`quantiles`, default 1, 50 and 99 %) of the clearance,
the other carried unknowns at their posterior medians. Each run gives its cycles to the limit;
each posterior sample's cycles are then interpolated linearly in its clearance between those
runs (extrapolated linearly beyond the outer two). That is exact at the runs and assumes the
cycles to the limit vary smoothly with the starting clearance over the posterior's range, which
is narrow: the runs themselves show how much they vary. A run that fails (the integrator on a
deeply worn surface) is reported and left out when two others remain."""
import os

import numpy as np

from . import forward
from .config import ConfigError

KEYS = ("study", "wear_evolution", "limit", "quantiles", "cycle_name", "cycles_per_hour",
        "carry", "description")
CLEARANCE = "parameters.contact.clearance"


def check(path, p, unknown_keys):
    """The prognosis block, checked when the configuration is loaded."""
    where = "prognosis"
    if not isinstance(p, dict):
        raise ConfigError(f"{path}: {where}: expected an object")
    for k in p:
        if k not in KEYS:
            raise ConfigError(f"{path}: {where}.{k}: unknown key; expected one of "
                              + ", ".join(f'"{a}"' for a in KEYS))
    for k in ("study", "limit"):
        if not isinstance(p.get(k), dict):
            raise ConfigError(f"{path}: {where}.{k}: missing: an object")
    lim = p["limit"]
    if len(lim) != 1 or next(iter(lim)) not in ("axial_clearance", "surface_backlash") or \
            not isinstance(next(iter(lim.values())), (int, float)) or \
            not next(iter(lim.values())) > 0:
        raise ConfigError(f"{path}: {where}.limit: expected {{\"axial_clearance\": m}} or "
                          "{\"surface_backlash\": rad}, a value > 0")
    carry = p.get("carry", [CLEARANCE])
    if CLEARANCE not in carry:
        raise ConfigError(f"{path}: {where}.carry: expected a list holding {CLEARANCE}")
    for i, k in enumerate(carry):
        if k not in unknown_keys:
            raise ConfigError(f"{path}: {where}.carry[{i}]: '{k}' is not one of the unknowns")
    q = p.get("quantiles", [0.01, 0.5, 0.99])
    if not isinstance(q, list) or len(q) < 2 or sorted(q) != q or \
            not all(isinstance(x, (int, float)) and 0 < x < 1 for x in q):
        raise ConfigError(f"{path}: {where}.quantiles: expected an increasing list of at "
                          "least two levels in (0, 1)")


def _study(cfg, values):
    p = cfg["prognosis"]
    name, lim = next(iter(p["limit"].items()))
    doc = {"name": "prognosis", **{k: v for k, v in p["study"].items()}}
    doc["wear_evolution"] = dict(p.get("wear_evolution", {}))
    doc["wear_evolution"]["clearance_limit" if name == "axial_clearance"
                          else "backlash_limit"] = lim
    params = doc.setdefault("parameters", {})
    for k, v in values.items():
        if k != CLEARANCE:
            params[k[len("parameters."):]] = float(v)
    doc["grid"] = [{"key": CLEARANCE, "values": [float(x) for x in values[CLEARANCE]]}]
    return doc


def run(cfg, flat, scratch):
    """The prognosis of the posterior samples `flat` (n, unknowns)."""
    import time
    t0 = time.monotonic()
    p = cfg["prognosis"]
    keys = [u["key"] for u in cfg["unknowns"]]
    ic = keys.index(CLEARANCE)
    levels = p.get("quantiles", [0.01, 0.5, 0.99])
    values = {k: np.median(flat[:, keys.index(k)]) for k in p.get("carry", [CLEARANCE])}
    values[CLEARANCE] = np.unique(np.quantile(flat[:, ic], levels))
    folder = forward.run_allow_failures(_study(cfg, values), scratch, cfg)
    runs = []
    for cid, row in forward.case_rows(folder):
        runs.append({"clearance": float(row[CLEARANCE]), "status": row["status"],
                     "cycles_to_limit": float(row["cycles_to_limit"]),
                     "wear_updates": float(row["wear_updates"])})
    runs.sort(key=lambda r: r["clearance"])
    c = np.array([r["clearance"] for r in runs])
    n = np.array([r["cycles_to_limit"] for r in runs])
    name, lim = next(iter(p["limit"].items()))
    out = {"limit_name": name.replace("_", " "), "limit": lim,
           "unit": "m" if name == "axial_clearance" else "rad",
           "cycle_name": p.get("cycle_name", "duty cycles"), "runs": runs,
           "duty_cycle": p.get("description", ""), "carried": {k: v for k, v in values.items()
                                                              if k != CLEARANCE}}
    ok = np.isfinite(n)
    if np.sum(ok) < min(2, len(n)):
        out["problem"] = ("the wear evolution reached the limit in fewer than two runs (see "
                          "prognosis.runs: failed runs, or raise "
                          "prognosis.wear_evolution.max_cycles or max_updates)")
        ok[:] = True
    elif not np.all(ok):
        out["note"] = (f"{int(np.sum(~ok))} of {len(n)} runs did not reach the limit (see "
                       "runs); the cycles are interpolated between the others")
    cycles = _interpolate(flat[:, ic], c[ok], n[ok])
    out["cycles_to_limit"] = {"q05": float(np.nanquantile(cycles, 0.05)),
                              "q50": float(np.nanquantile(cycles, 0.5)),
                              "q95": float(np.nanquantile(cycles, 0.95)),
                              "mean": float(np.nanmean(cycles))}
    if p.get("cycles_per_hour"):
        out["hours_to_limit"] = {k: v / float(p["cycles_per_hour"])
                                 for k, v in out["cycles_to_limit"].items()}
    out["seconds"] = time.monotonic() - t0
    out["_cycles"] = cycles[np.isfinite(cycles)]
    return out


def _interpolate(x, c, n):
    """n(x) piecewise linear through the runs (c, n), extrapolated linearly past the ends,
    never below 0; a single run: that run's value."""
    if len(c) == 1:
        return np.full(len(x), n[0])
    y = np.interp(x, c, n)
    lo, hi = x < c[0], x > c[-1]
    y[lo] = n[0] + (x[lo] - c[0]) * (n[1] - n[0]) / (c[1] - c[0])
    y[hi] = n[-1] + (x[hi] - c[-1]) * (n[-1] - n[-2]) / (c[-1] - c[-2])
    return np.maximum(y, 0.0)
