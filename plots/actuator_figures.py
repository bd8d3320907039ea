"""The mechanism and actuator figures of plots/plot_study.py: surface angle, hydraulics,
actuator response, spring forces, hinge moment, and the surface's phase plot and spectrum.
"""
import math
import numpy as np
import matplotlib.pyplot as plt

from figure_kit import (
    Skip, axis_label, case_legend, figure, first_present, moving_components, set_suptitle,
    shown, sig, sigs, time_rows, title, with_signals)


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
