"""The contact figures of plots/plot_study.py: eccentricity and contact force, the ball's
position relative to the socket and the force and wear over the contact angle (polar), the
trajectories out of the xy-plane, and the first-impact peak force against the grid.
"""
import numpy as np
import matplotlib.pyplot as plt
from matplotlib.lines import Line2D

from rodend.naming import coordinate_label, format_value, short_key
from figure_kit import (
    DISPLAY, NONZERO_Z, POLAR_BINS, Skip, axis_label, bottom_legend, case_legend,
    clearance_circle, clearance_lines, clearance_of, contact_angles, figure, finite_max,
    is_designed, polar_panels, readable_cases, sample_weights, set_axes_title, set_suptitle,
    shown, sig, sigs, step_polygon, title, with_signals)


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
    cases, which = readable_cases(study, with_signals(cases, "relative_position"))
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
                              "(thesis fig. 5.4, 5.11, 6.15)" + (f",\n{which}" if which else "")))
    case_legend(fig, cases, style, extra)
    return fig


@figure("polar_force_wear", "polar contact force and wear (fig. 5.5, 6.29)")
def fig_polar_force_wear(study, cases, style):
    cases = with_signals(cases, "contact_force")
    cases = [c for c in cases if c.has("contact_angle") or c.has("relative_position")]
    if not cases:
        raise Skip("neither contact_angle nor relative_position recorded")
    cases, which = readable_cases(study, cases)
    # bins centred on multiples of 360/POLAR_BINS degrees (0°, 90°, 270° are bin centres)
    half = np.pi / POLAR_BINS
    edges = np.linspace(-np.pi - half, np.pi - half, POLAR_BINS + 1)
    data = [(c, *force_wear_bins(c, edges)) for c in cases]
    if not any(d[1].max() > 0 for d in data):
        raise Skip("no contact in any case (contact_force is zero throughout)")
    fig, axes, legend_axes = polar_panels(len(data))
    for ax, lax, (c, fmax, wear) in zip(axes, legend_axes, data):
        # a fixed title height: the automatic one measures the theta labels 3 times per draw
        ax.set_title(c.describe("\n"), fontsize="small", color=style(c), y=1.12)
        ax.set_yticklabels([])
        ax.set_ylim(0, 1.05)
        if fmax.max() <= 0:
            ax.text(0, 0, "no contact", ha="center", va="center")
            continue
        handles = force_wear_panel(ax, style(c), edges, fmax, wear)
        lax.legend([h for h, _ in handles], [l for _, l in handles], loc="upper center",
                   fontsize="x-small", frameon=False)
    set_suptitle(fig, title(study, f"Contact force and wear over the contact angle in the xy-plane, "
                              f"{POLAR_BINS} bins,\neach normalised to its maximum "
                              f"(thesis fig. 5.5, 6.29)" + (f"; {which}" if which else "")))
    return fig



def force_wear_bins(c, edges):
    """(peak contact force per contact-angle bin [N], time-integrated wear per bin [J] or
    None when wear_indicator is not recorded) of one case."""
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
    return fmax, wear


def force_wear_panel(ax, color, edges, fmax, wear):
    """Draws one case's force and wear outlines with the angles of their maxima; returns the
    legend entries [(handle, label)]."""
    centres = 0.5 * (edges[:-1] + edges[1:])
    th, r = step_polygon(edges, fmax / fmax.max())
    ax.fill(th, r, color=color, alpha=0.35, lw=0)
    k = int(np.argmax(fmax))
    deg_f = np.degrees(centres[k]) % 360
    ax.plot([centres[k]] * 2, [0, 1.05], color="tab:blue", lw=1.6, ls="--", zorder=4)
    handles = [(Line2D([], [], color=color, lw=6, alpha=0.35),
                f"peak contact force (largest sample {fmax.max():.3g} N)"),
               (Line2D([], [], color="tab:blue", lw=1.6, ls="--"), f"max force at {deg_f:.0f}°")]
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
    return handles

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
    numeric = [k for k in study.numeric_grid_keys() if k in study.varying_keys
               and k != "design.sample"]
    if not numeric:
        raise Skip("no numeric grid axis that varies")
    if is_designed(study):
        return first_impact_samples(study, metric, numeric[0])
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
    along, others = split_keys(study, xkey, x_raw, rows_ok)
    groups = {}
    for r in rows_ok:
        groups.setdefault(tuple(format_value(study.summary[k][r]) for k in others), []).append(r)
    ylabel = axis_label("first-impact peak contact force", study.units.get(metric, "N"))
    if len(groups) > 1 and min(len(g) for g in groups.values()) == 1:
        # the grid does not give a line against x (zipped axes): one bar per case
        return first_impact_bars(study, cases, style, rows_ok, y_all, xkey, ylabel)
    fig, ax = plt.subplots(figsize=(7.5, 4.8), layout="constrained")
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


def split_keys(study, xkey, x_raw, rows_ok):
    """(along, others): the other varying grid keys, those zipped with x (one value per x)
    going along with it, the rest splitting the points into lines."""
    along, others = [], []
    for k in study.varying_keys:
        if k == xkey:
            continue
        per_x = {}
        for r in rows_ok:
            per_x.setdefault(x_raw[r], set()).add(format_value(study.summary[k][r]))
        (along if all(len(v) == 1 for v in per_x.values()) else others).append(k)
    return along, others


def first_impact_bars(study, cases, style, rows_ok, y_all, xkey, ylabel):
    """One bar per ok case, where zipped axes give no line against x."""
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


def first_impact_samples(study, metric, xkey):
    """A designed study: each ok case a point against the first factor, no line (the samples
    have no order; `rodend analyze` draws the metric against every factor)."""
    x, xunit = shown(study.summary[xkey].astype(float), study.summary_unit(xkey))
    y = study.summary[metric].astype(float)
    ok = np.isfinite(x) & np.isfinite(y)
    if "status" in study.summary:
        ok &= np.array([s == "ok" for s in study.summary["status"]])
    if not ok.any():
        raise Skip(f"no case finished ok with a finite {metric}")
    fig, ax = plt.subplots(figsize=(7.5, 4.8), layout="constrained")
    ax.plot(x[ok], y[ok], "o", ms=4, alpha=0.7)
    ax.set_xlabel(axis_label(short_key(xkey), xunit))
    ax.set_ylabel(axis_label("first-impact peak contact force", study.units.get(metric, "N")))
    ax.grid(True, alpha=0.3)
    set_axes_title(ax, title(study, f"First-impact peak contact force against {short_key(xkey)},"
                              f"\none point per sampled case ({int(ok.sum())} ok)"))
    return fig
