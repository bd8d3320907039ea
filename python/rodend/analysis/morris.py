"""Morris elementary effects from the design's unit-space trajectories.

Trajectory t is the rows t (d + 1) .. t (d + 1) + d; step k >= 1 moves one factor i by ±delta
in unit space (the factor's CDF value, design.json's unit_points). Its elementary effect is
EE = (y_k - y_{k-1}) / (±delta): the change of the metric per unit of the factor's unit-space
coordinate, so the effects of factors in different units compare directly. For a uniform
factor on [a, b], an effect per physical unit is EE / (b - a). For each factor, over its
effects: mu (the mean), mu* (the mean of |EE|: the overall influence) and sigma (the standard
deviation, ddof 1: interactions and non-linearity). An effect whose either end failed or is
non-finite is left out; the intervals of mu* and sigma are bootstrap percentile intervals over
the factor's effects (numpy, seeded).
"""
import numpy as np

MIN_EFFECTS = 2


def effects(unit, y, n, delta, keep):
    """([factor index], [EE], [kept]) of every step of the n trajectories."""
    d = unit.shape[1]
    factor, ee, ok = [], [], []
    for t in range(n):
        for k in range(1, d + 1):
            a, b = t * (d + 1) + k - 1, t * (d + 1) + k
            step = unit[b] - unit[a]
            moved = np.flatnonzero(np.abs(step) > 1e-12)
            if len(moved) != 1 or abs(abs(step[moved[0]]) - delta) > 1e-9:
                raise ValueError(f"morris: design points {a} and {b} (trajectory {t}, step {k}) "
                                 f"differ by {step.tolist()} in unit space: expected one factor "
                                 f"moved by ±{delta}")
            i = int(moved[0])
            factor.append(i)
            ee.append((y[b] - y[a]) / step[i])
            ok.append(bool(keep[a] and keep[b] and np.isfinite(y[a]) and np.isfinite(y[b])))
    return np.array(factor), np.array(ee), np.array(ok)


def _bootstrap(e, bootstrap, confidence, rng):
    if bootstrap <= 0 or len(e) < 2:
        return None, None
    idx = rng.integers(0, len(e), size=(int(bootstrap), len(e)))
    s = e[idx]
    a = (1 - confidence) / 2
    star = np.quantile(np.abs(s).mean(axis=1), [a, 1 - a])
    sig = np.quantile(s.std(axis=1, ddof=1), [a, 1 - a])
    return star.tolist(), sig.tolist()


def statistics(unit, y, n, delta, keep, bootstrap=200, confidence=0.95, seed=0):
    """mu, mu*, sigma per factor, with the number of effects used and intervals."""
    d = unit.shape[1]
    factor, ee, ok = effects(unit, y, n, delta, keep)
    rng = np.random.default_rng(seed)
    out = {"mu": [], "mu_star": [], "sigma": [], "effects": [], "left_out": [],
           "mu_star_interval": [], "sigma_interval": [],
           "scaling": "EE = (y_k - y_(k-1)) / (±delta), delta in unit space (the CDF value)"}
    for i in range(d):
        e = ee[(factor == i) & ok]
        if len(e) < MIN_EFFECTS:
            raise ValueError(f"morris: factor {i} has {len(e)} usable elementary effects (its "
                             f"others touch a failed case): at least {MIN_EFFECTS} are needed")
        out["mu"].append(float(e.mean()))
        out["mu_star"].append(float(np.abs(e).mean()))
        out["sigma"].append(float(e.std(ddof=1)))
        out["effects"].append(int(len(e)))
        out["left_out"].append(int(np.sum((factor == i) & ~ok)))
        star, sig = _bootstrap(e, bootstrap, confidence, rng)
        out["mu_star_interval"].append(star)
        out["sigma_interval"].append(sig)
    return out
