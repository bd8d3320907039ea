#!/usr/bin/env python3
"""Issue 36: the tables of docs/planar-slider-crank.md, "Against the measured rig", from the
summaries of the shipped studies (standard library only):

    build/rodend run studies/planar-slider-crank-clearance.json
    build/rodend run studies/planar-slider-crank-band.json
    build/rodend run studies/planar-slider-crank-start-angle.json    (the starting angle)
    build/rodend run studies/planar-slider-crank-flexible-rod.json   (issue 36 item 4a)
    build/rodend run studies/planar-slider-crank-guide.json          (item 4b)
    build/rodend run studies/planar-slider-crank-motor.json          (item 4c)
    build/rodend run studies/planar-slider-crank-all-joints.json     (item 5)
    build/rodend run studies/planar-slider-crank-combined.json       (items 4-5 at once)
    python3 scripts/slider-crank-comparison.py [results]

A study whose results are missing is skipped with a note (the baseline is required).

The measurement and the published Adams simulation are the values of the flap-actuation study
that quotes the rig (its Table 4; issue 36), crank at 500 rpm.
"""
import math
import os
import sys
from pathlib import Path

# the package rodend beside scripts/ (its reader needs no compiled module), else an installed one
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "python"))
from rodend import summary_rows  # noqa: E402

MEASURED = {1e-4: 268.0, 3e-4: 297.7, 5e-4: 345.4}  # [m/s^2] oscillation peak on the rig
ADAMS = {1e-4: 283.1, 3e-4: 318.2, 5e-4: 371.8}  # [m/s^2] the study's Adams model
CLEARANCE = "parameters.joints.rod_slider.clearance"
METRICS = [
    ("median_revolution_peak_slider_acceleration", "median revolution peak"),
    ("p95_revolution_peak_slider_acceleration", "95 % revolution peak"),
    ("lowpass_median_revolution_peak_slider_acceleration", "median, 1 kHz low-pass"),
    ("lowpass_p95_revolution_peak_slider_acceleration", "95 %, 1 kHz low-pass"),
    ("peak_slider_acceleration_settled", "largest (settled peak)"),
    ("slider_acceleration_peak_to_peak", "peak-to-peak"),
    ("steady_min_eccentricity_ratio", "min abs(e)/c"),
]


def rows(results, study):
    return summary_rows(Path(results) / study)


def err(x, ref):
    return f"{100.0 * (x - ref) / ref:+.0f} %"


def baseline(results):
    by_c = {}
    for r in rows(results, "planar-slider-crank-clearance"):
        assert r["status"] == "ok", r
        if r["parameters.joints.rod_slider.model"] == "clearance":
            by_c[float(r[CLEARANCE])] = r
    print("| clearance | measured | Adams (published) | " +
          " | ".join(label for _, label in METRICS[:4]) + " | settled | min abs(e)/c |")
    print("| --- " * 9 + "|")
    for c in sorted(MEASURED):
        r = by_c[c]
        m = MEASURED[c]
        cells = [f"{float(r[k]):.1f} ({err(float(r[k]), m)})" for k, _ in METRICS[:4]]
        print(f"| {c * 1e3:.1f} mm | {m} | {ADAMS[c]} ({err(ADAMS[c], m)}) | " + " | ".join(cells) +
              f" | {int(float(r['slider_response_settled']))} | "
              f"{float(r['steady_min_eccentricity_ratio']):.3f} |")


FRICTION = "parameters.friction.dynamic_coefficient"


def friction_group(r):
    """The band's two friction readings: the frictionless joint (c_f = 0, the published Adams
    contact code's normal force only) and the dry joint (c_f 0.1-0.3)."""
    return "frictionless" if float(r[FRICTION]) == 0.0 else "dry"


def band(results):
    by_c = {}
    for r in rows(results, "planar-slider-crank-band"):
        assert r["status"] == "ok", r
        by_c.setdefault((friction_group(r), float(r[CLEARANCE])), []).append(r)
    print("| joint | clearance | cases | settled | measured | " +
          " | ".join(label for _, label in METRICS) + " |")
    print("| --- " * (5 + len(METRICS)) + "|")
    for g, c in sorted(by_c, reverse=True):
        cells = []
        for k, _ in METRICS:
            v = [float(r[k]) for r in by_c[(g, c)] if not math.isnan(float(r[k]))]
            fmt = "{:.3f}" if k == "steady_min_eccentricity_ratio" else "{:.0f}"
            cells.append(fmt.format(min(v)) + " – " + fmt.format(max(v)))
        settled = sum(int(float(r["slider_response_settled"])) for r in by_c[(g, c)])
        print(f"| {g} | {c * 1e3:.1f} mm | {len(by_c[(g, c)])} | {settled} | {MEASURED[c]} | " +
              " | ".join(cells) + " |")
    print()
    # the largest median-revolution peak of each clearance and what set it
    keys = [FRICTION, "parameters.rod.inertia", "parameters.gravity",
            "parameters.contact.ball_radius", "parameters.contact.bearing_length"]
    k = METRICS[0][0]
    for g, c in sorted(by_c, reverse=True):
        for pick, name in ((max, "largest"), (min, "smallest")):
            r = pick(by_c[(g, c)], key=lambda r: float(r[k]))
            print(f"- {g}, {c * 1e3:.1f} mm, {name} median revolution peak {float(r[k]):.1f} m/s² "
                  "at " + ", ".join(f"{x.split('.')[-1]} {r[x]}" for x in keys))


def start_angle(results):
    """The starting angle (studies/planar-slider-crank-start-angle.json): per friction and
    clearance, the median and 95 % revolution peaks (unfiltered and low-passed) at theta0 = 0,
    their range over the starting angles and its deviation from theta0 = 0, the settled cases."""
    angle = "parameters.drive.initial_crank_angle"
    by = {}
    for r in rows(results, "planar-slider-crank-start-angle"):
        assert r["status"] == "ok", r
        by.setdefault((float(r[FRICTION]), float(r[CLEARANCE])), []).append(r)
    print("| c_f | clearance | measured | " +
          " | ".join(f"{label} at θ₀ = 0; over θ₀" for _, label in METRICS[:4]) +
          " | settled | min abs(e)/c |")
    print("| --- " * 9 + "|")
    for f, c in sorted(by):
        rs = by[(f, c)]
        zero = next(r for r in rs if float(r[angle]) == 0.0)
        cells = []
        for k, _ in METRICS[:4]:
            v = [float(r[k]) for r in rs]
            z = float(zero[k])
            cells.append(f"{z:.1f}; {min(v):.1f} – {max(v):.1f} "
                         f"({100 * (min(v) - z) / z:+.0f} … {100 * (max(v) - z) / z:+.0f} %)")
        settled = sum(int(float(r["slider_response_settled"])) for r in rs)
        ecc = min(float(r["steady_min_eccentricity_ratio"]) for r in rs)
        print(f"| {f} | {c * 1e3:.1f} mm | {MEASURED[c]} | " + " | ".join(cells) +
              f" | {settled} of {len(rs)} | {ecc:.3f} |")
    print()
    # does the low-passed median grow with clearance, starting angle by starting angle?
    low = METRICS[2][0]
    for f in sorted({f for f, _ in by}):
        lp = {}
        for c in sorted(MEASURED):
            for r in by.get((f, c), []):
                lp.setdefault(float(r[angle]), []).append(float(r[low]))
        grows = [a for a, v in lp.items() if all(y > x for x, y in zip(v, v[1:]))]
        print(f"- c_f {f}: the low-passed median grows with clearance from {len(grows)} of "
              f"{len(lp)} starting angles" +
              (" (θ₀/π = " + ", ".join(f"{a / math.pi:g}" for a in sorted(grows)) + ")"
               if grows else ""))


# the model forms (issue 36 items 4-5): study, its varied keys (short names), what it adds
MODEL_FORMS = [
    ("planar-slider-crank-flexible-rod", ["rod_flexibility.section_second_moment"],
     "flexible rod, first bending mode"),
    ("planar-slider-crank-guide", ["guide.clearance", "guide.friction_coefficient"],
     "guide with clearance and friction"),
    ("planar-slider-crank-motor", ["drive.flywheel_inertia"], "motor curve and flywheel"),
    ("planar-slider-crank-all-joints", ["joints.ground_crank.clearance"],
     "clearance at A and B too (same at both)"),
    ("planar-slider-crank-combined", [], "every form at once, default values"),
]


def peak_cell(r, key, c):
    v = float(r[key])
    return f"{v:.1f} ({err(v, MEASURED[c])})"


def model_forms(results):
    """One row per case of the model-form studies' other axes: the median revolution peak and
    the same after the 1 kHz low-pass at each clearance, the settling flags, the lowest
    eccentricity ratio, and whether the low-passed median grows with clearance."""
    print("| model form (study: varied value) | " +
          " | ".join(f"{c * 1e3:.1f} mm: median; 1 kHz median" for c in sorted(MEASURED)) +
          " | settled | min abs(e)/c | grows |")
    print("| --- " * (len(MEASURED) + 4) + "|")
    print("| measured | " + " | ".join(f"{MEASURED[c]}" for c in sorted(MEASURED)) +
          " | – | – | yes |")
    base = {float(r[CLEARANCE]): r for r in rows(results, "planar-slider-crank-clearance")
            if r["parameters.joints.rod_slider.model"] == "clearance"}
    print_form_row("baseline (planar-slider-crank-clearance)", base)
    for study, keys, what in MODEL_FORMS:
        if not (Path(results) / study / "summary.h5").exists():
            print(f"| {what}: no results of {study} | " + "– | " * (len(MEASURED) + 3))
            continue
        groups = {}
        for r in rows(results, study):
            assert r["status"] == "ok", r
            label = ", ".join(f"{k.split('.')[-1]} {r['parameters.' + k]}" for k in keys)
            groups.setdefault(label, {})[float(r[CLEARANCE])] = r
        for label, by_c in groups.items():
            print_form_row(f"{what} ({study}" + (f": {label})" if label else ")"), by_c)


def print_form_row(label, by_c):
    med, low = "median_revolution_peak_slider_acceleration", \
        "lowpass_median_revolution_peak_slider_acceleration"
    cs = sorted(MEASURED)
    cells = [peak_cell(by_c[c], med, c) + "; " + peak_cell(by_c[c], low, c) for c in cs]
    settled = "/".join(str(int(float(by_c[c]["slider_response_settled"]))) for c in cs)
    ecc = min(float(by_c[c]["steady_min_eccentricity_ratio"]) for c in cs)
    lp = [float(by_c[c][low]) for c in cs]
    grows = "yes" if all(b > a for a, b in zip(lp, lp[1:])) else "no"
    print(f"| {label} | " + " | ".join(cells) + f" | {settled} | {ecc:.3f} | {grows} |")


if __name__ == "__main__":
    where = sys.argv[1] if len(sys.argv) > 1 else "results"
    baseline(where)
    print()
    if (Path(where) / "planar-slider-crank-band" / "summary.h5").exists():
        band(where)
    else:
        print("(no results of planar-slider-crank-band)")
    print()
    if (Path(where) / "planar-slider-crank-start-angle" / "summary.h5").exists():
        start_angle(where)
    else:
        print("(no results of planar-slider-crank-start-angle)")
    print()
    model_forms(where)
