"""rodend.analyze and `rodend analyze`: the analysis of a study with a sampled design.

    python3 -m rodend.analyze results/S [--metric M]... [--threshold M=VALUE]...
                              [--history SIGNAL]... [--bootstrap N] [--confidence C]

or rodend.analyze(folder, ...) from Python. For each grid point of the study (each analysed on
its own) and each chosen metric:
  saltelli designs      first-order and total Sobol indices with bootstrap intervals (sobol)
  morris designs        Morris mu, mu*, sigma of unit-space elementary effects (morris)
  monte-carlo, latin-hypercube, sobol designs, and the A and B blocks of a saltelli design:
                        a polynomial-chaos surrogate with its exact leave-one-out Q² and its
                        Sobol indices (chaos); the metric's distribution (mean, std, quantiles
                        5/50/95 %, with intervals) and P(metric > threshold) with the
                        Clopper–Pearson interval (stats)
  the independent sample of any design (the rows its catalogue line names, analysis/catalogue.py;
  a file design's rows too): the same without the chaos when its factors have no distributions
and quantile bands of chosen histories. Failed cases (status not ok) and non-finite values are
left out and counted. Writes FOLDER/analysis/analysis.json, FOLDER/analysis/bands.h5 (histories
asked) and FOLDER/plots/analysis-*.png; prints per metric its spread and its factors ranked by
importance (ranking: the design's measure, else SRC/PRCC/Spearman; table: the printed layout).
"""
import argparse
import os
import sys

import numpy as np

from . import bands as _bands
from . import chaos as _chaos
from . import (clustered, display, factor_figures, figures, inputs, morris, output, ranking,
               sobol, stats)

__all__ = ["analyze", "analyze_arrays", "main"]


def _read_summary(folder):
    """summary.h5, its checksum checked (rodend.open_results). summary.csv alone is refused: it
    carries no checksum, so a damaged value would pass unseen."""
    path = os.path.join(folder, "summary.h5")
    if os.path.isfile(path):
        from ..results import Results
        s = Results(folder).summary
        return s, s.attrs.get("units", {})
    if os.path.isfile(os.path.join(folder, "summary.csv")):
        raise ValueError(f"{path}: missing; rodend analyze reads only summary.h5, whose checksum "
                         "it verifies (summary.csv has none). Write it again from the case files: "
                         f"rodend merge {folder}")
    raise ValueError(f"{folder}: no summary.h5: not a rodend results folder (or its run has not "
                     f"finished: rodend merge {folder} writes the summary from the case files)")


def _chaos_or_why(design, x, y, chaos):
    """The polynomial chaos of the sample, or why there is none."""
    if not inputs.DESIGN_METHODS[design["method"]]["distributions"]:
        return {"skipped": "a design without distributions (the points of a file): the chaos "
                           "needs the factors' distributions"}
    if design.get("correlation"):
        return {"skipped": "correlated factors (its indices assume independent ones)"}
    if np.ptp(y) <= 0:
        return {"skipped": "the metric is constant over the sample"}
    return _chaos.fit(design, x, y, chaos)


def analyze_arrays(design, x, y, keep, confidence=0.95, bootstrap=200, thresholds=(),
                   chaos="auto", seed=0):
    """The analysis of one metric at one grid point from arrays: x (points, d) the factor
    values in design.sample order, y (points,) the metric, keep (points,) the usable cases.
    Returns the dict analysis.json holds for it (plus loo_prediction and iid values for the
    figures)."""
    n = int(design["size"])
    keep = np.asarray(keep, dtype=bool) & np.isfinite(y)
    out = {}
    if design["method"] == "saltelli":
        out["sobol"] = sobol.indices(x, y, n, keep, bootstrap, confidence, seed)
    if design["method"] == "morris":
        unit = np.asarray(design["unit_points"], dtype=float)
        out["morris"] = morris.statistics(unit, y, n, float(design["delta"]), keep, bootstrap,
                                          confidence, seed)
    rows = inputs.iid_rows(design)
    rows = rows[keep[rows]]
    if len(rows):
        yi = y[rows]
        out["distribution"] = stats.distribution(yi, confidence, bootstrap, seed)
        out["exceedance"] = [stats.exceedance(yi, t, confidence) for t in thresholds]
        out["chaos"] = _chaos_or_why(design, x[rows], yi, chaos)
        out["_iid"] = yi
        out["correlation"] = ranking.correlations(x[rows], yi, bootstrap, confidence, seed)
    elif design["method"] == "morris":
        used = np.flatnonzero(keep)
        out["distribution"], out["exceedance"] = clustered.spread(
            y[used], used // (x.shape[1] + 1), thresholds, confidence, bootstrap, seed)
        out["_iid"] = y[used]
    else:
        raise ValueError("no usable case left (every case failed or is non-finite)")
    out["_points"] = (x[keep], y[keep])
    return out


def _analyze_metric(design, rows, m, units, opts, thresholds):
    y = rows[m].to_numpy(dtype=float)
    ok = inputs.ok_mask(rows)
    r = analyze_arrays(design, inputs.factor_matrix(rows, design), y, ok, opts["confidence"],
                       opts["bootstrap"], thresholds.get(m, ()), opts["chaos"], opts["seed"])
    r.update(units=units.get(m, ""), failed=int(np.sum(~ok)),
             non_finite=int(np.sum(ok & ~np.isfinite(y))),
             used=int(np.sum(ok & np.isfinite(y))))
    r["ranking"] = ranking.rank(r, [f["key"] for f in design["factors"]])
    r["shown"] = dict(zip(("units", "factor"), display.unit(r["units"])))
    return r


def _figures(folder, design, coords, suffix, m, r):
    keys, units = [f["key"] for f in design["factors"]], r["units"]
    where = figures.where(coords)
    title = m + (f", {where}" if where else "")
    paths = []
    s, c = r.get("sobol", {}), r.get("chaos", {})
    sets = []
    if "first_order" in s:
        sets += [("first order (Saltelli)", s["first_order"], s.get("first_order_interval")),
                 ("total (Saltelli)", s["total"], s.get("total_interval"))]
    if "first_order" in c:
        sets += [("first order (chaos)", c["first_order"], None),
                 ("total (chaos)", c["total"], None)]
    if sets and len(keys) > 1:
        paths.append(figures.indices(folder, f"{m}-indices{suffix}", title, keys, sets))
    if "_points" in r:
        paths.append(factor_figures.scatter(folder, f"{m}-scatter{suffix}", title, m,
                                            design["factors"], *r["_points"], units,
                                            r.get("ranking")))
    if "morris" in r:
        paths.append(figures.morris(folder, f"{m}-morris{suffix}", title, keys, r["morris"],
                                    units))
    if "_iid" in r:
        paths.append(figures.cdf(folder, f"{m}-cdf{suffix}", title, r["_iid"], units,
                                 r["exceedance"]))
    if c.get("loo_prediction") is not None:
        paths.append(figures.chaos(folder, f"{m}-chaos{suffix}", title, r["_chaos_y"],
                                   c["loo_prediction"], c["q2_loo"], units,
                                   c.get("validation") if "withheld" in c else None))
    return paths


def _group(folder, design, coords, rows, metrics, units, thresholds, opts, suffix):
    result = {"grid": coords, "cases": len(rows),
              "failed": int(np.sum(~inputs.ok_mask(rows))), "metrics": {}}
    for m in metrics:
        try:
            r = _analyze_metric(design, rows, m, units, opts, thresholds)
        except ValueError as e:
            where = f" at {coords}" if coords else ""
            raise ValueError(f"metric {m}{where}: {e}") from None
        if "_iid" in r and "loo_prediction" in r.get("chaos", {}):
            r["_chaos_y"] = r["_iid"]
        if opts["plots"]:
            result.setdefault("figures", []).extend(
                _figures(folder, design, coords, suffix, m, r))
        for k in ("_iid", "_chaos_y", "_points"):
            r.pop(k, None)
        r.get("chaos", {}).pop("loo_prediction", None)
        result["metrics"][m] = r
    return result


def _histories(folder, coords, rows, signals, opts, suffix):
    ok = rows["case_id"].to_numpy()[inputs.ok_mask(rows)]
    out = _bands.bands(folder, list(ok), list(dict.fromkeys(signals)))
    if opts["plots"]:
        where = figures.where(coords)
        for sig, b in out.items():
            figures.band(folder, f"{sig}-bands{suffix}", sig + (f", {where}" if where else ""), b)
    return out


def analyze(folder, metrics=None, thresholds=None, histories=None, bootstrap=200,
            confidence=0.95, chaos="auto", plots=True, quiet=False):
    """Analyses the results folder of a designed study; returns the analysis.json document.

    metrics: names of metric columns (default: every one with a finite value); thresholds:
    {metric: value or [values]} or ["metric=value", ...]; histories: signal names for quantile
    bands; bootstrap: resamples of the bootstrap intervals; confidence: their level; chaos:
    "least-squares" (degree by exact LOO), "lars" (OpenTURNS's sparse LARS, slow at 1e4) or
    "auto" (both when LARS is cheap, the larger Q² kept);
    plots: write FOLDER/plots/analysis-*.png; quiet: print nothing.
    Raises ValueError for a bad input (naming what was expected)."""
    folder = os.fspath(folder)
    design = inputs.read_design(folder)
    if not 0 < confidence < 1:
        raise ValueError(f"confidence {confidence}: expected a level in (0, 1), e.g. 0.95")
    if int(bootstrap) < 0:
        raise ValueError(f"bootstrap {bootstrap}: expected a number of resamples >= 0")
    if chaos not in ("auto", "least-squares", "lars"):
        raise ValueError(f"chaos {chaos!r}: expected auto, least-squares or lars")
    summary, units = _read_summary(folder)
    metrics = inputs.choose_metrics(summary, design, metrics)
    thresholds = inputs.parse_thresholds(thresholds, metrics)
    groups = inputs.groups(summary, design)
    opts = {"bootstrap": int(bootstrap), "confidence": float(confidence), "chaos": chaos,
            "plots": plots, "seed": int(design.get("seed", 0) or 0)}
    doc = {"folder": folder, "confidence": confidence, "bootstrap": int(bootstrap),
           "design": {k: design[k] for k in design if k not in ("unit_points", "factors")},
           "groups": []}
    doc["design"]["factor_keys"] = [f["key"] for f in design["factors"]]
    doc["design"]["factors"] = design["factors"]
    all_bands = []
    for k, (coords, rows) in enumerate(groups):
        suffix = f"-g{k}" if len(groups) > 1 else ""
        doc["groups"].append(_group(folder, design, coords, rows, metrics, units, thresholds,
                                    opts, suffix))
        if histories:
            all_bands.append((coords, _histories(folder, coords, rows, histories, opts, suffix)))
    if all_bands:
        doc["bands_file"] = output.write_bands(folder, all_bands)
    doc["analysis_file"] = os.path.join(folder, "analysis", "analysis.json")
    output.write_json(folder, doc)
    if not quiet:
        print(output.table(doc))
    return doc


def _parser():
    p = argparse.ArgumentParser(prog="rodend analyze", description=__doc__.split("\n\n")[0])
    p.add_argument("folder", help="a results folder (results/S) of a study with a design")
    p.add_argument("--metric", action="append", help="a metric to analyse (repeatable; "
                   "default: every metric with a finite value)")
    p.add_argument("--threshold", action="append", default=[],
                   help="METRIC=VALUE: report P(metric > VALUE) (repeatable)")
    p.add_argument("--history", action="append", help="a signal for quantile bands (repeatable)")
    p.add_argument("--bootstrap", type=int, default=200, help="bootstrap resamples (200)")
    p.add_argument("--confidence", type=float, default=0.95, help="interval level (0.95)")
    p.add_argument("--chaos", default="auto", choices=("auto", "least-squares", "lars"),
                   help="how the chaos's terms are chosen (auto: least squares, and sparse LARS "
                        "too when cheap, the better Q² kept)")
    p.add_argument("--no-plots", action="store_true", help="write no figures")
    return p


def main(argv=None):
    a = _parser().parse_args(argv)
    try:
        analyze(a.folder, a.metric, a.threshold, a.history, a.bootstrap, a.confidence, a.chaos,
                plots=not a.no_plots)
    except (ValueError, OSError) as e:  # CorruptFile is a ValueError, a missing file an OSError
        print(f"rodend analyze: {e}", file=sys.stderr)
        return 2
    return 0
