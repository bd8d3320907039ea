"""The planar slider-crank figure of plots/plot_study.py: the slider's acceleration over the last
full revolution with the ideal joint overlaid, and each clearance's eccentricity orbit.
"""
import math
import numpy as np
import matplotlib.pyplot as plt
from matplotlib.lines import Line2D

from figure_kit import (
    Skip, axis_label, case_legend, figure, finite_max, set_suptitle, shown, sig, sigs, title,
    with_signals)


def last_revolution(angle):
    """Mask of the samples of the last full crank revolution (turns counted from the first
    sample's angle), or None when the case did not complete one."""
    turns = np.abs(angle - angle[0]) / (2 * math.pi)
    full = math.floor(turns[-1] + 1e-9)
    if full < 1:
        return None
    return (turns >= full - 1 - 1e-9) & (turns <= full + 1e-9)


def rod_slider_clearance(case):
    """The rod-slider joint's clearance [m], or None when the joint is ideal."""
    if case.parameter("joints.rod_slider.model") != "clearance":
        return None
    try:
        return float(case.parameter("joints.rod_slider.clearance"))
    except (TypeError, ValueError):
        return None


@figure("slider_acceleration", "slider acceleration against crank angle and eccentricity orbits")
def fig_slider_acceleration(study, cases, style):
    if study.scene != "planar-slider-crank":
        raise Skip(f"scene {study.scene} is not planar-slider-crank")
    cases = with_signals(cases, "crank_angle", "slider_acceleration")
    clear = [c for c in cases if rod_slider_clearance(c)]
    ideal = [c for c in cases if c not in clear]
    orbits = [c for c in clear if c.has("relative_position")]
    n = max(len(orbits), 1)
    fig = plt.figure(figsize=(max(8.0, 3.0 * n), 8.0), layout="constrained")
    grid = fig.add_gridspec(2, n, height_ratios=[1.2, 1.0])
    ax = fig.add_subplot(grid[0, :])
    extra = []
    for c in clear + ideal:
        th, a = sigs(c, "crank_angle", "slider_acceleration")
        m = last_revolution(th)
        if m is None:
            continue
        deg = np.degrees(np.mod(th[m] - th[0], 2 * math.pi))
        order = np.argsort(deg, kind="stable")
        is_ideal = c in ideal
        ax.plot(deg[order], a[m][order], color="k" if is_ideal else style(c),
                lw=1.6 if is_ideal else 0.9, ls="--" if is_ideal else "-",
                zorder=3 if is_ideal else 2)
        if is_ideal:
            extra.append((Line2D([], [], color="k", ls="--", lw=1.6), f"ideal joint ({c.label})"))
    ax.set_xlim(0, 360)
    ax.set_xticks(range(0, 361, 45))
    ax.set_xlabel("crank angle over the last full revolution [deg]")
    ax.set_ylabel(axis_label("slider acceleration", cases[0].unit("slider_acceleration")))
    ax.grid(True, alpha=0.3)
    for i, c in enumerate(orbits):
        ax2 = fig.add_subplot(grid[1, i])
        th = sig(c, "crank_angle")
        r = sig(c, "relative_position")
        m = last_revolution(th)
        if m is None:
            m = np.ones(len(th), dtype=bool)
        x, unit = shown(r[m, 0], c.unit("relative_position"))
        y, _ = shown(r[m, 1], c.unit("relative_position"))
        ax2.plot(x, y, color=style(c), lw=0.8)
        cl, _ = shown(rod_slider_clearance(c), "m")
        ang = np.linspace(0, 2 * math.pi, 200)
        ax2.plot(cl * np.cos(ang), cl * np.sin(ang), color="0.5", ls=":", lw=1.0)
        ax2.set_aspect("equal")
        lim = 1.15 * max(cl, finite_max(np.hypot(x, y)))
        ax2.set_xlim(-lim, lim)
        ax2.set_ylim(-lim, lim)
        ax2.set_xlabel(f"x [{unit}]")
        ax2.set_ylabel(f"y [{unit}]")
        ax2.set_title(f"orbit, c = {cl:g} {unit}", fontsize="small")
        ax2.grid(True, alpha=0.3)
    if orbits:
        extra.append((Line2D([], [], color="0.5", ls=":"), "clearance circle"))
    set_suptitle(fig, title(study, "Slider acceleration, last full revolution; rod-slider orbits\n"
                              "(journal centre relative to bearing centre)"))
    case_legend(fig, clear, style, extra)
    return fig
