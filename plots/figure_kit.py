"""What the figures of plots/plot_study.py share: the registry of figures (figure, FIGURES, Skip),
the display units, reading signals with gaps for non-finite values, the case colours and line
styles (Style), titles (SHOW_TITLES: --no-title), legends, clearance lines and circles, polar
panels and stacked time panels.

A figure family (contact_figures.py, actuator_figures.py, motion_figures.py, wear_figures.py,
slider_crank_figures.py, input_figures.py) registers each of its figures with
@figure(stem, what); plot_study.py draws them in its ORDER.
"""
import math
import textwrap

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.lines import Line2D

from rodend.naming import DISPLAY_UNITS, format_value


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


READABLE_CASES = 9       # a figure of one panel (or one curve) per case shows at most this many


def readable_cases(study, cases, limit=READABLE_CASES):
    """(at most `limit` cases, a note saying which): the cases with the largest peak contact
    force (summary metric max_contact_force) when there are more, else the first ones in case
    order; the note is empty when every case is kept."""
    if len(cases) <= limit:
        return cases, ""
    metric = "max_contact_force"
    if metric in study.summary:
        peak = np.asarray(study.summary[metric], dtype=float)
        ranked = sorted(cases, key=lambda c: -np.nan_to_num(peak[c.row], nan=-np.inf))
        return ranked[:limit], (f"the {limit} of {len(cases)} cases with the largest peak "
                                f"contact force")
    return cases[:limit], f"the first {limit} of {len(cases)} cases"


def is_designed(study):
    """A study with a sampled design: its cases are samples, not points of a line."""
    return "design.sample" in study.summary


# figures of one point per case (every sample of a design is drawn): the others draw one curve
# (or panel) per case and a legend line naming it
SAMPLE_FIGURES = {"first_impact_force", "bode", "free_play_loop"}


def drawn_cases(study, cases, stem):
    """(the cases figure `stem` draws, a note saying which or ""): a designed study's figures
    of one curve per case draw the readable_cases (a curve and a legend line for each of a
    hundred samples, each line naming every factor, would bury the axes); the note goes into
    the figure's title and caption (title())."""
    if stem in SAMPLE_FIGURES or not is_designed(study):
        return cases, ""
    return readable_cases(study, cases)


def json_key(d):
    return tuple(sorted((k, format_value(v)) for k, v in d.items()))


SHOW_TITLES = True        # --no-title: figures without their titles (for publication)


def title(study, text):
    """The figure's title: what it shows (the caption's sentence), with study.cases_note (which
    cases it draws, drawn_cases) when there is one, then the study's name, scenes and size."""
    note = getattr(study, "cases_note", "")
    text = f"{text},\n{note}" if note else text
    return f"{text}\nstudy {study.name} ({', '.join(study.scenes)}, {len(study.cases())} case(s))"


def set_suptitle(fig, text, **kw):
    """The figure's title, unless --no-title."""
    if SHOW_TITLES:
        fig.suptitle(text, **kw)


def set_axes_title(ax, text, **kw):
    """A one-axes figure's title, unless --no-title."""
    if SHOW_TITLES:
        ax.set_title(text, **kw)


LEGEND_LINE = 110        # characters: a longer case label is wrapped onto several lines


def case_legend(fig, cases, style, extra=()):
    """A figure legend below the axes naming each case's grid coordinates (plus extra
    (handle, label) entries)."""
    handles = [Line2D([], [], color=style(c), ls=style.ls(c), lw=2) for c in cases]
    labels = [textwrap.fill(c.label, LEGEND_LINE) for c in cases]   # a design's many factors
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
    longest = max((len(line) for l in labels for line in l.split("\n")), default=10)
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
