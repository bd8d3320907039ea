#!/usr/bin/python3
"""Achieved against requested restitution of the contact laws (study studies/restitution.json).

    /usr/bin/python3 plots/plot_restitution.py RESULTS_DIR [--out DIR] [--dpi N]

Reads RESULTS_DIR/summary.h5 (through the package's reader, python/rodend/study.py) and draws,
into RESULTS_DIR/plots/ (or --out):

  restitution.png        left: achieved restitution -delta'+/delta'- (summary metric
                         first_impact_restitution) against the requested c_r
                         (parameters.contact.restitution), one line per law (the mean over the
                         approach speeds; a marker per speed), with the diagonal; right: the
                         ratio achieved / requested.
  restitution_loops.png  force against penetration of the first impact for each law at one
                         c_r and one approach speed (when the case files record penetration
                         and contact_force).

With --markdown it also prints the table of the README's "Contact laws" section: the achieved
restitution of each law at each requested c_r (mean over the approach speeds, and the largest
relative spread between speeds).

Laws on a geometry other than the sphere are labelled with it ("flap-modified (cylinder)").
Prints one line per file written. Exit status 0 when drawn, 2 when RESULTS_DIR is not a study
or its summary lacks the columns needed (one line, no traceback).

Needs only Debian's numpy, h5py and matplotlib (Agg backend).
"""
import argparse
import math
import os
import sys

# the package rodend beside plots/ (its reader needs no compiled module), else an installed one
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "python"))

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from rodend.naming import format_value  # noqa: E402
from rodend import NotAStudy, Study, open_study  # noqa: E402

LAW = "parameters.contact.law"
CR = "parameters.contact.restitution"
SPEED = "parameters.impact.approach_speed"
GEOMETRY = "parameters.contact.geometry"
ACHIEVED = "first_impact_restitution"
MARKERS = "osd^v<>p*"


def law_labels(summary, default_geometry="sphere"):
    """One label per row: the law, with its geometry when that is not the default."""
    laws = [str(v) for v in summary[LAW]]
    if GEOMETRY not in summary:
        return laws
    return [law if str(g) == default_geometry else f"{law} ({g})"
            for law, g in zip(laws, summary[GEOMETRY])]


def draw_restitution(summary, out, dpi):
    labels = law_labels(summary)
    requested = np.asarray(summary[CR], dtype=float)
    achieved = np.asarray(summary[ACHIEVED], dtype=float)
    ok = np.array([str(s) == "ok" for s in summary["status"]]) if "status" in summary \
        else np.ones(len(labels), bool)
    speeds = np.asarray(summary[SPEED], dtype=float) if SPEED in summary else np.full(len(labels), np.nan)
    speed_values = sorted({s for s in speeds if math.isfinite(s)})
    fig, (ax, axr) = plt.subplots(1, 2, figsize=(12, 5.2))
    ax.plot([0, 1], [0, 1], color="0.6", lw=1, ls="--", label="achieved = requested")
    axr.axhline(1.0, color="0.6", lw=1, ls="--")
    order = list(dict.fromkeys(labels))  # laws in grid order
    cmap = plt.get_cmap("tab10")
    for k, law in enumerate(order):
        rows = np.array([lab == law for lab in labels]) & ok & np.isfinite(achieved)
        if not rows.any():
            continue
        colour = cmap(k % 10)
        # laws on another geometry dashed: they may coincide with one on the sphere
        # (flap-modified on the cylinder has Gonthier's chi, hence its restitution)
        style = "--" if "(" in law else "-"
        crs = sorted(set(requested[rows]))
        mean = [np.mean(achieved[rows & (requested == c)]) for c in crs]
        ax.plot(crs, mean, style, color=colour, lw=1.5, label=law)
        axr.plot(crs, np.array(mean) / np.array(crs), style, color=colour, lw=1.5, label=law)
        for j, s in enumerate(speed_values or [np.nan]):
            sel = rows & (speeds == s) if speed_values else rows
            if sel.any():
                m = MARKERS[j % len(MARKERS)]
                ax.plot(requested[sel], achieved[sel], m, color=colour, ms=5, mfc="none")
                axr.plot(requested[sel], achieved[sel] / requested[sel], m, color=colour, ms=5,
                         mfc="none")
    # a legend entry per approach speed (markers)
    for j, s in enumerate(speed_values):
        ax.plot([], [], MARKERS[j % len(MARKERS)], color="0.3", mfc="none",
                label=f"approach speed {format_value(s)} m/s")
    ax.set_xlabel("requested restitution $c_r$")
    ax.set_ylabel(r"achieved restitution $-\dot\delta^+/\dot\delta^-$")
    ax.set_xlim(0, 1)
    ax.set_ylim(0, 1.05)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="lower right")
    if SHOW_TITLES:
        ax.set_title("Achieved against requested restitution (one free impact)")
    axr.set_xlabel("requested restitution $c_r$")
    axr.set_ylabel("achieved / requested")
    axr.set_xlim(0, 1)
    axr.set_yscale("log")
    axr.grid(alpha=0.3, which="both")
    if SHOW_TITLES:
        axr.set_title("Ratio (1 = the law restitutes what it is asked)")
    fig.tight_layout()
    path = os.path.join(out, "restitution.png")
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    print(f"wrote {path}")


def markdown_table(summary):
    """The achieved restitution per law (rows) and requested c_r (columns), as Markdown."""
    labels = law_labels(summary)
    requested = np.asarray(summary[CR], dtype=float)
    achieved = np.asarray(summary[ACHIEVED], dtype=float)
    crs = sorted(set(requested))
    lines = ["| law | " + " | ".join(f"c_r = {format_value(c)}" for c in crs) + " |",
             "|---|" + "---:|" * len(crs)]
    spread = 0.0
    for law in dict.fromkeys(labels):
        cells = []
        for c in crs:
            vals = achieved[np.array([lab == law for lab in labels]) & (requested == c)]
            vals = vals[np.isfinite(vals)]
            if len(vals) == 0:
                cells.append("-")
                continue
            cells.append(f"{np.mean(vals):.4f}")
            spread = max(spread, (vals.max() - vals.min()) / abs(np.mean(vals)))
        lines.append(f"| `{law}` | " + " | ".join(cells) + " |")
    lines.append("")
    lines.append(f"(largest relative spread between approach speeds: {spread:.1e})")
    return "\n".join(lines)


def draw_loops(study, out, dpi, cr_pick=0.5):
    """Force-penetration loops of the first impact, one per law, at c_r nearest cr_pick and the
    middle approach speed."""
    summary = study.summary
    crs = sorted(set(float(c) for c in summary[CR]))
    cr = min(crs, key=lambda c: abs(c - cr_pick))
    speeds = sorted(set(float(s) for s in summary[SPEED])) if SPEED in summary else []
    speed = speeds[len(speeds) // 2] if speeds else None
    fig, ax = plt.subplots(figsize=(7, 5))
    drawn = 0
    for case in study.cases():
        c = case.coordinates
        if abs(float(c.get(CR, case.parameter(CR, cr))) - cr) > 1e-12:
            continue
        if speed is not None and abs(float(c.get(SPEED, case.parameter(SPEED, speed))) - speed) > 1e-12:
            continue
        if not case.has("penetration", "contact_force"):
            continue
        pen, force = case.signals("penetration", "contact_force")
        inside = pen > 0
        if not inside.any():
            continue
        label = c.get(LAW, case.parameter(LAW, "?"))
        g = c.get(GEOMETRY, case.parameter(GEOMETRY, "sphere"))
        if g != "sphere":
            label = f"{label} ({g})"
        ax.plot(pen[inside] * 1e6, force[inside], lw=1.2, label=label)
        drawn += 1
    if not drawn:
        plt.close(fig)
        print("skip restitution_loops: no case records penetration and contact_force")
        return
    ax.set_xlabel(r"penetration $\delta$ [$\mu$m]")
    ax.set_ylabel("normal contact force [N]")
    title = f"First impact, $c_r$ = {format_value(cr)}"
    if speed is not None:
        title += f", approach speed {format_value(speed)} m/s"
    if SHOW_TITLES:
        ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    path = os.path.join(out, "restitution_loops.png")
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    print(f"wrote {path}")


SHOW_TITLES = True   # --no-title


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("results_dir")
    ap.add_argument("--out", help="output folder (default RESULTS_DIR/plots)")
    ap.add_argument("--dpi", type=int, default=130)
    ap.add_argument("--markdown", action="store_true",
                    help="also print the achieved-restitution table (Markdown) on stdout")
    ap.add_argument("--no-title", action="store_true", help="no figure titles (for publication)")
    a = ap.parse_args()
    global SHOW_TITLES
    SHOW_TITLES = not a.no_title
    try:
        summary = Study(a.results_dir).summary
    except NotAStudy as e:
        print(f"plot_restitution: {e}", file=sys.stderr)
        return 2
    missing = [c for c in (LAW, CR, ACHIEVED) if c not in summary]
    if missing:
        print(f"plot_restitution: {a.results_dir}: the summary has no column {', '.join(missing)} "
              f"(expected a study with grid axes {LAW} and {CR}, e.g. studies/restitution.json)",
              file=sys.stderr)
        return 2
    out = a.out or os.path.join(a.results_dir, "plots")
    os.makedirs(out, exist_ok=True)
    draw_restitution(summary, out, a.dpi)
    if a.markdown:
        print(markdown_table(summary))
    try:
        draw_loops(open_study(a.results_dir), out, a.dpi)
    except NotAStudy as e:
        print(f"skip restitution_loops: {e}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
