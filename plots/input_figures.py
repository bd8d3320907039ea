"""The figures of the periodic inputs (docs/inputs.md), drawn by plots/plot_study.py:

  bode            the frequency response, gain and phase of the surface and of the piston against
                  the drive frequency, one surface curve per clearance (and amplitude), the
                  piston's clearances merged where their curves agree (it does not see the
                  clearance), and the linearised model at zero clearance (plots/linear_actuator.py)
  free_play_loop  the free-play ground test's loop over the periods after the first, with the
                  metric's construction (each branch's least-squares line over 0.2 M to 0.9 M,
                  extrapolated to zero moment, where the two lines are the free-play apart) and
                  the ringing after each crossing marked (what a peak-to-peak reading would
                  take for the free-play)

The figures register themselves on import (plot_study.py draws them in its order); the
helpers (Skip, sigs, legends, titles) are plots/figure_kit.py's, H here.
"""
import math

import matplotlib.pyplot as plt
import numpy as np
import linear_actuator
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

import figure_kit as H
from rodend.naming import coordinate_label

FIT_WINDOW = (0.2, 0.9)     # the branches' fit window, a fraction of the largest moment
ZOOM = 0.3          # the left panel of the free-play loop: |M| up to this fraction of the largest


# --- the Bode diagram -------------------------------------------------------------------------

DASHES = ["-", "--", ":", "-."]
MERGE_GAIN, MERGE_PHASE = 0.01, 1.0     # piston curves closer than 1 % and 1 deg are one curve
# the parameters the linearised model reads (linear_actuator.Model)
MODEL_KEYS = ("actuator.", "geometry.", "slider_spring.", "crank_spring.", "surface.",
              "ball.mass", "socket.mass")


def is_clearance(kv):
    return kv[0].endswith("contact.clearance")


def bode_groups(cases):
    """One group per grid point less the frequency: {coordinates (json_key): cases}."""
    groups = {}
    for c in cases:
        key = H.json_key({k: v for k, v in c.coordinates.items()
                          if not k.endswith("motion.frequency") and not k.endswith(".cycles")
                          and k != "time.end"})
        groups.setdefault(key, []).append(c)
    return groups


def response(summ, members, what):
    """(frequency [Hz], gain, phase [deg]) of the surface or the piston over a group's cases,
    by frequency; NaN where the case did not settle."""
    rows = [c.row for c in members]
    f = np.asarray(summ["drive_frequency"], float)[rows]
    order = np.argsort(f)
    g = np.asarray(summ[f"{what}_gain"], float)[rows][order]
    ph = np.degrees(np.unwrap(np.nan_to_num(np.asarray(summ[f"{what}_phase"], float)[rows][order])))
    ph[~np.isfinite(g)] = np.nan
    return f[order], g, ph


def group_label(key, case):
    return ", ".join(coordinate_label(k, case.coordinates[k], case.coordinate_unit(k))
                     for k, _ in key) or "all cases"


def piston_curves(summ, groups):
    """The piston's curves: [(f, gain, phase, rest, clearance key or None, label)], one per
    coordinates less the clearance when its clearances' curves agree (MERGE_GAIN, MERGE_PHASE:
    the piston does not see the clearance), else one per group."""
    by_rest = {}
    for key, members in groups.items():
        by_rest.setdefault(tuple(kv for kv in key if not is_clearance(kv)), []).append(key)
    curves = []
    for rest, keys in by_rest.items():
        resp = [response(summ, groups[k], "piston") for k in keys]
        case = groups[keys[0]][0]
        if len(keys) > 1 and all(np.array_equal(r[0], resp[0][0]) for r in resp):
            g, ph = np.array([r[1] for r in resp]), np.array([r[2] for r in resp])
            dg = np.nanmax(np.nanmax(g, 0) / np.nanmin(g, 0) - 1)
            dph = np.nanmax(np.nanmax(ph, 0) - np.nanmin(ph, 0))
            if dg <= MERGE_GAIN and dph <= MERGE_PHASE:
                label = (f"piston, every clearance (within {100 * dg:.2g} %, {dph:.2g}°)"
                         + (": " + group_label(rest, case) if rest else ""))
                curves.append((resp[0][0], np.nanmean(g, 0), np.nanmean(ph, 0), rest, None, label))
                continue
        for k, r in zip(keys, resp):
            curves.append((*r, rest, k, "piston, " + group_label(k, groups[k][0])))
    return curves


def linear_references(groups, f_lo, f_hi):
    """The linearised model's (f, H_surface, H_piston, label), one per distinct set of the
    parameters it reads; none for a scene without the linkage."""
    refs, seen = [], []
    f = np.geomspace(f_lo, f_hi, 200)
    for members in groups.values():
        case = members[0]
        if case.scene != "rod-end-actuator":
            continue
        p = {k: v for k, v in case.parameters.items() if k.startswith(MODEL_KEYS)}
        if p in seen:
            continue
        seen.append(p)
        lin = linear_actuator.Linear(linear_actuator.Model(p), "mid")
        h = np.array([lin.response(x) for x in f])
        refs.append((f, h[:, 1], h[:, 0], "linearised model, zero clearance, at the mid pressure "
                     "(plots/linear_actuator.py)" + ("" if not refs else f" ({case.label})")))
    return refs


def draw_curve(axes, col, f, g, ph, **style):
    axes[0, col].semilogx(f, 20 * np.log10(g), **style)
    axes[1, col].semilogx(f, ph, **style)


@H.figure("bode", "Bode diagram of the frequency response, one curve per clearance")
def fig_bode(study, cases, style):
    summ = study.summary
    if "surface_gain" not in summ or not np.isfinite(np.asarray(summ["surface_gain"], float)).any():
        raise H.Skip("no gain/phase metrics (a sine command's frequency response) in the summary")
    freqs = np.asarray(summ["drive_frequency"], float)
    if len(set(freqs[np.isfinite(freqs)])) < 2:
        raise H.Skip("one drive frequency: no frequency axis for a Bode diagram")
    groups = bode_groups(cases)
    fig, axes = plt.subplots(2, 2, sharex=True, figsize=(11, 7), layout="constrained")
    cmap = plt.get_cmap("tab10")
    clearances = sorted({H.clearance_of(m[0]) or 0.0 for m in groups.values()})
    rests = []                                  # the coordinates less the clearance: dashes
    for key in groups:
        rest = tuple(kv for kv in key if not is_clearance(kv))
        if rest not in rests:
            rests.append(rest)
    handles, labels = [], []
    for key, members in groups.items():         # the surface: one curve per group
        kw = dict(color=cmap(clearances.index(H.clearance_of(members[0]) or 0.0) % 10),
                  ls=DASHES[rests.index(tuple(kv for kv in key if not is_clearance(kv))) % 4],
                  marker="o", ms=3, lw=1)
        draw_curve(axes, 0, *response(summ, members, "surface"), **kw)
        handles.append(Line2D([], [], **kw))
        labels.append("surface, " + group_label(key, members[0]))
    for f, g, ph, rest, key, label in piston_curves(summ, groups):
        color = "0.3" if key is None else cmap(
            clearances.index(H.clearance_of(groups[key][0]) or 0.0) % 10)
        kw = dict(color=color, ls=DASHES[rests.index(rest) % 4], marker="s", ms=3, lw=1)
        draw_curve(axes, 1, f, g, ph, **kw)
        handles.append(Line2D([], [], **kw))
        labels.append(label)
    for f, hs, hp, label in linear_references(groups, np.nanmin(freqs), np.nanmax(freqs)):
        kw = dict(color="k", lw=2.2, alpha=0.35, zorder=1)
        for col, h in ((0, hs), (1, hp)):
            draw_curve(axes, col, f, np.abs(h), np.degrees(np.unwrap(np.angle(h))), **kw)
        handles.append(Line2D([], [], **kw))
        labels.append(label)
    finish_bode(fig, axes, study, handles, labels)
    return fig


def finish_bode(fig, axes, study, handles, labels):
    axes[0, 0].set_title("surface angle / rigid-linkage angle of the command", fontsize="small",
                         loc="left")
    axes[0, 1].set_title("piston position / command", fontsize="small", loc="left")
    for col in range(2):
        axes[0, col].set_ylabel("gain [dB]")
        axes[1, col].set_ylabel("phase [deg]")
        axes[1, col].set_xlabel("drive frequency [Hz]")
        for r in range(2):
            axes[r, col].grid(True, which="both", alpha=0.3)
    H.set_suptitle(fig, H.title(study, "Frequency response (Bode diagram): gain and phase at the "
                                "drive frequency over settled periods (docs/inputs.md)"))
    H.bottom_legend(fig, handles, labels)


# --- the free-play loop ---------------------------------------------------------------------

def after_first_period(case, t):
    """Samples from the end of the moment's first period on, and those of its last period
    (where the metrics are read), as two boolean masks; everything when the case does not
    say its periods."""
    f, n = case.parameter("hinge.frequency"), case.parameter("hinge.cycles")
    t0 = case.parameter("hinge.start_time", 0.0)
    try:
        f, n, t0 = float(f), int(n), float(t0)
    except (TypeError, ValueError):
        every = np.ones(len(t), bool)
        return every, every
    shown = t >= t0 + 1.0 / f - 1e-9 if n >= 2 else np.ones(len(t), bool)
    last = (t >= t0 + (n - 1) / f - 1e-9) & (t <= t0 + n / f + 1e-9)
    return shown, last


def branch_line(t, m, angle, m_max, sign):
    """The branch's least-squares line angle = a + M/K over the samples with 0.2 M <= sign M <=
    0.9 M, each sample weighted by its share of time (as the metric integrates over time):
    (a [rad], K [N m/rad])."""
    lo, hi = FIT_WINDOW
    sel = (sign * m >= lo * m_max) & (sign * m <= hi * m_max)
    w = H.sample_weights(t)[sel]
    x, y = m[sel], angle[sel]
    xm, ym = np.average(x, weights=w), np.average(y, weights=w)
    slope = np.average((x - xm) * (y - ym), weights=w) / np.average((x - xm) ** 2, weights=w)
    return ym - slope * xm, 1.0 / slope


def loop_construction(case, summ):
    """What the figure draws of one case, from its last period: the branch lines, the free-play
    they give and the ringing's extremes of angle - M/K (K the mean of the two branches')."""
    t, m, a = H.sigs(case, "time", "hinge_moment", "surface_angle")
    shown, last = after_first_period(case, t)
    m_max = float(case.parameter("hinge.amplitude", 0.0) or np.nanmax(np.abs(m[last])))
    lines = {s: branch_line(t[last], m[last], a[last], m_max, s) for s in (1, -1)}
    k = 0.5 * (lines[1][1] + lines[-1][1])
    # the ringing: around the crossings, between the fit windows
    near = last & (np.abs(m) <= FIT_WINDOW[0] * m_max)
    rest = a[near] - m[near] / k
    hi, lo = int(np.nanargmax(rest)), int(np.nanargmin(rest))
    return {"t": t[shown], "m": m[shown], "a": a[shown], "m_max": m_max, "lines": lines, "k": k,
            "free_play": lines[1][0] - lines[-1][0], "metric": float(summ["free_play"][case.row]),
            "peaks": [(m[near][i], a[near][i], rest[i]) for i in (hi, lo)],
            "peak_to_peak": rest[hi] - rest[lo]}


def draw_branches(axes, g, color):
    """The branch lines from M = 0 to the fit window's end, solid over the window, and their
    intercepts at M = 0 (circles), on the loop (left) and on the loop less M/K (right)."""
    lo, hi = FIT_WINDOW
    for sign, (a0, kb) in g["lines"].items():
        for part, ls in (((0.0, lo), "--"), ((lo, hi), "-")):
            mm = sign * g["m_max"] * np.array(part)
            for ax, less in ((axes[0], 0.0), (axes[1], 1.0 / g["k"])):
                ax.plot(mm, np.degrees(a0 + mm / kb - less * mm), color="k", ls=ls, lw=0.8,
                        zorder=2)
        for ax in axes:
            ax.plot(0.0, math.degrees(a0), "o", mfc="white", mec=color, ms=5, zorder=5)


def draw_loop(axes, g, color):
    """The loop (left: near zero moment), the loop less M/K (right), the ringing's extremes."""
    deg = np.degrees
    axes[0].plot(g["m"], deg(g["a"]), color=color, lw=1.0, zorder=3)
    axes[1].plot(g["m"], deg(g["a"] - g["m"] / g["k"]), color=color, lw=1.0, zorder=3)
    for (mp, ap, rp), marker in zip(g["peaks"], ("v", "^")):
        axes[0].plot(mp, deg(ap), marker, color=color, mec="k", mew=0.5, ms=6, zorder=6)
        axes[1].plot(mp, deg(rp), marker, color=color, mec="k", mew=0.5, ms=6, zorder=6)
    draw_branches(axes, g, color)


def zoom_limits(ax, drawn, zoom):
    """The left panel: |M| <= zoom M_max, the angle's range there with a margin."""
    m_max = max(g["m_max"] for g in drawn)
    ys = [np.degrees(g["a"][np.abs(g["m"]) <= zoom * m_max]) for g in drawn]
    ys += [np.degrees([g["lines"][s][0] for s in (1, -1)]) for g in drawn]
    y = np.concatenate([v[np.isfinite(v)] for v in ys])
    pad = 0.05 * (y.max() - y.min())
    ax.set_xlim(-zoom * m_max, zoom * m_max)
    ax.set_ylim(y.min() - pad, y.max() + pad)


def free_play_label(case, g):
    text = (f"{case.label}: free-play {math.degrees(g['metric']):.3f} deg "
            f"(the lines drawn: {math.degrees(g['free_play']):.3f}")
    crank, clearance = case.parameter("geometry.crank"), H.clearance_of(case)
    if crank and clearance:
        text += f"; 2c/s {math.degrees(2 * clearance / float(crank)):.3f}"
    return text + f"), peak to peak {math.degrees(g['peak_to_peak']):.3f} deg"


@H.figure("free_play_loop", "free-play loop: surface angle against hinge moment, one per "
          "clearance")
def fig_free_play_loop(study, cases, style):
    summ = study.summary
    if "free_play" not in summ or not np.isfinite(np.asarray(summ["free_play"], float)).any():
        raise H.Skip("no free-play metrics (a triangle hinge moment) in the summary")
    cases = [c for c in H.with_signals(cases, "hinge_moment", "surface_angle")
             if np.isfinite(float(summ["free_play"][c.row]))]
    if not cases:
        raise H.Skip("no case with a free-play loop recorded (signals hinge_moment, surface_angle)")
    fig, axes = plt.subplots(1, 2, figsize=(12, 5.6), layout="constrained")
    handles, labels, drawn = [], [], []
    for c in cases:
        g = loop_construction(c, summ)
        draw_loop(axes, g, style(c))
        drawn.append(g)
        handles.append(Line2D([], [], color=style(c), lw=2))
        labels.append(free_play_label(c, g))
    lo, hi = FIT_WINDOW
    m_max = max(g["m_max"] for g in drawn)
    for side in (1, -1):
        axes[1].axvspan(side * lo * m_max, side * hi * m_max, color="0.92", zorder=0)
    zoom_limits(axes[0], drawn, ZOOM)
    finish_free_play(fig, axes, study, cases, handles, labels)
    return fig


def finish_free_play(fig, axes, study, cases, handles, labels):
    lo, hi = FIT_WINDOW
    axes[0].set_ylabel("surface angle θ [deg]")
    axes[1].set_ylabel("θ − M/K [deg], K the mean of the branches' stiffnesses")
    axes[0].set_title(f"the loop near zero moment (|M| ≤ {ZOOM:g} M): the branch lines meet "
                      "M = 0 the free-play apart", fontsize="small", loc="left")
    axes[1].set_title("the loop less the elastic deflection; grey: the fit windows",
                      fontsize="small", loc="left")
    for ax in axes:
        ax.set_xlabel(H.axis_label("hinge moment", cases[0].unit("hinge_moment")))
        ax.grid(True, alpha=0.3)
    handles += [Line2D([], [], color="k", lw=0.9),
                Line2D([], [], color="k", ls="--", lw=0.9),
                Line2D([], [], ls="", marker="o", mfc="white", mec="k", ms=5),
                Line2D([], [], ls="", marker="v", color="0.6", mec="k", mew=0.5, ms=6),
                Patch(color="0.92")]
    labels += [f"branch line: least squares of θ over {lo:g} M ≤ |M| ≤ {hi:g} M (the last period)",
               "the line extrapolated to M = 0",
               "its value at M = 0: free-play = upper − lower",
               f"ringing after the crossings (|M| < {lo:g} M): the highest and lowest θ − M/K "
               "(read peak to peak, they overstate the free-play)",
               "fit windows"]
    H.bottom_legend(fig, handles, labels)
    H.set_suptitle(fig, H.title(study, "Free-play ground test: surface angle against a slowly "
                                "reversing hinge moment, actuator holding, periods after the "
                                "first (docs/inputs.md)"))
