#!/usr/bin/python3
"""Draw the figures of a rodend study's results.

    /usr/bin/python3 plots/plot_study.py RESULTS_DIR [--pdf] [--out DIR] [--dpi N]

Writes PNG figures (and PDF with --pdf) into RESULTS_DIR/plots/ (or --out): every figure that
fits the study's scene and recorded signals. Prints one line per file written and, for each
figure it does not draw, one line saying why ("skip ...: ..."). Exit status: 0 when every
figure that applies was drawn, 1 when drawing one failed (the others are still drawn),
2 when RESULTS_DIR is not a study's results folder.

Figures (file stem: what, thesis figure):
  eccentricity_force       eccentricity with the clearance, contact force (5.2; 3.24, 3.26)
  polar_relative_position  ball centre relative to the socket, xy-plane, clearance circle (5.4, 5.11, 6.15)
  polar_force_wear         peak contact force and time-integrated wear per contact-angle bin (5.5, 6.29)
  surface_angle            surface angle and its difference to the first case (5.17)
  trajectories_xy_xz       xy and xz trajectories when the ball leaves the xy-plane (5.18-5.20)
  first_impact_force       summary metric first_impact_peak_force against the first numeric grid axis (5.15)
  hydraulics               chamber pressures and flows, spool, actuator load (6.16-6.22)
  spring_forces            outer and inner 3-D spring forces and moments (5.3, 5.7, 5.8, 6.13-6.14, 6.27-6.28)
  hinge_moment             applied hinge moment, surface angle, actuator position (6.23-6.25)
  actuator_response        piston position against command and LVDT, velocity, current, jet pipe (6.10-6.11)
  phase_fft                surface angular acceleration against rate, and its amplitude spectrum
  energy_audit             mechanical-energy change, input work, dissipation, residual
  ball_motion              ball (and socket) motion and forces, scenes without a mechanism (3.24, 3.26)
  body_motion              free-body position, velocity, attitude, rates (3.21-3.23)
  bode                     frequency response: gain and phase of surface and piston against the drive
                           frequency, one surface curve per clearance (and amplitude), the piston's
                           clearances merged where they agree, the linearised model (docs/inputs.md)
  free_play_loop           free-play ground test: surface angle against hinge moment over the periods
                           after the first, near zero moment and less the elastic deflection, with the
                           metric's branch lines extrapolated to zero moment and the ringing marked
  slider_acceleration      planar-slider-crank: slider acceleration against crank angle over the last
                           full revolution, the ideal joint overlaid, and each clearance's eccentricity
                           orbit (journal centre relative to bearing centre) (Wang et al. 2019)

When the scene is a grid axis (kinematic and full-system runs in one study), the colour names
the grid point without the scene and the line style names the scene, so the curves the thesis
compares (fig. 6.11-6.15) are overlaid.

Needs only Debian's numpy, h5py and matplotlib (Agg backend).
"""
import argparse
import math
import os
import signal
import sys
import time
import traceback
import warnings

# the package rodend beside plots/ (its reader needs no compiled module), else an installed one
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "python"))
# the figure modules beside this file (also when it is run by runpy, which adds no path)
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

from rodend.naming import DISPLAY_UNITS, coordinate_label, format_value, short_key  # noqa: E402
from rodend.study import NotAStudy, open_study  # noqa: E402

import input_figures  # noqa: E402

# how each SI unit is shown on an axis: (shown unit, factor), one table shared with the legend
# labels (rodend.naming)
DISPLAY = DISPLAY_UNITS
POLAR_BINS = 72
NONZERO_Z = 1e-9          # [m] a case with |z| above this leaves the xy-plane


class Skip(Exception):
    """A figure that does not apply; the message says why."""


FIGURES = []              # (file stem, what, function) in drawing order


def figure(stem, what):
    def register(fn):
        FIGURES.append((stem, what, fn))
        return fn
    return register


# --- helpers ------------------------------------------------------------------------------

def shown(values, unit):
    """(values in the display unit, display unit)."""
    if unit in DISPLAY:
        name, factor = DISPLAY[unit]
        return np.asarray(values) * factor, name
    return np.asarray(values), unit


def pretty_unit(unit):
    """rad/s^2 -> rad/s², N*m -> N·m (only for display)."""
    unit = unit or ""
    for a, b in (("^-1", "⁻¹"), ("^2", "²"), ("^3", "³"), ("*", "·")):
        unit = unit.replace(a, b)
    return unit


def axis_label(name, unit):
    return f"{name} [{pretty_unit(unit)}]" if unit not in ("", "1", None) else name


def with_signals(cases, *names):
    """The cases that record every signal in names; Skip naming the first missing one if none."""
    names = ("time",) + tuple(n for n in names if n != "time")
    have = [c for c in cases if c.has(*names)]
    if not have:
        missing = next(n for n in names if not any(c.has(n) for c in cases))
        raise Skip(f"signal {missing} not recorded")
    have = [c for c in have if len(c.signal("time")) >= 2]
    if not have:
        raise Skip("no case has two samples or more")
    return have


def first_present(cases, *names):
    """The first of the alternative signal names that some case records (or None)."""
    for n in names:
        if any(c.has(n) for c in cases):
            return n
    return None


def sig(case, name):
    """A signal with every non-finite value (a run that blew up) as NaN, so it plots as a gap."""
    v = case.signal(name)
    if v.dtype.kind == "f" and not np.isfinite(v).all():
        v = np.where(np.isfinite(v), v, np.nan)
    return v


def sigs(case, *names):
    case.signals(*names)            # one opening of the file for all of them
    return [sig(case, n) for n in names]


def finite_max(values, default=0.0):
    """Largest finite value (default when there is none)."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    return float(v.max()) if v.size else default


def sample_weights(t):
    """Trapezoid weights: each sample's share of the time axis [s]."""
    w = np.zeros_like(t, dtype=float)
    if len(t) > 1:
        dt = np.diff(t)
        w[1:] += dt / 2
        w[:-1] += dt / 2
    return w


def clearance_of(case):
    c = case.parameter("contact.clearance")
    try:
        c = float(c)
    except (TypeError, ValueError):
        return None
    return c if math.isfinite(c) and c > 0 else None


def clearances_vary(cases):
    values = {clearance_of(c) for c in cases}
    return len(values) > 1


SCENE_LINES = ["-", "--", ":", "-."]


class Style:
    """One colour per case, fixed for the whole study so every figure matches. When the scene
    is a grid axis (kinematic and full-system runs side by side), the colour names the grid
    point without the scene and the line style names the scene (ls), so the runs the thesis
    compares (fig. 6.11-6.15) are overlaid in the same colour."""

    def __init__(self, study):
        cases = study.cases()
        self.scenes = study.scenes
        self.line = {s: SCENE_LINES[i % len(SCENE_LINES)] for i, s in enumerate(self.scenes)}
        if len(self.scenes) > 1:
            keys = []
            for c in cases:
                k = json_key({k: v for k, v in c.coordinates.items() if k != "scene"})
                if k not in keys:
                    keys.append(k)
            key_of = {c.id: json_key({k: v for k, v in c.coordinates.items() if k != "scene"})
                      for c in cases}
        else:
            keys = [c.id for c in cases]
            key_of = {c.id: c.id for c in cases}
        n = len(keys)
        if n <= 10:
            cmap = plt.get_cmap("tab10")
            colors = [cmap(i) for i in range(n)]
        else:
            cmap = plt.get_cmap("viridis")
            colors = [cmap(i / max(n - 1, 1)) for i in range(n)]
        by_key = dict(zip(keys, colors))
        self.color = {cid: by_key[k] for cid, k in key_of.items()}

    def __call__(self, case):
        return self.color.get(case.id, "k")

    def ls(self, case):
        """Line style of the case's scene (solid when the study has one scene)."""
        return self.line.get(case.scene, "-")

    def scene_entries(self):
        """Legend entries naming the line style of each scene (none for a single scene)."""
        if len(self.scenes) < 2:
            return []
        return [(Line2D([], [], color="0.3", ls=self.line[s], lw=1.5), f"{s} ({self.line[s]})")
                for s in self.scenes]


def json_key(d):
    return tuple(sorted((k, format_value(v)) for k, v in d.items()))


SHOW_TITLES = True        # --no-title: figures without their titles (for publication)


def title(study, text):
    return f"{text}\nstudy {study.name} ({', '.join(study.scenes)}, {len(study.cases())} case(s))"


def set_suptitle(fig, text, **kw):
    """The figure's title, unless --no-title."""
    if SHOW_TITLES:
        fig.suptitle(text, **kw)


def set_axes_title(ax, text, **kw):
    """A one-axes figure's title, unless --no-title."""
    if SHOW_TITLES:
        ax.set_title(text, **kw)


def case_legend(fig, cases, style, extra=()):
    """A figure legend below the axes naming each case's grid coordinates (plus extra
    (handle, label) entries)."""
    handles = [Line2D([], [], color=style(c), ls=style.ls(c), lw=2) for c in cases]
    labels = [c.label for c in cases]
    for h, l in list(style.scene_entries()) + list(extra):
        handles.append(h)
        labels.append(l)
    return bottom_legend(fig, handles, labels)


def bottom_legend(fig, handles, labels):
    """A legend in a band reserved at the bottom of a constrained-layout figure.

    The figure grows by the legend's height (and width if the legend is wider), and the
    layout keeps the axes out of the band, so the figure is saved as it is laid out (no
    bbox_inches="tight", which would draw everything twice).
    """
    longest = max((len(l) for l in labels), default=10)
    ncol = max(1, min(len(labels), int(90 // max(longest, 1))))
    leg = fig.legend(handles, labels, loc="lower center", bbox_to_anchor=(0.5, 0.0),
                     ncol=ncol, fontsize="small", frameon=False)
    bb = leg.get_window_extent(fig.canvas.get_renderer())
    w_in, h_in = bb.width / fig.dpi + 0.2, bb.height / fig.dpi + 0.05
    width, height = fig.get_size_inches()
    width, height = max(width, w_in), height + h_in
    fig.set_size_inches(width, height)
    engine = fig.get_layout_engine()
    if engine is not None and hasattr(engine, "set"):
        engine.set(rect=(0, h_in / height, 1, 1 - h_in / height))
    return leg


def clearance_lines(ax, cases, style, factor, both_signs=False):
    """Dotted clearance level(s); returns the legend entry."""
    values = [(c, clearance_of(c)) for c in cases if clearance_of(c)]
    if not values:
        return None
    vary = clearances_vary(cases)
    drawn = set()
    for c, v in values:
        if not vary and v in drawn:
            continue
        drawn.add(v)
        color = style(c) if vary else "k"
        ax.axhline(v * factor, color=color, ls=":", lw=0.9, alpha=0.8)
        if both_signs:
            ax.axhline(-v * factor, color=color, ls=":", lw=0.9, alpha=0.8)
    label = "clearance (dotted, case colour)" if vary else \
        f"clearance {format_value(values[0][1] * 1e3)} mm (dotted)"
    return Line2D([], [], color="k" if not vary else "0.4", ls=":", lw=0.9), label


def clearance_circle(ax, cases, style, factor, polar):
    """Dotted clearance circle(s) in a polar or cartesian axes; returns the legend entry."""
    values = [(c, clearance_of(c)) for c in cases if clearance_of(c)]
    if not values:
        return None
    vary = clearances_vary(cases)
    th = np.linspace(0, 2 * np.pi, 361)
    drawn = set()
    for c, v in values:
        if not vary and v in drawn:
            continue
        drawn.add(v)
        color = style(c) if vary else "k"
        lw, alpha = (1.0, 0.7) if vary else (1.3, 0.9)
        if polar:
            ax.plot(th, np.full_like(th, v * factor), color=color, ls=":", lw=lw, alpha=alpha,
                    zorder=2)
        else:
            ax.plot(v * factor * np.cos(th), v * factor * np.sin(th), color=color, ls=":",
                    lw=lw, alpha=alpha, zorder=2)
    label = "clearance circle (dotted, case colour)" if vary else \
        f"clearance circle {format_value(values[0][1] * 1e3)} mm (dotted)"
    return Line2D([], [], color="k" if not vary else "0.4", ls=":", lw=1.3), label


def contact_angles(case):
    """Contact angle [rad] per sample: the signal contact_angle, else atan2 of relative_position."""
    if case.has("contact_angle"):
        return sig(case, "contact_angle")
    r = sig(case, "relative_position")
    return np.arctan2(r[:, 1], r[:, 0])


# --- figures ------------------------------------------------------------------------------

@figure("eccentricity_force", "eccentricity and contact force (fig. 5.2)")
def fig_eccentricity_force(study, cases, style):
    cases = with_signals(cases, "eccentricity", "contact_force")
    fig, (ax1, ax2) = plt.subplots(2, 1, sharex=True, figsize=(8, 6.5), layout="constrained")
    e_unit = None
    for c in cases:
        t, e, f = sigs(c, "time", "eccentricity", "contact_force")
        e, e_unit = shown(e, c.unit("eccentricity"))
        ax1.plot(t, e, color=style(c), ls=style.ls(c), lw=0.9)
        ax2.plot(t, f, color=style(c), ls=style.ls(c), lw=0.9)
    factor = DISPLAY.get(cases[0].unit("eccentricity"), ("", 1.0))[1]
    extra = [x for x in [clearance_lines(ax1, cases, style, factor)] if x]
    ax1.set_ylabel(axis_label("eccentricity |e|", e_unit))
    ax2.set_ylabel(axis_label("contact force", cases[0].unit("contact_force")))
    ax2.set_xlabel(axis_label("time", cases[0].unit("time")))
    for ax in (ax1, ax2):
        ax.grid(True, alpha=0.3)
    ref = {"gravity-drop": "3.24", "spring-contact": "3.26"}.get(study.scene, "5.2")
    if len(study.scenes) > 1:
        ref = "6.12"
    elif study.scene == "rod-end-actuator":
        ref = "5.2, 6.12, 6.24"
    set_suptitle(fig, title(study, f"Eccentricity and contact force (thesis fig. {ref})"))
    case_legend(fig, cases, style, extra)
    return fig


@figure("polar_relative_position", "polar relative position (fig. 5.4, 5.11, 6.15)")
def fig_polar_relative_position(study, cases, style):
    cases = with_signals(cases, "relative_position")
    fig = plt.figure(figsize=(7.8, 7.6), layout="constrained")
    ax = fig.add_subplot(projection="polar")
    ax.set_title("", y=1.0)                     # no automatic title placement (costly on polar)
    rmax = 0.0
    for c in cases:
        r = sig(c, "relative_position")
        _, unit = shown(0.0, c.unit("relative_position"))
        factor = DISPLAY.get(c.unit("relative_position"), ("", 1.0))[1]
        radius = np.hypot(r[:, 0], r[:, 1]) * factor
        theta = np.full(len(r), np.nan)
        ok = np.isfinite(radius)
        theta[ok] = np.unwrap(np.arctan2(r[ok, 1], r[ok, 0]))   # no jumps across ±180°
        ax.plot(theta, radius, color=style(c), ls=style.ls(c), lw=1.3, zorder=3)
        rmax = max(rmax, finite_max(radius))
        if clearance_of(c):
            rmax = max(rmax, clearance_of(c) * factor)
    extra = [x for x in [clearance_circle(ax, cases, style, factor, polar=True)] if x]
    if rmax > 0:
        ax.set_rlim(0, rmax * 1.08)
    ax.set_rlabel_position(112.5)
    ax.text(np.radians(112.5), rmax * 1.22 if rmax > 0 else 1, f"radius [{unit}]",
            ha="center", va="center", fontsize="small")
    ax.set_xlabel("angle of p_ball − p_socket in the xy-plane [deg] (x along the rod)")
    set_suptitle(fig, title(study, "Ball centre relative to the socket centre, xy-plane "
                              "(thesis fig. 5.4, 5.11, 6.15)"))
    case_legend(fig, cases, style, extra)
    return fig


@figure("polar_force_wear", "polar contact force and wear (fig. 5.5, 6.29)")
def fig_polar_force_wear(study, cases, style):
    cases = with_signals(cases, "contact_force")
    cases = [c for c in cases if c.has("contact_angle") or c.has("relative_position")]
    if not cases:
        raise Skip("neither contact_angle nor relative_position recorded")
    # bins centred on multiples of 360/POLAR_BINS degrees (0°, 90°, 270° are bin centres)
    half = np.pi / POLAR_BINS
    edges = np.linspace(-np.pi - half, np.pi - half, POLAR_BINS + 1)
    centres = 0.5 * (edges[:-1] + edges[1:])
    data = []
    for c in cases:
        t, f = sigs(c, "time", "contact_force")
        ang = np.mod(contact_angles(c) - edges[0], 2 * np.pi) + edges[0]
        idx = np.clip(np.digitize(ang, edges) - 1, 0, POLAR_BINS - 1)
        touching = (f > 0) & np.isfinite(ang)
        fmax = np.zeros(POLAR_BINS)
        np.maximum.at(fmax, idx[touching], f[touching])
        wear = None
        if c.has("wear_indicator"):
            w = np.nan_to_num(sig(c, "wear_indicator") * sample_weights(t))
            wear = np.bincount(idx[touching], weights=w[touching], minlength=POLAR_BINS)
        data.append((c, fmax, wear))
    if not any(d[1].max() > 0 for d in data):
        raise Skip("no contact in any case (contact_force is zero throughout)")
    fig, axes, legend_axes = polar_panels(len(data))
    for ax, lax, (c, fmax, wear) in zip(axes, legend_axes, data):
        # a fixed title height: the automatic one measures the theta labels 3 times per draw
        ax.set_title(c.describe("\n"), fontsize="small", color=style(c), y=1.12)
        ax.set_yticklabels([])
        ax.set_ylim(0, 1.05)
        handles = []
        if fmax.max() <= 0:
            ax.text(0, 0, "no contact", ha="center", va="center")
            continue
        th, r = step_polygon(edges, fmax / fmax.max())
        ax.fill(th, r, color=style(c), alpha=0.35, lw=0)
        k = int(np.argmax(fmax))
        deg_f = np.degrees(centres[k]) % 360
        ax.plot([centres[k]] * 2, [0, 1.05], color="tab:blue", lw=1.6, ls="--", zorder=4)
        handles.append((Line2D([], [], color=style(c), lw=6, alpha=0.35),
                        f"peak contact force (largest sample {fmax.max():.3g} N)"))
        handles.append((Line2D([], [], color="tab:blue", lw=1.6, ls="--"),
                        f"max force at {deg_f:.0f}°"))
        if wear is not None and wear.max() > 0:
            th, r = step_polygon(edges, wear / wear.max())
            ax.plot(th, r, color="k", lw=1.1)
            j = int(np.argmax(wear))
            deg_w = np.degrees(centres[j]) % 360
            ax.plot([centres[j]] * 2, [0, 1.05], color="tab:red", lw=2.4, zorder=3)
            handles.append((Line2D([], [], color="k", lw=1.1),
                            f"wear ∫ F·v_slip dt (total {wear.sum():.3g} J)"))
            handles.append((Line2D([], [], color="tab:red", lw=2.4), f"max wear at {deg_w:.0f}°"))
        elif wear is not None:
            handles.append((Line2D([], [], color="none"), "no wear (no slip)"))
        else:
            handles.append((Line2D([], [], color="none"), "wear_indicator not recorded"))
        lax.legend([h for h, _ in handles], [l for _, l in handles], loc="upper center",
                   fontsize="x-small", frameon=False)
    set_suptitle(fig, title(study, f"Contact force and wear over the contact angle in the xy-plane, "
                              f"{POLAR_BINS} bins,\neach normalised to its maximum "
                              f"(thesis fig. 5.5, 6.29)"))
    return fig


def step_polygon(edges, values, per_bin=6):
    """Closed polar outline of a histogram over the full circle: an arc at each bin's value,
    radial steps between bins (arcs sampled with per_bin points so they stay round)."""
    frac = np.linspace(0.0, 1.0, per_bin)
    th = (edges[:-1, None] + frac[None, :] * np.diff(edges)[:, None]).ravel()
    r = np.repeat(np.asarray(values, dtype=float), per_bin)
    return np.append(th, th[0] + 2 * np.pi), np.append(r, r[0])


def polar_panels(n, panel=3.4):
    """Small multiples of polar axes, each with a legend slot beneath it."""
    ncol = min(n, 3)
    nrow = int(math.ceil(n / ncol))
    fig = plt.figure(figsize=(panel * ncol + 0.4, (panel + 1.0) * nrow + 0.9), layout="constrained")
    gs = fig.add_gridspec(2 * nrow, ncol, height_ratios=[panel, 0.95] * nrow)
    axes, legend_axes = [], []
    for i in range(n):
        row, col = divmod(i, ncol)
        axes.append(fig.add_subplot(gs[2 * row, col], projection="polar"))
        lax = fig.add_subplot(gs[2 * row + 1, col])
        lax.axis("off")
        legend_axes.append(lax)
    return fig, axes, legend_axes


@figure("surface_angle", "surface angle (fig. 5.17)")
def fig_surface_angle(study, cases, style):
    cases = with_signals(cases, "surface_angle")
    diff = len(cases) > 1
    fig, axes = plt.subplots(2 if diff else 1, 1, sharex=True, figsize=(8, 7 if diff else 4.8),
                             layout="constrained", squeeze=False,
                             gridspec_kw={"height_ratios": [3, 2] if diff else [1]})
    ax = axes[0, 0]
    ref = cases[0]
    t0, a0 = sigs(ref, "time", "surface_angle")
    for c in cases:
        t, a = sigs(c, "time", "surface_angle")
        a, unit = shown(a, c.unit("surface_angle"))
        ax.plot(t, a, color=style(c), ls=style.ls(c), lw=1.0)
        if diff:
            r, _ = shown(np.interp(t, t0, a0, left=np.nan, right=np.nan), ref.unit("surface_angle"))
            axes[1, 0].plot(t, a - r, color=style(c), ls=style.ls(c), lw=1.0)
    ax.set_ylabel(axis_label("surface angle θ", unit))
    if diff:
        axes[1, 0].set_ylabel(axis_label("θ − θ of the first case", unit))
        axes[1, 0].set_title(f"difference to the first case ({ref.label})", fontsize="small")
    axes[-1, 0].set_xlabel(axis_label("time", cases[0].unit("time")))
    for a_ in axes[:, 0]:
        a_.grid(True, alpha=0.3)
    set_suptitle(fig, title(study, "Control-surface angle (thesis fig. 5.17"
                                   + (", 6.11" if len(study.scenes) > 1 else "") + ")"))
    case_legend(fig, cases, style)
    return fig


@figure("trajectories_xy_xz", "xy and xz trajectories (fig. 5.18-5.20)")
def fig_trajectories(study, cases, style):
    cases = with_signals(cases, "relative_position")
    cases = [c for c in cases if not c.has_feature("planar")]
    if not cases:
        raise Skip("planar scene: no out-of-plane motion to show")
    z_moves = any(np.nanmax(np.abs(sig(c, "relative_position")[:, 2]), initial=0.0) > NONZERO_Z
                  for c in cases)
    grid_mis = "parameters.socket.misalignment_z" in study.varying_keys
    if not (z_moves or grid_mis):
        raise Skip("no case leaves the xy-plane (relative_position z = 0) and the grid does "
                   "not vary socket.misalignment_z")
    fig, (axy, axz) = plt.subplots(1, 2, figsize=(11, 5.6), layout="constrained")
    for c in cases:
        r = sig(c, "relative_position")
        r, unit = shown(r, c.unit("relative_position"))
        axy.plot(r[:, 0], r[:, 1], color=style(c), ls=style.ls(c), lw=0.8)
        axz.plot(r[:, 0], r[:, 2], color=style(c), ls=style.ls(c), lw=0.8)
        axy.plot(r[0, 0], r[0, 1], "o", color=style(c), ms=4)
        axz.plot(r[0, 0], r[0, 2], "o", color=style(c), ms=4)
    factor = DISPLAY.get(cases[0].unit("relative_position"), ("", 1.0))[1]
    extra = [x for x in [clearance_circle(axy, cases, style, factor, polar=False)] if x]
    clearance_circle(axz, cases, style, factor, polar=False)
    extra.append((Line2D([], [], color="0.3", marker="o", ls="none", ms=4), "start"))
    for ax, v in ((axy, "y"), (axz, "z")):
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel(axis_label("x (ball − socket)", unit))
        ax.set_ylabel(axis_label(f"{v} (ball − socket)", unit))
        ax.grid(True, alpha=0.3)
    axy.set_title("xy-plane (fig. 5.19)")
    axz.set_title("xz-plane (fig. 5.20); the clearance sphere's outline")
    set_suptitle(fig, title(study, "Trajectory of the ball relative to the socket (thesis fig. 5.18-5.20)"))
    case_legend(fig, cases, style, extra)
    return fig


@figure("first_impact_force", "first-impact peak force against the grid (fig. 5.15)")
def fig_first_impact(study, cases, style):
    metric = "first_impact_peak_force"
    if metric not in study.summary:
        raise Skip(f"metric {metric} not in the summary")
    numeric = [k for k in study.numeric_grid_keys() if k in study.varying_keys]
    if not numeric:
        raise Skip("no numeric grid axis that varies")
    xkey = numeric[0]
    x_raw = study.summary[xkey].astype(float)
    y_all = study.summary[metric].astype(float)
    ok = np.isfinite(x_raw) & np.isfinite(y_all)
    if not ok.any():
        raise Skip(f"{metric} is NaN in every case (no contact)")
    if "status" in study.summary:
        ok &= np.array([s == "ok" for s in study.summary["status"]])
        if not ok.any():
            raise Skip("no case finished ok")
    rows_ok = [int(r) for r in study.order if ok[r]]
    x_all, xunit = shown(x_raw, study.summary_unit(xkey))
    xname = axis_label(short_key(xkey), xunit)
    # the other varying grid keys: those zipped with x (one value per x) go along with it,
    # the rest split the points into lines
    along, others = [], []
    for k in study.varying_keys:
        if k == xkey:
            continue
        per_x = {}
        for r in rows_ok:
            per_x.setdefault(x_raw[r], set()).add(format_value(study.summary[k][r]))
        (along if all(len(v) == 1 for v in per_x.values()) else others).append(k)
    groups = {}
    for r in rows_ok:
        groups.setdefault(tuple(format_value(study.summary[k][r]) for k in others), []).append(r)
    fig, ax = plt.subplots(figsize=(7.5, 4.8), layout="constrained")
    ylabel = axis_label("first-impact peak contact force", study.units.get(metric, "N"))
    if len(groups) > 1 and min(len(g) for g in groups.values()) == 1:
        # the grid does not give a line against x (zipped axes): one bar per case
        plt.close(fig)
        fig, ax = plt.subplots(figsize=(11, 1.6 + 0.45 * len(rows_ok)), layout="constrained")
        by_id = {c.row: c for c in cases}
        pos = np.arange(len(rows_ok))[::-1]
        ax.barh(pos, y_all[rows_ok], height=0.6,
                color=[style(by_id[r]) if r in by_id else "0.5" for r in rows_ok])
        for p, r in zip(pos, rows_ok):
            ax.text(y_all[r], p, f" {y_all[r]:.4g}", va="center", fontsize="small")
        ax.set_yticks(pos)
        ax.set_yticklabels([by_id[r].label if r in by_id else str(r) for r in rows_ok],
                           fontsize="small")
        ax.set_xlabel(ylabel)
        ax.set_xlim(0, np.nanmax(y_all[rows_ok]) * 1.15)
        ax.grid(True, axis="x", alpha=0.3)
        set_axes_title(ax, title(study, f"First-impact peak contact force per case (thesis fig. 5.15); "
                                  f"\n{short_key(xkey)} is zipped with other keys, so one bar "
                                  f"per case"), fontsize="medium")
        return fig
    handles, labels = [], []
    for i, (key, rows) in enumerate(groups.items()):
        rows = sorted(rows, key=lambda r: x_all[r])
        (h,) = ax.plot(x_all[rows], y_all[rows], "o-", color=plt.get_cmap("tab10")(i % 10),
                       ms=6, lw=1.2)
        handles.append(h)
        parts = [coordinate_label(k, v, study.summary_unit(k)) for k, v in zip(others, key)]
        parts += [f"{short_key(k)} zipped with {short_key(xkey)}" for k in along]
        labels.append(", ".join(parts) if parts else
                      f"{len(rows)} case(s) with status ok of {len(study)}")
    ax.set_xlabel(xname)
    ax.set_ylabel(ylabel)
    ax.grid(True, alpha=0.3)
    ax.set_ylim(0, 1.1 * float(np.nanmax(y_all[rows_ok])))
    set_axes_title(ax, title(study, f"First-impact peak contact force against {short_key(xkey)} "
                              f"(thesis fig. 5.15)"))
    bottom_legend(fig, handles, labels)
    return fig


@figure("hydraulics", "hydraulics (fig. 6.16-6.22)")
def fig_hydraulics(study, cases, style):
    # (panel title, alternative signal names, component or None for a scalar)
    panels = [("chamber 1 (rear) pressure (fig. 6.16)", ("chamber_pressures", "chamber_pressure"), 0),
              ("chamber 2 (front) pressure (fig. 6.18)", ("chamber_pressures", "chamber_pressure"), 1),
              ("flow into chamber 1 (fig. 6.20)", ("chamber_flows", "chamber_flow"), 0),
              ("flow into chamber 2 (fig. 6.21)", ("chamber_flows", "chamber_flow"), 1),
              ("servovalve spool position (fig. 6.22)", ("spool_position",), None),
              ("actuator external force (fig. 6.17)", ("actuator_external_force",), None)]
    core = [first_present(cases, *names) for _, names, _ in panels[:5]]
    if not any(core):
        raise Skip("signals chamber_pressures, chamber_flows and spool_position not recorded "
                   "(no actuator in this scene)")
    drawn = []
    for what, names, k in panels:
        name = first_present(cases, *names)
        if not name:
            continue
        have = [c for c in cases if c.has("time", name) and len(c.signal("time")) >= 2]
        width = max(sig(c, name).reshape(len(c.signal("time")), -1).shape[1] for c in have) \
            if have else 0
        if not have or (k is not None and width <= k):
            continue
        drawn.append((what, name, k, have))
    if not drawn:
        raise Skip("no case has two samples or more")
    ncol = 2 if len(drawn) > 2 else 1
    nrow = int(math.ceil(len(drawn) / ncol))
    fig, axes = plt.subplots(nrow, ncol, sharex=True, figsize=(6.2 * ncol, 2.5 * nrow + 1.4),
                             layout="constrained", squeeze=False)
    axes = axes.ravel()
    for ax in axes[len(drawn):]:
        ax.set_visible(False)
    for ax, (what, name, k, have) in zip(axes, drawn):
        unit = ""
        for c in have:
            t, v = sigs(c, "time", name)
            v, unit = shown(v, c.unit(name))
            v = v.reshape(len(t), -1)
            ax.plot(t, v[:, 0 if k is None else k], color=style(c), ls=style.ls(c), lw=0.9)
        quantity = {"chamber_pressures": "pressure", "chamber_pressure": "pressure",
                    "chamber_flows": "flow", "chamber_flow": "flow",
                    "spool_position": "position", "actuator_external_force": "force"}[name]
        ax.set_ylabel(axis_label(quantity, unit))
        ax.set_title(what, fontsize="small", loc="left")
        ax.grid(True, alpha=0.3)
    time_unit = drawn[0][3][0].unit("time")
    for i, ax in enumerate(axes[:len(drawn)]):
        if i + ncol >= len(drawn):                 # lowest visible axes of its column
            ax.set_xlabel(axis_label("time", time_unit))
            ax.xaxis.set_tick_params(labelbottom=True)
    set_suptitle(fig, title(study, "Actuator chambers, flows, spool and load (thesis fig. 6.16-6.22)"))
    case_legend(fig, sorted({c for d in drawn for c in d[3]}, key=lambda c: c.row), style)
    return fig


@figure("actuator_response", "actuator response (fig. 6.10-6.11)")
def fig_actuator_response(study, cases, style):
    cases = with_signals(cases, "actuator_command", "actuator_position")

    def recorded(name):
        return any(c.has(name) for c in cases)

    rows = [("position", [("actuator_position", "-", "piston position"),
                          ("actuator_command", "--", "command")]
             + ([("lvdt_position", ":", "LVDT reading")] if recorded("lvdt_position") else []))]
    for quantity, name, what in (("velocity", "actuator_velocity", "piston velocity"),
                                 ("current", "controller_current", "torque-motor current"),
                                 ("deflection", "jet_pipe_position", "jet-pipe deflection")):
        if recorded(name):
            rows.append((quantity, [(name, "-", what)]))
    return time_rows("Actuator response to its command (thesis fig. 6.10-6.11)",
                     study, cases, style, rows)


@figure("spring_forces", "spring forces and moments (fig. 5.3, 5.7, 5.8, 6.13, 6.14, 6.27, 6.28)")
def fig_spring_forces(study, cases, style):
    # (panel title, signal, component)
    panels = [("outer (rod-socket) spring force, x (fig. 5.3, 6.13, 6.27)", "slider_spring_force", 0),
              ("outer (rod-socket) spring force, y (fig. 6.13, 6.27)", "slider_spring_force", 1),
              ("inner (ball-crank) spring force, x (fig. 5.7, 6.14, 6.28)", "crank_spring_force", 0),
              ("inner (ball-crank) spring force, y (fig. 6.14, 6.28)", "crank_spring_force", 1),
              ("outer spring moment, z (fig. 5.8)", "slider_spring_moment", 2),
              ("inner spring moment, z", "crank_spring_moment", 2)]
    cases = with_signals(cases, "slider_spring_force", "crank_spring_force")
    # a z component that moves (misalignment): its own panels
    for name, what in (("slider_spring_force", "outer"), ("crank_spring_force", "inner")):
        if any(2 in moving_components(sig(c, name)) for c in cases):
            panels.append((f"{what} spring force, z", name, 2))
    panels = [p for p in panels if any(c.has(p[1]) for c in cases)]
    nrow = int(math.ceil(len(panels) / 2))
    fig, axes = plt.subplots(nrow, 2, sharex=True, figsize=(12.4, 2.5 * nrow + 1.4),
                             layout="constrained", squeeze=False)
    axes = axes.ravel()
    for ax in axes[len(panels):]:
        ax.set_visible(False)
    for ax, (what, name, k) in zip(axes, panels):
        unit = ""
        for c in cases:
            if not c.has(name):
                continue
            t, v = sigs(c, "time", name)
            v = v.reshape(len(t), -1)
            unit = c.unit(name)
            ax.plot(t, v[:, k], color=style(c), ls=style.ls(c), lw=0.9)
        ax.axhline(0.0, color="0.5", lw=0.6)
        ax.set_ylabel(axis_label("moment" if "moment" in name else "force", unit))
        ax.set_title(what, fontsize="small", loc="left")
        ax.grid(True, alpha=0.3)
    for i, ax in enumerate(axes[:len(panels)]):
        if i + 2 >= len(panels):
            ax.set_xlabel(axis_label("time", cases[0].unit("time")))
            ax.xaxis.set_tick_params(labelbottom=True)
    set_suptitle(fig, title(study, "3-D spring forces (on the socket and on the ball) and moments "
                              "(thesis fig. 5.3, 5.7, 5.8, 6.13-6.14, 6.27-6.28)"))
    case_legend(fig, cases, style)
    return fig


@figure("hinge_moment", "applied hinge moment and surface angle (fig. 6.23-6.25)")
def fig_hinge_moment(study, cases, style):
    cases = with_signals(cases, "hinge_moment", "surface_angle")
    if not any(np.nanmax(np.abs(sig(c, "hinge_moment")), initial=0.0) > 0 for c in cases):
        raise Skip("no hinge moment in any case")
    rows = 3 if any(c.has("actuator_position") for c in cases) else 2
    fig, axes = plt.subplots(rows, 1, sharex=True, figsize=(8.5, 2.4 * rows + 1.6),
                             layout="constrained")
    for c in cases:
        t, m, a = sigs(c, "time", "hinge_moment", "surface_angle")
        axes[0].plot(t, m, color=style(c), ls=style.ls(c), lw=0.9)
        a, a_unit = shown(a, c.unit("surface_angle"))
        axes[1].plot(t, a, color=style(c), ls=style.ls(c), lw=0.9)
        if rows == 3 and c.has("actuator_position"):
            x, x_unit = shown(sig(c, "actuator_position"), c.unit("actuator_position"))
            axes[2].plot(t, x, color=style(c), ls=style.ls(c), lw=0.9)
            axes[2].set_ylabel(axis_label("actuator position", x_unit))
    axes[0].set_ylabel(axis_label("hinge moment", cases[0].unit("hinge_moment")))
    axes[0].set_title("applied hinge moment, counter-clockwise positive (fig. 6.25)",
                      fontsize="small", loc="left")
    axes[1].set_ylabel(axis_label("surface angle θ", a_unit))
    if rows == 3:
        axes[2].set_title("actuator position (fig. 6.23)", fontsize="small", loc="left")
    axes[-1].set_xlabel(axis_label("time", cases[0].unit("time")))
    for ax in axes:
        ax.grid(True, alpha=0.3)
    set_suptitle(fig, title(study, "Applied hinge moment, surface angle and actuator position "
                              "(thesis fig. 6.23-6.25)"))
    case_legend(fig, cases, style)
    return fig


@figure("phase_fft", "phase diagram and FFT of the surface acceleration")
def fig_phase_fft(study, cases, style):
    cases = with_signals(cases, "surface_acceleration", "surface_rate")
    fig, (ap, af) = plt.subplots(1, 2, figsize=(12, 5), layout="constrained")
    for c in cases:
        t, w, a = sigs(c, "time", "surface_rate", "surface_acceleration")
        ap.plot(w, a, color=style(c), lw=0.6, alpha=0.85)
        ok = np.isfinite(t) & np.isfinite(a)
        t, a = t[ok], a[ok]
        if len(t) < 16:
            continue
        dt = float(np.median(np.diff(t)))
        if np.ptp(np.diff(t)) > 1e-6 * dt:       # not uniformly sampled: resample
            tu = np.arange(t[0], t[-1], dt)
            a = np.interp(tu, t, a)
        x = a - np.mean(a)
        win = np.hanning(len(x))
        spec = 2.0 * np.abs(np.fft.rfft(x * win)) / np.sum(win)
        spec[0] /= 2.0
        freq = np.fft.rfftfreq(len(x), dt)
        af.loglog(freq[1:], spec[1:], color=style(c), lw=0.7)
    ap.set_xlabel(axis_label("surface angular rate $\\dot\\theta$", cases[0].unit("surface_rate")))
    ap.set_ylabel(axis_label("surface angular acceleration $\\ddot\\theta$", cases[0].unit("surface_acceleration")))
    ap.set_title("phase diagram")
    ap.grid(True, alpha=0.3)
    af.set_xlabel("frequency [Hz]")
    af.set_ylabel(axis_label("amplitude of $\\ddot\\theta$", cases[0].unit("surface_acceleration")))
    af.set_title("one-sided amplitude spectrum (Hann window, mean removed)")
    af.grid(True, which="major", alpha=0.3)
    af.minorticks_off()                         # minor log ticks cost more than they show
    set_suptitle(fig, title(study, "Surface angular acceleration: phase diagram and spectrum"))
    case_legend(fig, cases, style)
    return fig


@figure("energy_audit", "energy audit")
def fig_energy_audit(study, cases, style):
    names = ("mechanical_energy", "input_work", "dissipated_energy", "energy_residual")
    cases = with_signals(cases, *names)
    fig, axes = plt.subplots(2, 2, sharex=True, figsize=(11, 6.8), layout="constrained")
    panels = [("change of mechanical energy ΔE_mech", "mechanical_energy"),
              ("input work W_in", "input_work"),
              ("dissipated energy E_diss", "dissipated_energy"),
              ("residual ΔE_mech − W_in + E_diss", "energy_residual")]
    for ax, (what, name) in zip(axes.ravel(), panels):
        for c in cases:
            t, v = sigs(c, "time", name)
            if name == "mechanical_energy" and len(v):
                v = v - v[0]
            ax.plot(t, v, color=style(c), lw=0.9)
        ax.set_ylabel(axis_label(what, cases[0].unit(name)))
        ax.grid(True, alpha=0.3)
    for ax in axes[1]:
        ax.set_xlabel(axis_label("time", cases[0].unit("time")))
    rel = ""
    if "energy_residual" in study.summary:
        vals = np.asarray(study.summary["energy_residual"], dtype=float)
        if np.isfinite(vals).any():
            rel = f" (largest |residual| / largest energy flow: {np.nanmax(vals):.2g})"
    set_suptitle(fig, title(study, "Energy audit" + rel))
    case_legend(fig, cases, style)
    return fig


def moving_components(v):
    """Indices of the columns of v (samples, width) that change over the run."""
    v = np.asarray(v, dtype=float).reshape(len(v), -1)
    if not len(v):
        return []
    span = np.nanmax(v, axis=0) - np.nanmin(v, axis=0)
    scale = max(float(np.nanmax(np.abs(v))), 1e-300)
    return [k for k in range(v.shape[1]) if span[k] > 1e-9 * scale]


COMPONENT_STYLE = {0: "-", 1: "--", 2: ":"}
AXES_NAMES = "xyz"


def time_rows(fig_title, study, cases, style, rows):
    """Stacked panels of signals against time, one line per case (colour).

    rows: list of (quantity, [(signal, line style, name in the legend)]). A vector signal is
    drawn by its components that move in some case: alone, it is drawn solid and the panel
    names the component; otherwise components get line styles x -, y --, z :. Components that
    stay constant in every case are left out (the legend says so).
    """
    fig, axes = plt.subplots(len(rows), 1, sharex=True, figsize=(8.5, 2.3 * len(rows) + 1.6),
                             layout="constrained", squeeze=False)
    legend = {}
    flat = False
    for ax, (quantity, entries) in zip(axes[:, 0], rows):
        unit = ""
        names = []
        for name, ls, legend_name in entries:
            have = [c for c in cases if c.has(name)]
            if not have:
                continue
            width = max(sig(c, name).reshape(len(sig(c, name)), -1).shape[1] for c in have)
            moving = sorted({k for c in have for k in moving_components(sig(c, name))})
            if width > 1 and len(moving) < width:
                flat = True
            comps = moving or [0]
            single = width == 1 or (len(comps) == 1 and len(entries) == 1)
            big = max(float(np.nanmax(np.abs(sig(c, name)), initial=0.0)) for c in have)
            for c in have:
                t, v = sigs(c, "time", name)
                if c.unit(name) == "m" and big >= 1.0:     # metres stay metres
                    unit = "m"
                else:
                    v, unit = shown(v, c.unit(name))
                v = v.reshape(len(t), -1)
                for k in comps:
                    line = ls if (single and ls) else ("-" if single else COMPONENT_STYLE[k % 3])
                    ax.plot(t, v[:, k], color=style(c), ls=line, lw=0.9)
            if width == 1:
                names.append(legend_name)
                if len(entries) > 1:
                    legend.setdefault(legend_name, (Line2D([], [], color="0.3", ls=ls or "-"),
                                                    f"{legend_name} ({ls or '-'})"))
            elif single:
                names.append(f"{legend_name}, {AXES_NAMES[comps[0]]} component")
            else:
                names.append(legend_name)
                for k in comps:
                    legend.setdefault(f"~{k}", (Line2D([], [], color="0.3", ls=COMPONENT_STYLE[k % 3]),
                                                f"{AXES_NAMES[k]} component ({COMPONENT_STYLE[k % 3]})"))
        ax.set_ylabel(axis_label(quantity, unit), fontsize="small")
        ax.set_title(", ".join(names), fontsize="small", loc="left")
        ax.grid(True, alpha=0.3)
    axes[-1, 0].set_xlabel(axis_label("time", cases[0].unit("time")))
    set_suptitle(fig, title(study, fig_title))
    extra = [legend[k] for k in sorted(legend)]
    if flat:
        extra.append((Line2D([], [], color="none"), "constant components not drawn"))
    case_legend(fig, cases, style, extra)
    return fig


@figure("ball_motion", "ball motion (fig. 3.24, 3.26)")
def fig_ball_motion(study, cases, style):
    cases = [c for c in cases if not c.has_feature("mechanism")]
    if not cases:
        raise Skip(f"scene {study.scene} has a mechanism (its ball follows the crank: "
                   "see the other figures)")
    cases = with_signals(cases, "ball_position")

    def recorded(name):
        return any(c.has(name) for c in cases)

    rows = [("position", [("ball_position", None, "ball position")])]
    if recorded("socket_position") and any(moving_components(sig(c, "socket_position"))
                                           for c in cases if c.has("socket_position")):
        rows.append(("position", [("socket_position", None, "socket position")]))
    if recorded("drive_anchor_position"):
        rows.append(("position", [("drive_anchor_position", None, "driven end of the ball spring")]))
    if recorded("ball_velocity"):
        rows.append(("velocity", [("ball_velocity", None, "ball velocity")]))
    forces = [(n, ls, what) for n, ls, what in (("contact_force", "-", "contact force"),
                                                 ("friction_force", ":", "friction force"))
              if recorded(n)]
    if forces:
        rows.append(("force", forces))
    fig_no = {"gravity-drop": "thesis fig. 3.24", "spring-contact": "thesis fig. 3.25-3.26"}
    what = f" ({fig_no[study.scene]})" if study.scene in fig_no else ""
    return time_rows(f"Ball and socket motion{what}", study, cases, style, rows)


@figure("body_motion", "free-body motion (fig. 3.21-3.23)")
def fig_body_motion(study, cases, style):
    cases = with_signals(cases, "body_position")
    rows = [("position", [("body_position", None, "mass-centre position")])]
    for quantity, name, what in (("velocity", "body_velocity", "mass-centre velocity"),
                                 ("angle", "body_euler_321", "3-2-1 Euler angles"),
                                 ("angular velocity", "body_angular_velocity",
                                  "angular velocity, body frame")):
        if any(c.has(name) for c in cases):
            rows.append((quantity, [(name, None, what)]))
    return time_rows("Free-body motion (thesis fig. 3.21-3.23)", study, cases, style, rows)


# --- wear (issue 11) ------------------------------------------------------------------------

@figure("wear_maps", "wear maps of ball and socket beside the wear-indicator polar plot")
def fig_wear_maps(study, cases, style):
    cases = [c for c in cases if c.has_array("wear", "ball_depth")]
    if not cases:
        raise Skip("no wear maps (wear.model is not archard)")
    cases = cases[:6]
    fig = plt.figure(figsize=(13.5, 3.3 * len(cases)), layout="constrained")
    gs = fig.add_gridspec(len(cases), 3, width_ratios=[1.45, 1.45, 1])
    for row, c in enumerate(cases):
        lon, _ = c.array("wear", "longitude")
        lat, _ = c.array("wear", "latitude")
        evolved = c.has_array("evolution", "cycles")
        for col, body in enumerate(("ball", "socket")):
            depth, _ = c.array("wear", f"{body}_depth")
            ax = fig.add_subplot(gs[row, col])
            dl, dt = np.degrees(lon[1] - lon[0]), np.degrees(lat[1] - lat[0])
            extent = [np.degrees(lon[0]) - dl / 2, np.degrees(lon[-1]) + dl / 2,
                      np.degrees(lat[0]) - dt / 2, np.degrees(lat[-1]) + dt / 2]
            im = ax.imshow(depth * 1e6, origin="lower", extent=extent, aspect="auto",
                           cmap="magma_r", interpolation="nearest")
            # zoom on the worn band: rows with any wear, padded
            rows = np.nonzero(depth.max(axis=1) > 0)[0]
            if rows.size:
                lo = np.degrees(lat[max(rows[0] - 4, 0)]) - dt / 2
                hi = np.degrees(lat[min(rows[-1] + 4, lat.size - 1)]) + dt / 2
                ax.set_ylim(lo, hi)
            ax.set_xlabel(f"longitude in the {body} frame [°]")
            ax.set_ylabel("latitude [°]")
            vol = float(np.sum(depth * c.array("wear", f"{body}_cell_area")[0][:, None]))
            ax.set_title(f"{body}: max {depth.max() * 1e6:.3g} µm, volume {vol * 1e9:.3g} mm³"
                         + (" (final)" if evolved else " (this run)"), fontsize="small")
            fig.colorbar(im, ax=ax, label="worn depth [µm]", shrink=0.9)
        ax = fig.add_subplot(gs[row, 2], projection="polar")
        ax.set_title(c.describe("\n"), fontsize="x-small", color=style(c), y=1.1)
        if c.has("wear_indicator", "contact_force"):
            t, w, f = sigs(c, "time", "wear_indicator", "contact_force")
            ang = contact_angles(c)
            touching = (f > 0) & np.isfinite(ang)
            half = np.pi / POLAR_BINS
            edges = np.linspace(-np.pi - half, np.pi - half, POLAR_BINS + 1)
            idx = np.clip(np.digitize(np.mod(ang - edges[0], 2 * np.pi) + edges[0], edges) - 1,
                          0, POLAR_BINS - 1)
            wb = np.bincount(idx[touching], weights=np.nan_to_num(w * sample_weights(t))[touching],
                             minlength=POLAR_BINS)
            if wb.max() > 0:
                th, r = step_polygon(edges, wb / wb.max())
                ax.fill(th, r, color="tab:red", alpha=0.35, lw=0)
                ax.plot(th, r, color="tab:red", lw=1.0)
            ax.set_yticklabels([])
            ax.text(0.5, -0.12, "wear indicator ∫F·v_slip dt per contact angle (world xy-plane),"
                    + (" first duty cycle" if evolved else "") + " (thesis fig. 5.5)",
                    transform=ax.transAxes, ha="center", fontsize="x-small")
    set_suptitle(fig, title(study, "Archard wear maps (unrolled spheres, body frames) and the "
                              "wear indicator of the same case"))
    return fig


@figure("wear_evolution", "clearance and backlash against cycles")
def fig_wear_evolution(study, cases, style):
    cases = [c for c in cases if c.has_array("evolution", "cycles")]
    if not cases:
        raise Skip("not a wear-evolution study")
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.6), layout="constrained")
    for c in cases:
        n, _ = c.array("evolution", "cycles")
        axial, _ = c.array("evolution", "axial_clearance")
        worst, _ = c.array("evolution", "max_clearance")
        back, _ = c.array("evolution", "surface_backlash")
        col = style(c)
        axes[0].plot(n, axial * 1e3, color=col, marker=".", label=c.describe(", "))
        axes[0].plot(n, worst * 1e3, color=col, ls=":", lw=1)
        axes[1].plot(n, np.degrees(back), color=col, marker=".")
        vol, _ = c.array("evolution", "worn_volume")
        axes[2].plot(n, vol * 1e9, color=col, marker=".")
        row = c.row
        lim = study.summary.get("cycles_to_limit")
        if lim is not None and np.isfinite(lim[row]):
            for ax in axes[:2]:
                ax.axvline(lim[row], color=col, ls="--", lw=0.8)
    axes[0].set_ylabel("clearance [mm]: along the rod axis (solid), largest local (dotted)")
    axes[1].set_ylabel("surface backlash [°]")
    axes[2].set_ylabel("worn volume, ball + socket [mm³]")
    for ax in axes:
        ax.set_xlabel("duty cycles")
        ax.grid(True, alpha=0.3)
    axes[0].legend(fontsize="x-small")
    set_suptitle(fig, title(study, "Wear evolution: clearance, backlash and worn volume against "
                              "cycles (dashed: cycles to limit)"))
    return fig


# --- planar slider-crank (issue 21) ---------------------------------------------------------

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


# --- driver -------------------------------------------------------------------------------

# the inputs' figures (bode, free_play_loop) are in plots/input_figures.py
input_figures.register(sys.modules[__name__])


def save(fig, path, dpi):
    """Save a figure. The constrained layout is computed once and then frozen: savefig would
    otherwise draw the whole figure once more just to lay it out."""
    engine = fig.get_layout_engine()
    if engine is not None:
        engine.execute(fig)
        with matplotlib.rc_context({"figure.autolayout": False,
                                    "figure.constrained_layout.use": False}):
            fig.set_layout_engine(None)         # None, not "none": no placeholder engine
    fig.savefig(path, dpi=dpi)


def main(argv=None):
    p = argparse.ArgumentParser(description="Draw the figures of a rodend study's results.")
    p.add_argument("results_dir", help="a study's results folder (with summary.h5 and cases/)")
    p.add_argument("--pdf", action="store_true", help="write a PDF beside each PNG")
    p.add_argument("--out", help="output folder (default: RESULTS_DIR/plots)")
    p.add_argument("--dpi", type=int, default=150, help="PNG resolution (default 150)")
    p.add_argument("--no-title", action="store_true",
                   help="no figure titles (for publication: the caption says it)")
    args = p.parse_args(argv)
    global SHOW_TITLES
    SHOW_TITLES = not args.no_title

    try:
        study = open_study(args.results_dir)
        cases = study.cases()
        if not cases:
            raise NotAStudy(f"{args.results_dir}: no case files in cases/")
    except NotAStudy as e:
        print("plot_study: " + " ".join(str(e).split()), file=sys.stderr)
        return 2

    out = args.out or os.path.join(study.path, "plots")
    os.makedirs(out, exist_ok=True)
    if study.missing:
        print(f"note: {len(study.missing)} case(s) of the summary have no readable case file: "
              + ", ".join(study.missing))
    failed = [c for c in cases if c.status != "ok"]
    if failed:
        print(f"note: {len(failed)} case(s) did not finish ok; drawn up to where they stopped: "
              + ", ".join(f"{c.id} ({c.status})" for c in failed))

    style = Style(study)
    status = 0
    for stem, what, fn in FIGURES:
        try:
            fig = fn(study, cases, style)
        except Skip as e:
            print(f"skip {what}: {e}")
            continue
        except Exception as e:      # a bug must not stop the other figures
            print(f"error drawing {what}: {type(e).__name__}: {e}", file=sys.stderr)
            traceback.print_exc(limit=3, file=sys.stderr)
            plt.close("all")
            status = 1
            continue
        for ext in (("png", "pdf") if args.pdf else ("png",)):
            path = os.path.join(out, f"{stem}.{ext}")
            save(fig, path, args.dpi)
            print(path)
        plt.close(fig)
    return status


if __name__ == "__main__":
    signal.signal(signal.SIGPIPE, signal.SIG_DFL)   # `plot_study.py ... | head` ends quietly
    warnings.filterwarnings("ignore", category=RuntimeWarning)   # all-NaN slices of a failed run
    t0 = time.perf_counter()
    code = main()
    if os.environ.get("RODEND_PLOT_TIMING"):
        print(f"{time.perf_counter() - t0:.2f} s", file=sys.stderr)
    sys.exit(code)
