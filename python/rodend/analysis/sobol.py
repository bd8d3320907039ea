"""First-order and total Sobol indices from a Saltelli pick-freeze design (OpenTURNS).

The design's rows, in sample order, are N rows of A, N of B, then for each factor i N rows of
A with column i taken from B (ot.SobolIndicesExperiment's order). Row r of every block is one
row group: a failed or non-finite case removes its whole row group, and the estimator runs on
the N' complete groups (ot.SaltelliSensitivityAlgorithm(X, Y, N')). The intervals are
OpenTURNS's bootstrap intervals: the N' row groups resampled with replacement B times, the
indices recomputed on each resample, and the interval at the confidence level taken from that
bootstrap distribution.
"""
import numpy as np
import openturns as ot

MIN_GROUPS = 8


def complete_groups(keep, n, d):
    """The row groups r (0..n-1) whose d + 2 rows are all kept."""
    return np.flatnonzero(keep.reshape(d + 2, n).all(axis=0))


def indices(x, y, n, keep, bootstrap=200, confidence=0.95, seed=0):
    """Sobol indices of y from the pick-freeze design x (n (d + 2), d); keep marks the usable
    rows. Returns a dict: first_order, total and their [lower, upper] intervals, groups used
    and removed."""
    d = x.shape[1]
    groups = complete_groups(keep, n, d)
    if len(groups) < MIN_GROUPS:
        raise ValueError(f"saltelli: only {len(groups)} of {n} row groups are complete (every "
                         f"one of their {d + 2} cases ok with a finite value): at least "
                         f"{MIN_GROUPS} are needed")
    rows = (np.arange(d + 2)[:, None] * n + groups[None, :]).ravel()
    ys = y[rows]
    if np.ptp(ys) == 0:
        return {"skipped": "the metric is constant over the design: no variance to share",
                "groups": len(groups), "removed_groups": n - len(groups)}
    ot.RandomGenerator.SetSeed(int(seed))
    algo = ot.SaltelliSensitivityAlgorithm(ot.Sample(x[rows]), ot.Sample(ys.reshape(-1, 1)),
                                           len(groups))
    if bootstrap > 0:  # 0: no intervals (OpenTURNS refuses a bootstrap size of 0)
        algo.setBootstrapSize(int(bootstrap))
        algo.setConfidenceLevel(float(confidence))
    out = {"estimator": "Saltelli (OpenTURNS SaltelliSensitivityAlgorithm)",
           "groups": len(groups), "removed_groups": n - len(groups),
           "first_order": list(algo.getFirstOrderIndices()),
           "total": list(algo.getTotalOrderIndices())}
    if bootstrap > 0:
        for name, iv in (("first_order_interval", algo.getFirstOrderIndicesInterval()),
                         ("total_interval", algo.getTotalOrderIndicesInterval())):
            lo, hi = iv.getLowerBound(), iv.getUpperBound()
            out[name] = [[lo[i], hi[i]] for i in range(d)]
    return out
