"""A metric's distribution from an iid sample: mean, std, quantiles, exceedance probabilities,
each with an interval at the confidence level.

mean      Student-t interval: mean ± t_(n-1) s / sqrt(n)
std       bootstrap percentile interval (the sample resampled with replacement, numpy, seeded)
quantile  distribution-free order-statistic interval: [x_(l), x_(u)] with l, u the
          (1-c)/2 and (1+c)/2 quantiles of Binomial(n, p) (1-based ranks l and u + 1),
          which covers the p-quantile with probability >= c for any continuous distribution;
          null where n is too small for a rank to exist
exceedance P(y > threshold) = k / n with the Clopper–Pearson (exact binomial) interval:
          [qBeta(k, n - k + 1; (1-c)/2), qBeta(k + 1, n - k; (1+c)/2)], 0 and 1 at k = 0, n
The intervals assume independent draws (monte-carlo; the A and B blocks of a saltelli design).
Latin-hypercube and Sobol points are not independent: their mean is usually more precise than
these intervals say, so there the intervals are conservative for the mean.
"""
import math

import numpy as np
import openturns as ot

QUANTILES = (0.05, 0.5, 0.95)


def _quantile_interval(sorted_y, p, confidence):
    n = len(sorted_y)
    binom = ot.Binomial(n, p)
    a = (1 - confidence) / 2
    lo = int(binom.computeQuantile(a)[0])          # rank lo (1-based) is x_(lo)
    hi = int(binom.computeQuantile(1 - a)[0]) + 1  # rank hi
    return [float(sorted_y[lo - 1]) if lo >= 1 else None,
            float(sorted_y[hi - 1]) if hi <= n else None]


def _std_interval(y, bootstrap, confidence, seed):
    if bootstrap <= 0 or len(y) < 2:
        return None
    rng = np.random.default_rng(seed)
    stds, chunk = [], max(1, 2_000_000 // len(y))
    for start in range(0, int(bootstrap), chunk):
        m = min(chunk, int(bootstrap) - start)
        stds.append(y[rng.integers(0, len(y), size=(m, len(y)))].std(axis=1, ddof=1))
    a = (1 - confidence) / 2
    return np.quantile(np.concatenate(stds), [a, 1 - a]).tolist()


def distribution(y, confidence=0.95, bootstrap=200, seed=0):
    """Mean, std and quantiles of y (finite values), with intervals."""
    n = len(y)
    if n < 2:
        raise ValueError(f"{n} usable value(s): a distribution needs at least 2")
    mean, std = float(y.mean()), float(y.std(ddof=1))
    half = ot.DistFunc.qStudent(n - 1, (1 + confidence) / 2) * std / math.sqrt(n)
    s = np.sort(y)
    return {"n": n, "mean": mean, "mean_interval": [mean - half, mean + half], "std": std,
            "std_interval": _std_interval(y, bootstrap, confidence, seed),
            "min": float(s[0]), "max": float(s[-1]),
            "quantiles": {f"{p:g}": float(np.quantile(s, p)) for p in QUANTILES},
            "quantile_intervals": {f"{p:g}": _quantile_interval(s, p, confidence)
                                   for p in QUANTILES},
            "mean_interval_kind": "Student t", "std_interval_kind": "bootstrap percentile",
            "quantile_interval_kind": "order statistics (binomial, distribution-free)"}


def clopper_pearson(k, n, confidence):
    """The exact (Clopper–Pearson) interval of a binomial proportion k / n."""
    a = (1 - confidence) / 2
    lo = 0.0 if k == 0 else ot.DistFunc.qBeta(k, n - k + 1, a)
    hi = 1.0 if k == n else ot.DistFunc.qBeta(k + 1, n - k, 1 - a)
    return [float(lo), float(hi)]


def exceedance(y, threshold, confidence=0.95):
    """P(y > threshold) with its Clopper–Pearson interval."""
    k, n = int(np.sum(y > threshold)), len(y)
    return {"threshold": float(threshold), "exceed": k, "n": n, "probability": k / n,
            "interval": clopper_pearson(k, n, confidence), "interval_kind": "Clopper-Pearson"}
