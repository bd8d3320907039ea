#!/usr/bin/python3
"""Work-precision of the stiff and explicit methods on one thesis cycle: for each
scene and configuration (method:tolerance), one run of the thesis cycle (2.4 s, clearance 0.5 mm,
the scene's defaults, samples every 1 ms), its error on the converging metrics against a tight
reference, its steps, right-hand-side calls and, with --callgrind, its instructions (whole run,
and inside rodend::simulate, the integration with its observers, without loading and writing).
Counts and instructions are deterministic: meaningful on a busy machine.

    /usr/bin/python3 bench/stiff-work-precision.py [--callgrind] [--scenes rod-end-kinematic,...]
        [--configs dopri5:1e-7,cvode_bdf:1e-5,rosenbrock4:1e-4:1e-2,...]
        [--reference dopri5:1e-11]

A configuration is method:tolerance[:max_step] (max_step 1e-3 s by default, as the presets).

Errors: relative |x - x_ref| / |x_ref| of max_contact_force, max_eccentricity, wear_integral
(the total wear indicator), first_impact_peak_force, and the surface-angle errors at the stroke
ends (surface_angle_error_extended / _retracted, relative to the reference's). "max" is the
largest of them. Prints a Markdown table per scene.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

# the package rodend beside bench/ (its reader needs no compiled module), else an installed one
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "python"))
from rodend import summary_rows  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
METRICS = ["max_contact_force", "max_eccentricity", "wear_integral", "first_impact_peak_force",
           "surface_angle_error_extended", "surface_angle_error_retracted"]
SHORT = ["F_max", "e_max", "wear", "F_1", "sae_ext", "sae_ret"]
DEFAULT_CONFIGS = ("dopri5:1e-6,dopri5:1e-7,dopri5:1e-8,rosenbrock4:1e-4,rosenbrock4:1e-4:1e-2,"
                   "rosenbrock4:1e-6,"
                   "cvode_bdf:1e-5,cvode_bdf:1e-6,cvode_bdf:1e-7,cvode_bdf:1e-8")


def run(rodend, scene, method, tol, callgrind, tmp, max_step="1e-3"):
    study = {"name": "x", "scene": scene,
             "integrator": {"method": method, "abs_tol": float(tol), "rel_tol": float(tol),
                            "max_step": float(max_step)},
             "time": {"end": 2.4, "sample_interval": 1e-3}}
    d = tempfile.mkdtemp(dir=tmp)
    path = os.path.join(d, "s.json")
    with open(path, "w") as f:
        json.dump(study, f)
    cmd = [rodend, "run", path, "--results-root", d, "-q", "-j", "1"]
    instr = sim = None
    if callgrind:
        out = os.path.join(d, "cg.out")
        subprocess.run(["valgrind", "--tool=callgrind", "--callgrind-out-file=" + out] + cmd,
                       capture_output=True)
        ann = subprocess.run(["callgrind_annotate", "--inclusive=yes", out], capture_output=True,
                             text=True).stdout
        for line in ann.splitlines():
            if "PROGRAM TOTALS" in line and instr is None:
                instr = int(line.split()[0].replace(",", ""))
            if "rodend::simulate(" in line and sim is None:
                sim = int(line.split()[0].replace(",", ""))
    else:
        subprocess.run(cmd, capture_output=True)
    row = summary_rows(os.path.join(d, "x"))[0]
    subprocess.run(["rm", "-rf", d])
    row["instr"], row["sim_instr"] = instr, sim
    return row


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rodend", default=os.path.join(ROOT, "build", "rodend"))
    ap.add_argument("--scenes", default="rod-end-kinematic,rod-end-actuator")
    ap.add_argument("--configs", default=DEFAULT_CONFIGS)
    ap.add_argument("--reference", default="dopri5:1e-11")
    ap.add_argument("--callgrind", action="store_true")
    a = ap.parse_args()
    tmp = tempfile.mkdtemp(prefix="stiff-wp-")
    for scene in a.scenes.split(","):
        m, t = a.reference.split(":")
        ref = run(a.rodend, scene, m, t, False, tmp)
        print(f"\n### {scene} (reference {a.reference}: {ref['steps_accepted']} steps)\n")
        head = "| method | tol | status | steps (rej.) | mean h [s] | RHS calls | " + \
            " | ".join(SHORT) + " | max err |" + (" instr [M] | simulate [M] |" if a.callgrind else "")
        print(head)
        print("|" + "---|" * (head.count("|") - 1))
        for cfg in a.configs.split(","):
            m, t, *ms = cfg.split(":")  # method:tol[:max_step], max_step 1e-3 by default
            r = run(a.rodend, scene, m, t, a.callgrind, tmp, *ms)
            if ms:
                t = f"{t} (max_step {ms[0]})"
            errs = []
            for k in METRICS:
                try:
                    x, xr = float(r[k]), float(ref[k])
                    errs.append(abs(x - xr) / abs(xr))
                except (ValueError, ZeroDivisionError):
                    errs.append(float("nan"))
            steps = int(r["steps_accepted"])
            h = 2.4 / steps if steps else float("nan")
            cells = [m, t, r["status"], f"{steps} ({r['steps_rejected']})", f"{h:.2e}",
                     r["rhs_calls"]] + [f"{e:.1e}" for e in errs] + [f"{max(errs):.1e}"]
            if a.callgrind:
                cells += [f"{(r['instr'] or 0) / 1e6:.1f}", f"{(r['sim_instr'] or 0) / 1e6:.1f}"]
            print("| " + " | ".join(cells) + " |", flush=True)
    subprocess.run(["rm", "-rf", tmp])


if __name__ == "__main__":
    sys.exit(main())
