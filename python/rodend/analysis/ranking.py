"""Sampling-based importance measures, and the factors of one metric ranked by importance.

Correlation measures (any design with an independent sample: monte-carlo, latin-hypercube,
sobol, the A and B blocks of a saltelli design), point values from OpenTURNS's
CorrelationAnalysis:
  SRC       standardised regression coefficient: the coefficient of a linear least-squares fit
            of y on the factors, times std(x_i) / std(y); its square is factor i's share of the
            variance when the fit is good (r2_linear close to 1) and the factors independent
  PRCC      partial rank correlation: the correlation of the ranks of x_i and y once the ranks
            of the other factors are regressed out; for a monotonic, non-linear effect
  Spearman  the rank correlation of x_i and y, the other factors ignored
Their intervals are bootstrap percentile intervals (the points resampled, numpy, seeded),
computed with numpy: SRC = R_xx⁻¹ r_xy from the correlation matrix R of the values, PRCC from
the regressions of the ranks, Spearman from their correlation matrix (the tests check them
against OpenTURNS). A PRCC whose residual vanishes (the metric a monotonic function of the
factors in a resample) is left out of its interval.

The ranking (`rank`): the design's own measure where it has one, else the best measure of the
sample: saltelli: the total Sobol' index (Saltelli, with its interval); morris: μ* (with its
interval); otherwise the total Sobol' index of the polynomial chaos when its leave-one-out Q² is
at least CHAOS_Q2 and it passed its validation (chaos.py: a withheld chaos never ranks), else
|PRCC| (with its interval). Sorted by that measure, largest first.
"""
import warnings

import numpy as np
import openturns as ot

CHAOS_Q2 = 0.9       # a chaos whose Q² (LOO) is below this does not rank the factors


def _ranks(a):
    """Ranks along axis 0 (ties broken by order: the factors here are continuous or few-valued,
    where the bootstrap's spread dominates)."""
    return np.argsort(np.argsort(a, axis=0, kind="stable"), axis=0).astype(float)


def _partial(r, i):
    """The correlation of column i and the last column of r once the other columns are
    regressed out (least squares with an intercept); NaN where a residual vanishes."""
    others = np.column_stack([np.ones(len(r)), np.delete(r[:, :-1], i, axis=1)])
    res = r[:, [i, -1]] - others @ np.linalg.lstsq(others, r[:, [i, -1]], rcond=None)[0]
    a, b = res[:, 0] - res[:, 0].mean(), res[:, 1] - res[:, 1].mean()
    den = np.sqrt(np.sum(a * a) * np.sum(b * b))
    return float(np.sum(a * b) / den) if den > 1e-12 * len(r) * np.std(r[:, -1]) ** 2 \
        else np.nan


def _from_matrices(x, y):
    """(SRC, PRCC, Spearman): SRC from the correlation matrix of (x, y), PRCC from the
    regressions of the ranks, Spearman the correlation of the ranks."""
    d = x.shape[1]
    with np.errstate(invalid="ignore", divide="ignore"):
        c = np.corrcoef(np.column_stack([x, y]), rowvar=False)
        src = np.linalg.lstsq(c[:d, :d], c[:d, d], rcond=None)[0]
        ranks = np.column_stack([_ranks(x), _ranks(y)])
        cr = np.corrcoef(ranks, rowvar=False)
        prcc = np.array([_partial(ranks, i) for i in range(d)])
        return src, prcc, cr[:d, d]


def _bootstrap(x, y, bootstrap, confidence, seed):
    if bootstrap <= 0 or len(y) < 4:
        return None
    rng = np.random.default_rng(seed)
    reps = [_from_matrices(x[i], y[i]) for i in
            (rng.integers(0, len(y), len(y)) for _ in range(int(bootstrap)))]
    a = (1 - confidence) / 2
    out = []
    for j in range(3):
        vals = np.array([r[j] for r in reps])
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)    # a column of NaN: no interval
            lo, hi = np.nanquantile(vals, [a, 1 - a], axis=0)
        out.append([[float(u), float(v)] if np.isfinite(u) and np.isfinite(v) else None
                    for u, v in zip(lo, hi)])
    return out


def correlations(x, y, bootstrap=200, confidence=0.95, seed=0):
    """SRC, PRCC and Spearman of y on the columns of x (n, d), with bootstrap intervals, and
    r2_linear (the linear fit's R²: how far the SRC can be read as shares of the variance).
    None when there are too few points (n < d + 3) or y is constant."""
    n, d = x.shape
    if n < d + 3 or np.ptp(y) == 0:
        return None
    ca = ot.CorrelationAnalysis(ot.Sample(x), ot.Sample(y.reshape(-1, 1)))
    out = {"n": int(n), "src": list(ca.computeSRC()), "prcc": list(ca.computePRCC()),
           "spearman": list(ca.computeSpearmanCorrelation()),
           "estimator": "OpenTURNS CorrelationAnalysis; intervals: bootstrap percentile"}
    design = np.column_stack([np.ones(n), x])
    fit = design @ np.linalg.lstsq(design, y, rcond=None)[0]
    out["r2_linear"] = 1 - float(np.sum((y - fit) ** 2) / np.sum((y - y.mean()) ** 2))
    ivs = _bootstrap(x, y, bootstrap, confidence, seed)
    for name, iv in zip(("src", "prcc", "spearman"), ivs or [None] * 3):
        out[name + "_interval"] = iv
    return out


def _measure(r):
    """(what, measure key, values, intervals or None, unit kind) of the ranking of a metric's
    result r; None when no measure applies."""
    s, m, c, k = r.get("sobol", {}), r.get("morris"), r.get("chaos", {}), r.get("correlation")
    if "total" in s:
        return ("total Sobol' index (Saltelli)", "sobol_total", s["total"],
                s.get("total_interval"), "1")
    if m:
        return ("μ*, mean |elementary effect| per unit-space step (Morris)", "mu_star",
                m["mu_star"], m.get("mu_star_interval"), "metric")
    q2 = c.get("q2_loo")
    if "total" in c and "withheld" not in c and q2 is not None and q2 >= CHAOS_Q2:
        return (f"total Sobol' index (polynomial chaos, Q² {q2:.3f})", "chaos_total",
                c["total"], None, "1")
    if k:
        iv = k.get("prcc_interval")
        return ("|PRCC|, partial rank correlation", "abs_prcc", [abs(v) for v in k["prcc"]],
                [None if v is None else sorted([abs(v[0]), abs(v[1])]) if v[0] * v[1] > 0
                 else [0.0, max(abs(v[0]), abs(v[1]))] for v in iv] if iv else None, "1")
    return None


def rank(r, keys):
    """The factors of one metric's result r sorted by importance: {by, measure, units,
    factors: [{rank, factor, value, interval}]}, largest first; None when nothing ranks."""
    got = _measure(r)
    if got is None:
        return None
    by, key, values, ivs, kind = got
    order = sorted(range(len(keys)), key=lambda i: -(values[i] if np.isfinite(values[i])
                                                     else -np.inf))
    return {"by": by, "measure": key, "units": r.get("units", "") if kind == "metric" else "1",
            "factors": [{"rank": j + 1, "factor": keys[i], "value": values[i],
                         "interval": ivs[i] if ivs else None} for j, i in enumerate(order)]}
