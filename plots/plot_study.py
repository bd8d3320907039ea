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
                           (both: at most 9 cases, those of the largest peak contact force, said in
                           the title; on a designed study, every figure of one curve per case too)
  surface_angle            surface angle and its difference to the first case (5.17)
  trajectories_xy_xz       xy and xz trajectories when the ball leaves the xy-plane (5.18-5.20)
  first_impact_force       summary metric first_impact_peak_force against the first numeric grid axis (5.15);
                           a designed study: one point per case against its first factor, no line
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

The figures are drawn by family, one file each beside this one: contact_figures.py,
actuator_figures.py, motion_figures.py, wear_figures.py, slider_crank_figures.py and
input_figures.py, with what they share in figure_kit.py.

Each PNG carries its caption (its title) and the question it answers ("cases") as text chunks,
which `rodend report` reads. Needs only Debian's numpy, h5py and matplotlib (Agg backend).
"""
import argparse
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

from rodend import NotAStudy, open_study  # noqa: E402

import figure_kit  # noqa: E402
# each family registers its figures on import
import actuator_figures  # noqa: E402,F401
import contact_figures  # noqa: E402,F401
import input_figures  # noqa: E402,F401
import motion_figures  # noqa: E402,F401
import slider_crank_figures  # noqa: E402,F401
import wear_figures  # noqa: E402,F401

# the drawing order (file stems): the list of the docstring above
ORDER = ("eccentricity_force", "polar_relative_position", "polar_force_wear", "surface_angle",
         "trajectories_xy_xz", "first_impact_force", "hydraulics", "actuator_response",
         "spring_forces", "hinge_moment", "phase_fft", "energy_audit", "ball_motion",
         "body_motion", "wear_maps", "wear_evolution", "slider_acceleration", "bode",
         "free_play_loop")


def figures():
    """[(file stem, what, function)] of every registered figure in ORDER (any not in it last)."""
    rank = {stem: i for i, stem in enumerate(ORDER)}
    return sorted(figure_kit.FIGURES, key=lambda f: rank.get(f[0], len(ORDER)))


def save(fig, path, dpi, caption=None):
    """Save a figure. The constrained layout is computed once and then frozen: savefig would
    otherwise draw the whole figure once more just to lay it out. A PNG carries the question
    it answers and its caption as text chunks (rodend-question "cases", Description), which
    `rodend report` groups and captions it by."""
    engine = fig.get_layout_engine()
    if engine is not None:
        engine.execute(fig)
        with matplotlib.rc_context({"figure.autolayout": False,
                                    "figure.constrained_layout.use": False}):
            fig.set_layout_engine(None)         # None, not "none": no placeholder engine
    meta = {"rodend-question": "cases", "Description": caption} \
        if caption and path.endswith(".png") else None
    fig.savefig(path, dpi=dpi, metadata=meta)


def caption_of(what, fig):
    """A one-sentence caption: the figure's title (its first line), else what it shows."""
    text = fig._suptitle.get_text() if fig._suptitle is not None else ""
    if not text and fig.axes:
        text = fig.axes[0].get_title()
    first = (text.split("\nstudy ")[0] or what).replace("\n", " ")
    return first[:1].upper() + first[1:].rstrip(".") + "."


def main(argv=None):
    p = argparse.ArgumentParser(description="Draw the figures of a rodend study's results.")
    p.add_argument("results_dir", help="a study's results folder (with summary.h5 and cases/)")
    p.add_argument("--pdf", action="store_true", help="write a PDF beside each PNG")
    p.add_argument("--out", help="output folder (default: RESULTS_DIR/plots)")
    p.add_argument("--dpi", type=int, default=150, help="PNG resolution (default 150)")
    p.add_argument("--no-title", action="store_true",
                   help="no figure titles (for publication: the caption says it)")
    args = p.parse_args(argv)
    figure_kit.SHOW_TITLES = not args.no_title

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

    style = figure_kit.Style(study)
    status = 0
    for stem, what, fn in figures():
        drawn, study.cases_note = figure_kit.drawn_cases(study, cases, stem)
        try:
            fig = fn(study, drawn, style)
        except figure_kit.Skip as e:
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
            save(fig, path, args.dpi, caption_of(what, fig))
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
