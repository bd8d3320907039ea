"""The motion figures of plots/plot_study.py: the energy audit, the ball's (and socket's)
motion in scenes without a mechanism, and a free body's motion.
"""
import numpy as np
import matplotlib.pyplot as plt

from figure_kit import (
    Skip, axis_label, case_legend, figure, moving_components, set_suptitle, sig, sigs,
    time_rows, title, with_signals)


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
