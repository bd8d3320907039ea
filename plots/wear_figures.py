"""The wear figures of plots/plot_study.py: the wear maps over the contact angle and the wear's
evolution over the cycles.
"""
import numpy as np
import matplotlib.pyplot as plt

from figure_kit import (
    POLAR_BINS, Skip, contact_angles, figure, sample_weights, set_suptitle, sigs, step_polygon,
    title)


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
