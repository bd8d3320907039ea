"""The analysis figures, PNG into FOLDER/plots/analysis-*.png (matplotlib, Agg).

Each PNG carries two text chunks that `rodend report` reads to group and caption it:
`rodend-question` (rank: which factor drives a metric; spread: how a metric is spread and how
likely it passes a limit; surrogate: whether the chaos can be trusted; histories: how the
histories spread over time) and `Description` (a one-sentence caption). The images are
stored with a 256-colour palette (a quarter of the bytes of full colour for these line
drawings), so the report that embeds them stays small. Values in the shown units (display.py).
The figures of each metric against each factor and of Morris's μ* are in factor_figures.py.
"""
import io
import numbers
import os

import numpy as np

from ..atomic import atomic_file
from . import display as dp


def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def _save(fig, folder, name, question, caption):
    """Writes plots/analysis-NAME.png (palette colours, the question and caption as text
    chunks) through rodend.atomic.atomic_file: a fresh temporary file created without
    following links, renamed over the final name (never written through a link)."""
    from PIL import Image, PngImagePlugin
    path = os.path.join(folder, "plots", f"analysis-{name}.png")
    buf = io.BytesIO()
    try:
        fig.savefig(buf, dpi=100, bbox_inches="tight", format="png")
    finally:
        _plt().close(fig)
    info = PngImagePlugin.PngInfo()
    info.add_itxt("rodend-question", question)
    info.add_itxt("Description", caption)
    image = Image.open(io.BytesIO(buf.getvalue())).convert("RGB").quantize(256)
    with atomic_file(path) as fh:  # never through a link (rodend/atomic.py)
        image.save(fh, format="png", pnginfo=info, optimize=True)
    return path


def where(coords):
    """"clearance = 0.0001, scene = rod-end-actuator": a grid point for a title."""
    return ", ".join(f"{_short(k)} = {v:g}" if isinstance(v, numbers.Real) else
                     f"{_short(k)} = {v}" for k, v in coords.items())


_short = dp.short


def indices(folder, name, title, keys, sets):
    """Bars of Sobol indices: sets = [(label, values, intervals or None)]; None (no figure)
    for a single factor, whose index is 1 by definition."""
    if len(keys) < 2:
        return None
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
    caption = (f"Sobol' indices of {title.split(',')[0]}: the share of its variance each "
               "factor explains alone (first order) and with its interactions (total).")
    return _save(fig, folder, name, "rank", caption)


def morris(folder, name, title, keys, res, units):
    """Morris's μ* sorted, normalised, and against σ (factor_figures.morris)."""
    from .factor_figures import morris as draw
    return draw(folder, name, title, keys, res, units)


def cdf(folder, name, title, y, units, exceedances):
    plt = _plt()
    fig, ax = plt.subplots(figsize=(4.6, 3.4))
    shown, f = dp.unit(units)
    s = np.sort(y) * f
    ax.step(s, np.arange(1, len(s) + 1) / len(s), where="post")
    for e in exceedances:
        ax.axvline(e["threshold"] * f, color="C3", ls="--", lw=0.8,
                   label=f"P(> {dp.g(e['threshold'] * f)}{dp.suffix(units)}) = "
                         f"{e['probability']:.3g} {dp.interval(e.get('interval'))}")
    metric = title.split(",")[0]
    ax.set_xlabel(f"{metric} [{shown}]")
    ax.set_ylabel("empirical CDF [1]")
    ax.set_title(title, fontsize=9)
    if exceedances:
        ax.legend(fontsize=7)
    caption = (f"The distribution of {metric} over the cases: the share of cases below each "
               "value" + (", and each threshold with the probability of exceeding it." if
                          exceedances else "."))
    return _save(fig, folder, name, "spread", caption)


def chaos(folder, name, title, y, pred, q2, units, withheld=None):
    """Each case's leave-one-out prediction against its value; withheld: the validation's
    reason when the chaos's indices are withheld (said in the caption)."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(4.0, 3.8))
    shown, f = dp.unit(units)
    y, pred = np.asarray(y) * f, np.asarray(pred) * f
    ax.plot(y, pred, ".", ms=3, alpha=0.6)
    lo, hi = float(np.min(y)), float(np.max(y))
    ax.plot([lo, hi], [lo, hi], "k-", lw=0.7)
    ax.set_xlabel(f"actual [{shown}]")
    ax.set_ylabel(f"leave-one-out prediction [{shown}]")
    ax.set_title(f"{title}\npolynomial chaos, Q² (LOO) = {q2:.4f}", fontsize=9)
    trust = (f"its indices are withheld: {withheld}" if withheld else
             "on the diagonal, its indices can be trusted")
    caption = (f"The polynomial chaos of {title.split(',')[0]}: each case's leave-one-out "
               f"prediction against its value (Q² {q2:.3f}; {trust}).")
    return _save(fig, folder, name, "surrogate", caption)


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
    caption = (f"The median and the 5–95 % band of {title.split(',')[0]} over time across the "
               f"{b['cases']} ok cases.")
    return _save(fig, folder, name, "histories", caption)
