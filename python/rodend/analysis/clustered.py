"""A metric's spread over the points of a Morris design, with intervals from its trajectories.

A Morris design is not a sample of the factors' distributions: its points lie on a grid of
levels in unit space (0, 1/(p − 1), ..., 1: the bands' ends carry as much weight as their
middle) and the d + 1 points of a trajectory are dependent. The mean, standard deviation,
5/50/95 % quantiles and P(metric > threshold) over its points still tell where the metric lies
over the bands, and are labelled as such. Their intervals resample whole trajectories (the
independent units) with replacement, numpy seeded: a percentile bootstrap over clusters, so
they account for the dependence within a trajectory. The keys are those of stats.distribution
and stats.exceedance.
"""
import numpy as np

from .stats import QUANTILES


def _weighted_quantile(ys, cw, p):
    """The p-quantile of sorted values ys with cumulative weights cw (replicates × points)."""
    idx = (cw < p * cw[:, -1:]).sum(axis=1)
    return ys[np.minimum(idx, len(ys) - 1)]


def _replicates(traj, bootstrap, seed):
    """Weights (bootstrap × points): how often each point's trajectory was drawn."""
    ids, inverse = np.unique(traj, return_inverse=True)
    rng = np.random.default_rng(seed)
    draws = rng.integers(0, len(ids), size=(int(bootstrap), len(ids)))
    counts = np.stack([np.bincount(r, minlength=len(ids)) for r in draws])
    return counts[:, inverse].astype(float)


def spread(y, traj, thresholds=(), confidence=0.95, bootstrap=200, seed=0):
    """(distribution, [exceedance]) of y (finite values) over design points whose trajectory
    numbers are traj; intervals None when bootstrap is 0 or fewer than 2 trajectories."""
    n = len(y)
    if n < 2:
        raise ValueError(f"{n} usable value(s): a distribution needs at least 2")
    order = np.argsort(y, kind="stable")
    ys, traj = y[order], np.asarray(traj)[order]
    a = (1 - confidence) / 2
    dist = {"n": n, "sample": "Morris design points (on a grid of levels: not a sample of the distributions)",
            "trajectories": int(len(np.unique(traj))), "mean": float(y.mean()),
            "std": float(y.std(ddof=1)), "min": float(ys[0]), "max": float(ys[-1]),
            "quantiles": {f"{p:g}": float(np.quantile(ys, p)) for p in QUANTILES}}
    exc = [{"threshold": float(t), "exceed": int(np.sum(y > t)), "n": n,
            "probability": float(np.mean(y > t))} for t in thresholds]
    w = _replicates(traj, bootstrap, seed) if bootstrap > 0 and \
        dist["trajectories"] >= 2 else None
    kind = "bootstrap over trajectories" if w is not None else None
    dist.update(mean_interval_kind=kind, std_interval_kind=kind, quantile_interval_kind=kind)
    if w is None:
        dist.update(mean_interval=None, std_interval=None,
                    quantile_intervals={f"{p:g}": None for p in QUANTILES})
        for e in exc:
            e.update(interval=None, interval_kind=None)
        return dist, exc
    tot = w.sum(axis=1)
    mean = w @ ys / tot
    var = (w * (ys[None, :] - mean[:, None]) ** 2).sum(axis=1) / np.maximum(tot - 1, 1)
    cw = np.cumsum(w, axis=1)
    iv = lambda v: [float(q) for q in np.quantile(v, [a, 1 - a])]  # noqa: E731
    dist.update(mean_interval=iv(mean), std_interval=iv(np.sqrt(var)),
                quantile_intervals={f"{p:g}": iv(_weighted_quantile(ys, cw, p))
                                    for p in QUANTILES})
    for e in exc:
        e.update(interval=iv(w @ (ys > e["threshold"]) / tot), interval_kind=kind)
    return dist, exc
