"""The analysis figures, PNG into FOLDER/plots/analysis-*.png (matplotlib, Agg)."""
import numbers
import os

import numpy as np

from ..atomic import atomic_file


def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def _save(fig, folder, name):
    path = os.path.join(folder, "plots", f"analysis-{name}.png")
    try:
        with atomic_file(path) as fh:  # never through a link (rodend/atomic.py)
            fig.savefig(fh, format="png", dpi=110, bbox_inches="tight")
    finally:
        _plt().close(fig)
    return path


def where(coords):
    """"clearance = 0.0001, scene = rod-end-actuator": a grid point for a title."""
    return ", ".join(f"{_short(k)} = {v:g}" if isinstance(v, numbers.Real) else
                     f"{_short(k)} = {v}" for k, v in coords.items())


def _short(key):
    """A factor's label: its key without "parameters." (slider_spring.stiffness and
    crank_spring.stiffness must stay two labels)."""
    return key[len("parameters."):] if key.startswith("parameters.") else key


def indices(folder, name, title, keys, sets):
    """Bars of Sobol indices: sets = [(label, values, intervals or None)]."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(1.2 + 1.1 * len(keys) * max(1, len(sets)) / 2, 3.4))
    width = 0.8 / len(sets)
    for j, (label, values, iv) in enumerate(sets):
        pos = np.arange(len(keys)) + (j - (len(sets) - 1) / 2) * width
        err = None
        if iv is not None:
            lo = np.array([v - a for v, (a, _) in zip(values, iv)])
            hi = np.array([b - v for v, (_, b) in zip(values, iv)])
            err = np.vstack([np.maximum(lo, 0), np.maximum(hi, 0)])
        ax.bar(pos, values, width, yerr=err, capsize=3, label=label)
    ax.set_xticks(np.arange(len(keys)), [_short(k) for k in keys], rotation=20, ha="right")
    ax.set_ylabel("Sobol index [1]")
    ax.axhline(0, color="k", lw=0.5)
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=8)
    return _save(fig, folder, name)


def morris(folder, name, title, keys, res, units):
    plt = _plt()
    fig, ax = plt.subplots(figsize=(4.6, 3.6))
    ivs = res.get("mu_star_interval") or []
    if ivs and all(iv is not None for iv in ivs):
        err = np.array([[max(m - a, 0), max(b - m, 0)] for m, (a, b) in
                        zip(res["mu_star"], ivs)]).T
        ax.errorbar(res["mu_star"], res["sigma"], xerr=err, fmt="o", capsize=3,
                    label="μ* with its bootstrap interval")
    else:
        ax.scatter(res["mu_star"], res["sigma"])
    for k, x, y in zip(keys, res["mu_star"], res["sigma"]):
        ax.annotate(_short(k), (x, y), fontsize=8, xytext=(3, 3), textcoords="offset points")
    top = max(max(res["mu_star"]), max(res["sigma"])) * 1.1 or 1.0
    ax.plot([0, top], [0, top], "k:", lw=0.7, label="σ = μ*")
    ax.set_xlim(0, top)
    ax.set_ylim(0, top)
    ax.set_xlabel(f"μ*, effect per unit-space step [{units}]")
    ax.set_ylabel(f"σ [{units}]")
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=8)
    return _save(fig, folder, name)


def cdf(folder, name, title, y, units, exceedances):
    plt = _plt()
    fig, ax = plt.subplots(figsize=(4.6, 3.4))
    s = np.sort(y)
    ax.step(s, np.arange(1, len(s) + 1) / len(s), where="post")
    for e in exceedances:
        lo, hi = e["interval"]
        ax.axvline(e["threshold"], color="C3", ls="--", lw=0.8,
                   label=f"P(> {e['threshold']:.4g}) = {e['probability']:.3g} "
                         f"[{lo:.3g}, {hi:.3g}]")
    ax.set_xlabel(f"{title.split(',')[0]} [{units}]")
    ax.set_ylabel("empirical CDF [1]")
    ax.set_title(title, fontsize=9)
    if exceedances:
        ax.legend(fontsize=7)
    return _save(fig, folder, name)


def chaos(folder, name, title, y, pred, q2, units):
    plt = _plt()
    fig, ax = plt.subplots(figsize=(4.0, 3.8))
    ax.plot(y, pred, ".", ms=3, alpha=0.6)
    lo, hi = float(np.min(y)), float(np.max(y))
    ax.plot([lo, hi], [lo, hi], "k-", lw=0.7)
    ax.set_xlabel(f"actual [{units}]")
    ax.set_ylabel(f"leave-one-out prediction [{units}]")
    ax.set_title(f"{title}\npolynomial chaos, Q² (LOO) = {q2:.4f}", fontsize=9)
    return _save(fig, folder, name)


def band(folder, name, title, b):
    plt = _plt()
    q = b["quantiles"]
    comps = 1 if q.ndim == 2 else q.shape[2]
    fig, axes = plt.subplots(comps, 1, figsize=(5.5, 2.2 + 1.4 * comps), squeeze=False,
                             sharex=True)
    for c in range(comps):
        ax = axes[c, 0]
        lo, mid, hi = (q[i] if q.ndim == 2 else q[i][:, c] for i in range(3))
        ax.fill_between(b["time"], lo, hi, alpha=0.3, label="5–95 %")
        ax.plot(b["time"], mid, lw=1, label="median")
        ax.set_ylabel(f"[{b['units']}]" if comps == 1 else f"component {c} [{b['units']}]")
    axes[-1, 0].set_xlabel("time [s]")
    axes[0, 0].set_title(f"{title} ({b['cases']} ok cases)", fontsize=9)
    axes[0, 0].legend(fontsize=8)
    return _save(fig, folder, name)
