"""analysis.json, bands.h5 and the table printed to stdout."""
import json
import math
import os

import h5py
import numpy as np

from ..atomic import atomic_file


def _plain(v):
    if isinstance(v, dict):
        return {str(k): _plain(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [_plain(x) for x in v]
    if isinstance(v, np.ndarray):
        return _plain(v.tolist())
    if isinstance(v, (np.integer,)):
        return int(v)
    if isinstance(v, (float, np.floating)):
        return None if not math.isfinite(float(v)) else float(v)
    return v


def write_json(folder, doc):
    path = os.path.join(folder, "analysis", "analysis.json")
    text = json.dumps(_plain(doc), indent=1, allow_nan=False) + "\n"
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
            g.attrs["coordinates_json"] = json.dumps(_plain(coords))
            for name, b in bands.items():
                s = g.create_group(name)
                s.attrs["cases"] = b["cases"]
                s.attrs["resampled"] = b["resampled"]
                for ds, data, units in (("time", b["time"], "s"), ("levels", b["levels"], "1"),
                                        ("quantiles", b["quantiles"], b["units"])):
                    s.create_dataset(ds, data=np.asarray(data, dtype=float))
                    s[ds].attrs["units"] = units
    return path


def _intervals(doc):
    """"95% intervals", "99.9% intervals" (never rounded up to 100%), or none with --bootstrap 0
    (the Sobol and Morris intervals are bootstrap intervals)."""
    if doc["bootstrap"] == 0:
        return "no intervals (bootstrap 0)"
    return f"{100 * doc['confidence']:.10g}% intervals"


def _iv(v, iv):
    return f"{v:8.4f}" + (f" [{iv[0]:7.4f}, {iv[1]:7.4f}]" if iv else " " * 19)


def table(doc):
    """The indices with their intervals, as lines of text."""
    lines = []
    for g in doc["groups"]:
        where = ", ".join(f"{k} = {v}" for k, v in g["grid"].items())
        for m, r in g["metrics"].items():
            lines.append(f"\n{m} [{r['units']}]" + (f" at {where}" if where else "")
                         + f": {r['used']} cases used, {r['failed']} failed, "
                           f"{r['non_finite']} non-finite")
            keys = doc["design"]["factor_keys"]
            width = max(len(k) for k in keys)
            if "sobol" in r and "first_order" in r["sobol"]:
                s = r["sobol"]
                lines.append(f"  Sobol (Saltelli, {s['groups']} row groups, "
                             f"{s['removed_groups']} removed), "
                             f"{_intervals(doc)}")
                lines.append(f"  {'factor':<{width}}  {'first order':<27}  total")
                for i, k in enumerate(keys):
                    lines.append(f"  {k:<{width}}  "
                                 f"{_iv(s['first_order'][i], (s.get('first_order_interval') or [None] * len(keys))[i])}"
                                 f"  {_iv(s['total'][i], (s.get('total_interval') or [None] * len(keys))[i])}")
            if "morris" in r:
                s = r["morris"]
                lines.append("  Morris (effects per unit-space step), "
                             f"{_intervals(doc)}")
                lines.append(f"  {'factor':<{width}}  {'mu':>10}  {'mu*':>10}{'':23}  {'sigma':>10}"
                             "  effects")
                for i, k in enumerate(keys):
                    iv = s["mu_star_interval"][i]
                    star = f"{s['mu_star'][i]:10.4g}" + \
                        (f" [{iv[0]:9.4g}, {iv[1]:9.4g}]" if iv else " " * 23)
                    lines.append(f"  {k:<{width}}  {s['mu'][i]:10.4g}  {star}  "
                                 f"{s['sigma'][i]:10.4g}  {s['effects'][i]}")
            c = r.get("chaos", {})
            if "first_order" in c:
                lines.append(f"  chaos ({c['method']}, {c['terms']} terms, degree {c['degree']}, "
                             f"Q2 LOO = {c['q2_loo']:.4f})")
                for i, k in enumerate(keys):
                    lines.append(f"  {k:<{width}}  {c['first_order'][i]:8.4f}  "
                                 f"{' ' * 19}{c['total'][i]:8.4f}")
            elif "withheld" in c:
                lines.append(f"  chaos ({c['method']}): indices withheld: {c['validation']}")
            for e in r.get("exceedance", []):
                lines.append(f"  P({m} > {e['threshold']:g}) = {e['probability']:.4g} "
                             f"[{e['interval'][0]:.4g}, {e['interval'][1]:.4g}] "
                             f"({e['exceed']} of {e['n']})")
    return "\n".join(lines).lstrip("\n")
