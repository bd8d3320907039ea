"""Detectability of clearance growth by diagnostic features (docs/health-monitoring.md).

For a study of populations at several clearances (the first, the smallest, "as new") and
sensor-noise levels (``sensors.noise_scale``), e.g. ``studies/detectability.json``: for each
feature, each noise level and each grown clearance, the ROC curve of "grown by dc" against "as
new", its AUC with a bootstrap interval, and the probability of detection at 5 % false alarms;
the smallest dc detected with 95 % probability. A feature may fall as the clearance grows: it is
oriented by the sign of the difference of the medians.

    /usr/bin/python3 python/rodend/analysis/detectability.py RESULTS_DIR [--markdown]

writes RESULTS_DIR/plots/detectability.png and prints the table.
"""

import argparse
import math
import os
import sys

import numpy as np

CLEARANCE = "parameters.contact.clearance"
NOISE = "sensors.noise_scale"
#: (feature, the metric read exactly, the metric read from the sensors or None)
FEATURES = [
    ("free-play", "free_play", "sensed_free_play"),
    ("hysteresis", "hysteresis", "sensed_hysteresis"),
    ("onsets per cycle", "contact_onsets_per_cycle", None),
    ("surface acceleration > f_hp", "surface_acceleration_hf", "sensed_surface_acceleration_hf"),
    ("pressure ripple at onsets", "pressure_ripple", "sensed_pressure_ripple"),
]
FALSE_ALARM = 0.05
DETECTION = 0.95


def auc(negatives, positives):
    """P(X_pos > X_neg) + P(tie)/2: the area under the ROC curve (Mann-Whitney U / n m)."""
    neg = np.asarray(negatives, float)
    pos = np.asarray(positives, float)
    greater = (pos[:, None] > neg[None, :]).sum()
    ties = (pos[:, None] == neg[None, :]).sum()
    return (greater + 0.5 * ties) / (len(pos) * len(neg))


def roc(negatives, positives):
    """The ROC curve: false-alarm and detection rates at every threshold, from (0, 0) to (1, 1)."""
    neg = np.asarray(negatives, float)
    pos = np.asarray(positives, float)
    thresholds = np.unique(np.concatenate([neg, pos]))[::-1]
    fa = [0.0] + [float((neg >= t).mean()) for t in thresholds]
    pd_ = [0.0] + [float((pos >= t).mean()) for t in thresholds]
    return np.array(fa), np.array(pd_)


def auc_interval(negatives, positives, level=0.90, resamples=2000, seed=0):
    """Percentile bootstrap interval of the AUC (each population resampled with replacement)."""
    rng = np.random.default_rng(seed)
    neg = np.asarray(negatives, float)
    pos = np.asarray(positives, float)
    values = [auc(rng.choice(neg, len(neg)), rng.choice(pos, len(pos))) for _ in range(resamples)]
    lo, hi = np.quantile(values, [(1 - level) / 2, (1 + level) / 2])
    return float(lo), float(hi)


def detection_probability(negatives, positives, false_alarm=FALSE_ALARM):
    """Fraction of the positives above the threshold that the negatives exceed at most
    `false_alarm` of the time (the (1 - false_alarm) empirical quantile of the negatives)."""
    neg = np.sort(np.asarray(negatives, float))
    k = int(math.ceil((1 - false_alarm) * len(neg))) - 1
    threshold = neg[min(max(k, 0), len(neg) - 1)]
    return float((np.asarray(positives, float) > threshold).mean())


def oriented(values, as_new):
    """The feature, negated if it falls as the clearance grows (medians)."""
    return -values if np.median(values) < np.median(as_new) else values


def analyse(table):
    """Rows (feature, source, noise, dc [m], auc, lo, hi, p_detect) of a summary table."""
    rows = []
    clearances = sorted(table[CLEARANCE].unique())
    c0 = clearances[0]
    for noise in sorted(table[NOISE].unique()):
        at = table[table[NOISE] == noise]
        for name, exact, sensed in FEATURES:
            for source, column in (("exact", exact), ("sensed", sensed)):
                if column is None or column not in at:
                    continue
                new = at[at[CLEARANCE] == c0][column].dropna().to_numpy()
                for c in clearances[1:]:
                    worn = at[at[CLEARANCE] == c][column].dropna().to_numpy()
                    if len(new) < 2 or len(worn) < 2:
                        continue
                    w = oriented(worn, new)
                    n = -new if w is not worn else new
                    lo, hi = auc_interval(n, w)
                    rows.append((name, source, noise, c - c0, auc(n, w), lo, hi,
                                 detection_probability(n, w)))
    return rows


def smallest_detected(rows):
    """{(feature, source, noise): the smallest dc with p_detect >= 0.95, or None}."""
    out = {}
    for name, source, noise, dc, _a, _lo, _hi, p in sorted(rows, key=lambda r: r[3]):
        key = (name, source, noise)
        out.setdefault(key, None)
        if out[key] is None and p >= DETECTION:
            out[key] = dc
    return out


def markdown(rows):
    """The table of the smallest detectable dc, and the AUCs at each dc."""
    small = smallest_detected(rows)
    noises = sorted({r[2] for r in rows})
    dcs = sorted({r[3] for r in rows})
    lines = ["| feature | source | " + " | ".join(f"smallest Δc, noise ×{n:g}" for n in noises) +
             " | " + " | ".join(f"AUC at Δc = {dc * 1e3:.3g} mm, noise ×{noises[-1]:g}"
                                for dc in dcs) + " |"]
    lines.append("|" + "---|" * (2 + len(noises) + len(dcs)))
    for name, exact, sensed in FEATURES:
        for source in ("exact", "sensed"):
            if (name, source, noises[0]) not in small:
                continue
            cells = []
            for n in noises:
                dc = small.get((name, source, n))
                cells.append("> max" if dc is None else f"{dc * 1e3:.3g} mm")
            aucs = []
            for dc in dcs:
                r = [x for x in rows if x[:3] == (name, source, noises[-1]) and x[3] == dc]
                aucs.append(f"{r[0][4]:.2f} [{r[0][5]:.2f}, {r[0][6]:.2f}]" if r else "")
            lines.append(f"| {name} | {source} | " + " | ".join(cells) + " | " +
                         " | ".join(aucs) + " |")
    return "\n".join(lines)


def figure(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    noises = sorted({r[2] for r in rows})
    fig, axes = plt.subplots(1, len(noises), figsize=(5.5 * len(noises), 4.2), sharey=True)
    axes = np.atleast_1d(axes)
    for ax, noise in zip(axes, noises):
        for name, _exact, _sensed in FEATURES:
            for source, style in (("exact", "-"), ("sensed", "--")):
                r = sorted((x for x in rows if x[:3] == (name, source, noise)), key=lambda x: x[3])
                if not r:
                    continue
                dc = [x[3] * 1e3 for x in r]
                ax.errorbar(dc, [x[4] for x in r],
                            yerr=[[x[4] - x[5] for x in r], [x[6] - x[4] for x in r]],
                            linestyle=style, marker="o", capsize=2,
                            label=f"{name} ({source})")
        ax.axhline(0.5, color="grey", linewidth=0.5)
        ax.set_xlabel("clearance growth Δc [mm]")
        ax.set_title(f"sensor noise × {noise:g}")
    axes[0].set_ylabel("AUC (90 % bootstrap interval)")
    axes[-1].legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    os.makedirs(os.path.dirname(path), exist_ok=True)
    fig.savefig(path, dpi=110)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("results", help="the study's results directory (summary.h5)")
    args = parser.parse_args(argv)
    from ..results import open_results
    table = open_results(args.results).summary
    table = table[table["status"] == "ok"]
    rows = analyse(table)
    figure(rows, os.path.join(args.results, "plots", "detectability.png"))
    print(markdown(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
