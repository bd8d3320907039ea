"""Post-processing: plots/plot_study.py draws the figures that fit a study and says why it skips
the others; it refuses a folder that is not a study (exit 2, one line, no traceback) and
survives studies that record only some signals.

Usage (CTest): test_plots.py PLOTS_DIR, with RODEND set to the rodend executable."""
import glob
import json
import os
import shutil
import subprocess
import sys
import tempfile

import h5py

from common import check, finish, reseal, run, write_study

PLOTS = os.path.abspath(sys.argv[1])
SCRIPT = os.path.join(PLOTS, "plot_study.py")
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"

# the figures, by file stem, and the start of the line that says one is skipped
SKIP_LINE = {
    "eccentricity_force": "skip eccentricity and contact force",
    "polar_relative_position": "skip polar relative position",
    "polar_force_wear": "skip polar contact force and wear",
    "surface_angle": "skip surface angle",
    "trajectories_xy_xz": "skip xy and xz trajectories",
    "first_impact_force": "skip first-impact peak force",
    "hydraulics": "skip hydraulics",
    "actuator_response": "skip actuator response",
    "spring_forces": "skip spring forces and moments",
    "hinge_moment": "skip applied hinge moment",
    "phase_fft": "skip phase diagram",
    "energy_audit": "skip energy audit",
    "ball_motion": "skip ball motion",
    "body_motion": "skip free-body motion",
    "slider_acceleration": "skip slider acceleration",
}


def plot(args):
    return subprocess.run([sys.executable, SCRIPT] + args, capture_output=True, text=True)


def simulate(tmp, doc):
    path = write_study(os.path.join(tmp, doc["name"] + ".json"), doc)
    r = run(["run", path, "--results-root", tmp, "-q"])
    check(r.returncode == 0, f"{doc['name']}: rodend run failed: {r.returncode} {r.stderr}")
    return os.path.join(tmp, doc["name"])


def expect_figures(what, r, out, drawn, formats=("png",)):
    """plot_study succeeded, wrote exactly the drawn figures and printed a skip line for each
    of the others."""
    check(r.returncode == 0, f"{what}: exit {r.returncode}\n{r.stdout}\n{r.stderr}")
    check("Traceback" not in r.stderr and "error drawing" not in r.stderr,
          f"{what}: errors on stderr:\n{r.stderr}")
    lines = r.stdout.splitlines()
    for stem in SKIP_LINE:
        for ext in formats:
            path = os.path.join(out, f"{stem}.{ext}")
            if stem in drawn:
                check(os.path.isfile(path) and os.path.getsize(path) > 1000,
                      f"{what}: {stem}.{ext} missing or empty")
                check(any(l.strip() == path for l in lines),
                      f"{what}: {path} not printed:\n{r.stdout}")
                if os.path.isfile(path):
                    with open(path, "rb") as f:
                        head = f.read(8)
                    magic = PNG_MAGIC if ext == "png" else b"%PDF"
                    check(head.startswith(magic), f"{what}: {stem}.{ext} is not a {ext}: {head!r}")
            else:
                check(not os.path.exists(path), f"{what}: {stem}.{ext} written but should be skipped")
        if stem not in drawn:
            check(any(l.startswith(SKIP_LINE[stem]) and ": " in l for l in lines),
                  f"{what}: no skip line for {stem}:\n{r.stdout}")
    extra = sorted(os.path.basename(p) for p in glob.glob(os.path.join(out, "*"))
                   if os.path.splitext(os.path.basename(p))[0] not in drawn)
    check(not extra, f"{what}: unexpected files {extra}")


PSC_DRAWN = {"eccentricity_force", "polar_relative_position", "polar_force_wear", "first_impact_force",
             "energy_audit", "slider_acceleration"}

with tempfile.TemporaryDirectory() as tmp:
    # a 2-case clearance sweep on the mechanism, short: extension starts, first impacts
    kin = simulate(tmp, {
        "name": "kin",
        "scene": "rod-end-kinematic",
        "integrator": {"method": "dopri5", "abs_tol": 1e-6, "rel_tol": 1e-6, "max_step": 1e-3},
        "time": {"end": 0.6, "sample_interval": 2e-4},
        "grid": [{"key": "parameters.contact.clearance", "values": [2e-4, 5e-4]}],
    })
    r = plot([kin])
    expect_figures("kinematic", r, os.path.join(kin, "plots"),
                   {"eccentricity_force", "polar_relative_position", "polar_force_wear",
                    "surface_angle", "first_impact_force", "phase_fft", "energy_audit",
                    "spring_forces"})
    check("skip phase diagram" not in r.stdout, "kinematic: phase diagram skipped")
    check(any(l.startswith("skip applied hinge moment") and "no hinge moment" in l
              for l in r.stdout.splitlines()), f"kinematic: hinge-moment skip reason:\n{r.stdout}")
    check("not recorded" in next((l for l in r.stdout.splitlines()
                                  if l.startswith("skip hydraulics")), ""),
          f"kinematic: the hydraulics skip line does not say the signals are missing:\n{r.stdout}")

    # the scene as a grid axis (kinematic and full system side by side) with a hinge moment:
    # the figures of both scenes, the actuator's drawn from its cases only
    both = simulate(tmp, {
        "name": "both",
        "parameters": {"hinge.kind": "constant", "hinge.constant_moment": -20.0},
        "integrator": {"method": "dopri5", "abs_tol": 1e-6, "rel_tol": 1e-6, "max_step": 1e-3},
        "time": {"end": 0.3, "sample_interval": 5e-4},
        "grid": [{"key": "scene", "values": ["rod-end-kinematic", "rod-end-actuator"]},
                 {"key": "parameters.contact.clearance", "values": [5e-4]}],
    })
    r = plot([both])
    expect_figures("scene axis", r, os.path.join(both, "plots"),
                   {"eccentricity_force", "polar_relative_position", "polar_force_wear",
                    "surface_angle", "phase_fft", "energy_audit",
                    "spring_forces", "hinge_moment", "hydraulics", "actuator_response"})
    # rodend report: one self-contained page with the summary, the figures and the provenance
    r = run(["report", kin])
    page = os.path.join(kin, "report.html")
    check(r.returncode == 0 and r.stdout.strip() == page, f"report: {r.returncode} {r.stderr}")
    with open(page, encoding="utf-8") as f:
        html = f.read()
    # every figure embedded, or past the page's budget of figures linked with its caption
    pngs = glob.glob(os.path.join(kin, "plots", "*.png"))
    embedded, linked = html.count('src="data:image/png;base64,'), html.count('class="more"')
    check(embedded + linked == len(pngs) and embedded >= 1 and len(pngs) >= 5,
          f"report: {embedded} embedded and {linked} linked figures, {len(pngs)} drawn")
    budget = 1_300_000   # app/report_sections.hpp figure_budget_bytes
    check(linked == 0 or sum(os.path.getsize(p) for p in pngs) > budget,
          "report: figures linked although they fit the budget")
    check(os.path.getsize(page) < 2_000_000, f"report of {os.path.getsize(page)} bytes")
    check("What happened in the cases?" in html and "<figcaption>Eccentricity" in html,
          "report: the study's figures are not grouped and captioned by their titles")
    check("max_contact_force [N]" in html and "git_revision" in html and "<h1>Study kin</h1>" in html,
          "report: no summary table header with units, provenance or title")
    check("src=\"plots/" not in html, "report: an image not embedded in the page")
    r = run(["report", os.path.join(tmp, "nope")])
    check(r.returncode == 2 and "nope" in r.stderr, f"report of a missing folder: {r.returncode} {r.stderr}")

    # a designed study (12 sampled drops): the first-impact figure is a cloud against the first
    # factor, no line in sample order; the polar panels show 9 cases and say which
    designed = simulate(tmp, {
        "name": "designed", "scene": "gravity-drop",
        "time": {"end": 0.015, "sample_interval": 1e-3},
        "design": {"method": "monte-carlo", "size": 12, "seed": 4, "factors": [
            {"key": "parameters.contact.clearance", "distribution": "uniform",
             "lower": 1e-4, "upper": 5e-4}]},
    })
    r = plot([designed])
    check(r.returncode == 0, f"designed: exit {r.returncode}\n{r.stderr}")
    from PIL import Image
    out = os.path.join(designed, "plots")
    cap = Image.open(os.path.join(out, "first_impact_force.png")).text.get("Description", "")
    check("against contact.clearance" in cap and "one point per sampled case (12 ok)" in cap,
          f"designed: first-impact figure caption {cap!r}")
    cap = Image.open(os.path.join(out, "polar_relative_position.png")).text.get("Description", "")
    check("the 9 of 12 cases with the largest peak contact force" in cap,
          f"designed: polar figure caption {cap!r}")
    # so does every figure of one curve per case (a curve and a legend line per sample would
    # bury the axes), and says so
    cap = Image.open(os.path.join(out, "eccentricity_force.png")).text.get("Description", "")
    check("the 9 of 12 cases with the largest peak contact force" in cap,
          f"designed: eccentricity figure caption {cap!r}")
    # its report before any analysis: the answers section says how to get them
    r = run(["report", designed])
    with open(os.path.join(designed, "report.html"), encoding="utf-8") as f:
        html = f.read()
    check(r.returncode == 0 and "No analysis yet: <code>rodend analyze" in html and
          html.index("<h2>Answers") < html.index("<h2>Figures"),
          f"designed: the report does not point to rodend analyze ({r.returncode} {r.stderr})")
    # after the analysis: 12 points give a 5 % quantile no lower end at 95 % (0.95^12 > 0.025);
    # the answers show "none" there, not a blank
    a = run(["analyze", designed, "--no-plots", "--metric", "first_impact_speed"])
    r = run(["report", designed])
    with open(os.path.join(designed, "report.html"), encoding="utf-8") as f:
        html = f.read()
    check(a.returncode == 0 and r.returncode == 0 and '<span class="iv">[none, ' in html
          and "An interval's end is none where too few points give it." in html,
          f"designed: the quantile's missing end not shown as none ({a.returncode} {a.stderr})")

    # a scene without a mechanism, one case, no grid
    drop = simulate(tmp, {
        "name": "drop",
        "scene": "gravity-drop",
        "integrator": {"method": "dopri5", "abs_tol": 1e-8, "rel_tol": 1e-8, "max_step": 1e-3},
        "time": {"end": 0.05, "sample_interval": 1e-4},
    })
    r = plot([drop])
    expect_figures("gravity-drop", r, os.path.join(drop, "plots"),
                   {"eccentricity_force", "polar_relative_position", "polar_force_wear",
                    "energy_audit", "ball_motion"})
    check(any(l.startswith("skip phase diagram") and "surface_acceleration not recorded" in l
              for l in r.stdout.splitlines()), f"gravity-drop: phase-diagram skip reason:\n{r.stdout}")
    check(any(l.startswith("skip first-impact") and "grid" in l for l in r.stdout.splitlines()),
          f"gravity-drop: first-impact skip reason:\n{r.stdout}")

    # --no-title: the same figures without titles; legends give lengths in the axes' unit (mm)
    sys.path.insert(0, PLOTS)
    import matplotlib
    matplotlib.use("Agg")
    import plot_study  # noqa: F401  (puts the package rodend beside plots/ on the path)
    import contact_figures
    import figure_kit
    from rodend.naming import coordinate_label
    from rodend.study import open_study
    check(coordinate_label("parameters.contact.clearance", 1e-4, "m") ==
          "contact.clearance = 0.1 mm", "legend label of a length is not in mm")
    check(coordinate_label("parameters.contact.restitution", 0.8, "1") ==
          "contact.restitution = 0.8", "legend label of a number")
    r = plot([kin, "--no-title", "--out", os.path.join(tmp, "notitle")])
    check(r.returncode == 0, f"--no-title: exit {r.returncode}\n{r.stderr}")
    study = open_study(kin)
    for titled in (True, False):
        figure_kit.SHOW_TITLES = titled
        fig = contact_figures.fig_eccentricity_force(study, study.cases(), figure_kit.Style(study))
        has = fig._suptitle is not None and fig._suptitle.get_text() != ""
        check(has == titled, f"eccentricity_force: title {'missing' if titled else 'drawn'}")
        legend = [t.get_text() for leg in fig.legends for t in leg.get_texts()]
        check(any("mm" in t for t in legend) and not any(t.endswith(" m") for t in legend),
              f"eccentricity_force legend units: {legend}")
        matplotlib.pyplot.close(fig)
    # the figures read through the package's reader, which needs no compiled module: drawn
    # above without loading it, and drawn again with it withheld (as where it is not built)
    check("rodend._rodend" not in sys.modules, "the figures loaded the compiled module")
    withheld = os.path.join(tmp, "withheld")
    code = ("import runpy, sys, rodend\n"
            "def absent():\n    raise ImportError('compiled module withheld by test_plots')\n"
            "import rodend.extension\nrodend.extension.load = absent\n"
            f"sys.argv = [{SCRIPT!r}, {kin!r}, '--out', {withheld!r}]\n"
            f"runpy.run_path({SCRIPT!r}, run_name='__main__')\n")
    env = dict(os.environ, PYTHONPATH=os.path.join(PLOTS, os.pardir, "python"))
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
    check(r.returncode == 0 and len(glob.glob(os.path.join(withheld, "*.png"))) >= 5,
          f"figures without the compiled module: exit {r.returncode}\n{r.stderr[-2000:]}")
    # the figures ask the scene's features (case attribute features_json), not its signals: the
    # same gravity-drop files declared to have a mechanism lose ball_motion; files without the
    # attribute (older rodend) fall back to guessing from the signals
    for study, want in ((kin, ["contact", "mechanism", "energy_audit"]),
                        (drop, ["contact", "energy_audit"])):
        for path in glob.glob(os.path.join(study, "cases", "*.h5")):
            with h5py.File(path, "r") as f:
                got = json.loads(f.attrs["features_json"])
            check(got == want, f"{path}: features_json {got}, expected {want}")
    for what, features, drawn in (
            ("declared mechanism", json.dumps(["contact", "mechanism", "energy_audit"]),
             {"eccentricity_force", "polar_relative_position", "polar_force_wear", "energy_audit"}),
            ("no features_json", None,
             {"eccentricity_force", "polar_relative_position", "polar_force_wear", "energy_audit",
              "ball_motion"})):
        copy = os.path.join(tmp, "drop-" + what.replace(" ", "-"))
        shutil.copytree(drop, copy, ignore=shutil.ignore_patterns("plots"))
        for path in glob.glob(os.path.join(copy, "cases", "*.h5")):
            with h5py.File(path, "r+") as f:
                del f.attrs["features_json"]
                if features is not None:
                    f.attrs["features_json"] = features
            reseal(path)  # a file of another rodend version, not a damaged one
        expect_figures(f"gravity-drop, {what}", plot([copy]), os.path.join(copy, "plots"), drawn)

    # only two signals recorded: no crash, only the figure that fits
    few = simulate(tmp, {
        "name": "few",
        "scene": "gravity-drop",
        "integrator": {"method": "dopri5", "abs_tol": 1e-8, "rel_tol": 1e-8, "max_step": 1e-3},
        "time": {"end": 0.03, "sample_interval": 1e-4},
        "signals": ["eccentricity", "contact_force"],
        "grid": [{"key": "parameters.contact.restitution", "values": [0.5, 0.9]}],
    })
    r = plot([few])
    expect_figures("two signals", r, os.path.join(few, "plots"),
                   {"eccentricity_force", "first_impact_force"})
    check(any("relative_position not recorded" in l for l in r.stdout.splitlines()),
          f"two signals: no reason naming relative_position:\n{r.stdout}")

    # the actuator alone: its figures, PDF as well, into another folder
    act = simulate(tmp, {
        "name": "act",
        "scene": "servo-actuator",
        "integrator": {"method": "dopri5", "abs_tol": 1e-6, "rel_tol": 1e-6, "max_step": 1e-3},
        "time": {"end": 0.1, "sample_interval": 1e-4},
        "grid": [{"key": "parameters.actuator.proportional_gain", "values": [1.0, 2.0]}],
    })
    out = os.path.join(tmp, "act-figures")
    r = plot([act, "--pdf", "--out", out])
    expect_figures("servo-actuator, --pdf --out", r, out,
                   {"hydraulics", "actuator_response", "energy_audit"}, formats=("png", "pdf"))
    check(not os.path.exists(os.path.join(act, "plots")), "--out: wrote into the study folder too")

    # the planar slider-crank rig (issue 21): the ideal joint and one clearance, two revolutions
    psc = simulate(tmp, {
        "name": "psc",
        "scene": "planar-slider-crank",
        "integrator": {"preset": "fast"},
        "time": {"end": 0.24, "sample_interval": 2e-4},
        "grid": [{"zip": [
            {"key": "parameters.joints.rod_slider.model", "values": ["ideal", "clearance"]},
            {"key": "parameters.joints.rod_slider.clearance", "values": [0.0, 5e-4]}]}],
    })
    r = plot([psc])
    expect_figures("planar-slider-crank", r, os.path.join(psc, "plots"), PSC_DRAWN)

    # not a study: exit 2, one line naming the folder, no traceback, nothing written
    empty = os.path.join(tmp, "empty")
    os.mkdir(empty)
    no_cases = os.path.join(tmp, "no-cases")
    os.mkdir(no_cases)
    shutil.copy(os.path.join(kin, "summary.h5"), no_cases)
    junk = os.path.join(tmp, "junk")
    os.makedirs(os.path.join(junk, "cases"))
    with open(os.path.join(junk, "summary.h5"), "w") as f:
        f.write("not hdf5\n")
    for what, folder in (("empty folder", empty), ("missing folder", os.path.join(tmp, "nope")),
                         ("summary without cases", no_cases), ("corrupt summary", junk),
                         ("a cases folder", os.path.join(kin, "cases"))):
        r = plot([folder])
        message = (r.stdout + r.stderr).strip()
        check(r.returncode == 2, f"{what}: exit {r.returncode}, expected 2\n{message}")
        check("Traceback" not in message and len(message.splitlines()) == 1 and folder in message,
              f"{what}: expected one line naming the folder, got:\n{message}")
        check(not os.path.exists(os.path.join(folder, "plots")), f"{what}: wrote a plots folder")
finish("plots")
