"""The figures that answer "which factor drives the metric": each metric against each factor
(scatter, panels in the ranking's order) and Morris's μ* (sorted bars, normalised bars, and μ*
against σ). Values in the shown units (display.py)."""
import numpy as np

from . import display as dp
from .figures import _plt, _save

SCATTER_POINTS = 4000     # more points than this are thinned (every k-th) for a readable figure
LABELLED = 0.05           # in the μ*–σ plane, factors below this share of the largest μ* are
                          # not labelled (they crowd the origin; the bars name every factor)


SYMBOL = {"sobol_total": "S_T", "mu_star": "μ*", "chaos_total": "S_T (chaos)",
          "abs_prcc": "|PRCC|"}


def _factor_unit(f):
    return dp.unit(f.get("units", ""))


def scatter(folder, name, title, metric, factors, x, y, units, ranking):
    """One panel per factor (in ranking order when there is one): the metric against the
    factor at every usable point, the factor's rank and measure in the panel's title."""
    plt = _plt()
    keys = [f["key"] for f in factors]
    order = [keys.index(f["factor"]) for f in ranking["factors"]] if ranking else \
        list(range(len(keys)))
    cols = min(len(keys), 4)
    rows = -(-len(keys) // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(2.6 * cols + 0.4, 2.3 * rows + 0.6),
                             squeeze=False, sharey=True)
    step = max(1, len(y) // SCATTER_POINTS)
    shown, fy = dp.unit(units)
    for j, i in enumerate(order):
        ax = axes[j // cols, j % cols]
        fu, fx = _factor_unit(factors[i])
        ax.plot(x[::step, i] * fx, y[::step] * fy, ".", ms=3, alpha=0.5)
        ax.set_xlabel(f"{dp.short(keys[i])}" + (f" [{fu}]" if fu else ""), fontsize=8)
        if ranking:
            e = ranking["factors"][j]
            label = SYMBOL.get(ranking["measure"], ranking["measure"])
            ax.set_title(f"#{e['rank']}: {label} "
                         f"{dp.g(dp.scaled(e['value'], _rank_si(ranking)))}", fontsize=8)
        ax.tick_params(labelsize=7)
    for j in range(len(keys), rows * cols):
        axes[j // cols, j % cols].set_visible(False)
    for r in range(rows):
        axes[r, 0].set_ylabel(f"{metric} [{shown}]", fontsize=8)
    what = f"ranked by {ranking['by']}" if ranking else "no ranking"
    fig.suptitle(f"{title}\n{what}", fontsize=9)
    fig.tight_layout()
    caption = (f"{metric} against each factor at every usable case, the factors in the order of "
               f"their importance ({what}).")
    return _save(fig, folder, name, "rank", caption)


def _rank_si(ranking):
    return ranking["units"] if ranking["units"] != "1" else ""


def _bars(ax, labels, values, err, xlabel):
    pos = np.arange(len(labels))[::-1]
    ax.barh(pos, values, xerr=err, capsize=3, color="C0", ecolor="0.3")
    ax.set_yticks(pos, labels, fontsize=8)
    ax.set_xlabel(xlabel, fontsize=8)
    ax.tick_params(axis="x", labelsize=7)
    ax.set_xlim(0, None)


def morris(folder, name, title, keys, res, units):
    """μ* sorted (with its interval), μ* normalised by the sum of the μ*, and σ against μ*."""
    plt = _plt()
    shown, f = dp.unit(units)
    star, sigma = np.array(res["mu_star"]) * f, np.array(res["sigma"]) * f
    ivs = res.get("mu_star_interval") or [None] * len(keys)
    order = np.argsort(-star, kind="stable")
    lo = np.array([star[i] - iv[0] * f if iv else 0.0 for i, iv in enumerate(ivs)])
    hi = np.array([iv[1] * f - star[i] if iv else 0.0 for i, iv in enumerate(ivs)])
    err = np.vstack([np.maximum(lo, 0), np.maximum(hi, 0)])[:, order]
    labels = [dp.short(keys[i]) for i in order]
    fig, axes = plt.subplots(1, 3, figsize=(13, 0.9 + 0.32 * len(keys) + 1.6),
                             gridspec_kw={"width_ratios": [1.2, 1, 1.3]})
    _bars(axes[0], labels, star[order], err, f"μ* [{shown}] per unit-space step")
    total = star.sum() or 1.0
    _bars(axes[1], labels, star[order] / total, err / total, "μ* / Σ μ* [1]")
    axes[1].set_yticklabels([])
    _plane(axes[2], keys, star, sigma, err[:, np.argsort(order)], shown)
    fig.suptitle(title + "\nMorris screening: factors sorted by μ*, 95 % bootstrap intervals",
                 fontsize=9)
    fig.tight_layout()
    caption = ("Morris screening of " + title.split(",")[0] + ": the factors sorted by μ* (the "
               "mean size of their effect), as a share of the sum, and σ against μ* (above the "
               "dotted line the effect depends on the other factors).")
    return _save(fig, folder, name, "rank", caption)


def _plane(ax, keys, star, sigma, err, shown):
    """σ against μ*, every point inside the axes (the intervals included)."""
    ax.errorbar(star, sigma, xerr=err, fmt="o", ms=4, capsize=2, lw=0.8)
    top_x = float(np.max(star + err[1])) * 1.08 or 1.0
    top_y = float(np.max(sigma)) * 1.12 or 1.0
    m = max(top_x, top_y)
    ax.plot([0, m], [0, m], "k:", lw=0.7, label="σ = μ*")
    big = star >= LABELLED * star.max()
    for k, xv, yv, b in zip(keys, star, sigma, big):
        if b:   # a point in the right part of the axes is labelled on its left: never clipped
            left = xv > 0.55 * top_x
            ax.annotate(dp.short(k), (xv, yv), fontsize=7, xytext=(-3 if left else 3, 3),
                        textcoords="offset points", ha="right" if left else "left")
    ax.set_xlim(0, top_x)
    ax.set_ylim(0, top_y)
    # the unlabelled factors are said under the axes, where no point or label can be
    note = "" if big.all() else (f"\n{int((~big).sum())} factor(s) below {LABELLED:.0%} of the "
                                 "largest μ*\nnot labelled (the bars name them)")
    ax.set_xlabel(f"μ* [{shown}]{note}", fontsize=8)
    ax.set_ylabel(f"σ [{shown}]", fontsize=8)
    ax.tick_params(labelsize=7)
    ax.legend(fontsize=7, loc="upper left")
