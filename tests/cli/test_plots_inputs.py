"""The numbers of the inputs' figures against the simulation (docs/inputs.md):

1. plots/linear_actuator.py's linearised model against rodend's simulated response to a small
   sine command at zero clearance (1 um, +-1 mm): at 4 Hz, and at the piston's -3 dB bandwidth
   the model gives, where the simulated piston gain must be 1/sqrt(2). Tolerance 1 % of gain and
   1 deg: the two differ by the nonlinearity at +-1 mm (up to 0.5 % of gain and 0.44 deg at
   12 Hz, measured by tests/test_inputs.cpp) and by the chambers' pressures, which start at the
   model's mid pressure and relax towards the settled one (the gains there up to 0.3 % lower at
   11 Hz). The bandwidth docs/inputs.md gave before, 10.5 Hz, fails it: the gain there is 0.72.
2. The settled pressure the model finds by Newton's method against a held run's chamber
   pressures after 8 s (9 of the sum-pressure mode's time constants): within 0.005 MPa.
3. The free-play figure's construction (plots/input_figures.py: each branch's time-weighted
   least-squares line over 0.2-0.9 M on the recorded samples, extrapolated to M = 0) against the
   metrics free_play and stiffness_positive/negative (sweep/periodic_metrics.cpp, exact over the
   step frames' interpolant): within 0.01 % and 0.002 %, what the 1 ms samples' trapezoid
   weights leave (measured 0.001 % and 0.0001 % at 0.5 mm; a fit window of 0.25-0.9 M instead
   moves the free-play by 0.025 %).
4. The intercept of the least-squares line of x^(2/3) on [0.2, 0.9] (the Hertz penetration the
   branch lines leave at zero load): the closed form against a dense numerical fit, 0.204; the
   secant's 0.173.

Usage (CTest): test_plots_inputs.py PLOTS_DIR STUDIES_DIR, with RODEND set to the executable."""
import csv
import glob
import json
import math
import os
import sys
import tempfile

import h5py
import numpy as np

from common import check, finish, run

PLOTS, STUDIES = (os.path.abspath(a) for a in sys.argv[1:3])
sys.path.insert(0, PLOTS)
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import linear_actuator as la  # noqa: E402
import plot_study  # noqa: E402,F401  (puts the package rodend on the path, registers the figures)
import input_figures  # noqa: E402
from rodend.study import open_study  # noqa: E402


def run_study(tmp, study, *sets):
    args = ["run", os.path.join(STUDIES, study), "--results-root", tmp, "-q"]
    for s in sets:
        args += ["--set", s]
    r = run(args)
    check(r.returncode == 0, f"{study} {sets}: exit {r.returncode}: {r.stderr}")
    name = os.path.splitext(study)[0]
    with open(os.path.join(tmp, name, "summary.csv"), newline="") as f:
        return os.path.join(tmp, name), list(csv.DictReader(f))


def frequency_response(tmp, lin):
    bandwidth = lin.bandwidth(0)
    check(11.0 < bandwidth < 11.05, f"linear model: piston bandwidth {bandwidth:.3f} Hz, "
          "docs/inputs.md says 11.02 Hz at the mid pressure")
    freqs, cycles = [4.0, bandwidth], [5, 7]
    grid = [{"key": "parameters.contact.clearance", "values": [1e-6]},
            {"zip": [{"key": "parameters.motion.frequency", "values": freqs},
                     {"key": "parameters.motion.cycles", "values": cycles},
                     {"key": "time.end", "values": [n / f for n, f in zip(cycles, freqs)]}]}]
    _, rows = run_study(tmp, "frequency-response.json", "parameters.motion.amplitude=0.001",
                        "grid=" + json.dumps(grid))
    for row in rows:
        f = float(row["drive_frequency"])
        piston, surface = lin.response(f)
        for what, h in (("piston", piston), ("surface", surface)):
            gain, phase = float(row[f"{what}_gain"]), float(row[f"{what}_phase"])
            err = gain / abs(h) - 1
            dph = math.degrees(math.remainder(phase - np.angle(h), 2 * math.pi))
            print(f"{f:.3f} Hz {what}: gain {gain:.4f} (linear {abs(h):.4f}, {100 * err:+.2f} %), "
                  f"phase error {dph:+.2f} deg")
            check(abs(err) <= 0.01 and abs(dph) <= 1.0,
                  f"{f} Hz {what}: simulated gain {gain:.4f}, phase {math.degrees(phase):.2f} "
                  f"deg against the linear {abs(h):.4f}, {math.degrees(np.angle(h)):.2f} deg")
        if abs(f - bandwidth) < 1e-6:
            g = float(row["piston_gain"])
            check(abs(g * math.sqrt(2) - 1) <= 0.01,
                  f"at the model's bandwidth {f:.3f} Hz the simulated piston gain is {g:.4f}")


def settled_pressure(tmp, model):
    x0 = la.operating_point(model, "settled")
    hold = {"name": "hold", "scene": "rod-end-actuator",
            "parameters": {"motion.shape": "step", "motion.extension": 0.0,
                           "motion.retraction": 0.0, "contact.clearance": 1e-6},
            "integrator": {"preset": "balanced"}, "time": {"end": 8.0, "sample_interval": 0.1},
            "signals": ["chamber_pressures"]}
    path = os.path.join(tmp, "hold.json")
    with open(path, "w") as f:
        json.dump(hold, f)
    r = run(["run", path, "--results-root", tmp, "-q"])
    check(r.returncode == 0, f"held run: exit {r.returncode}: {r.stderr}")
    with h5py.File(glob.glob(os.path.join(tmp, "hold", "cases", "*.h5"))[0], "r") as f:
        p_end = f["signals/chamber_pressures"][-1]
    print(f"settled pressure: model {x0[la.P1] / 1e6:.4f} MPa, held run at 8 s "
          f"{p_end[0] / 1e6:.4f}, {p_end[1] / 1e6:.4f} MPa")
    for p in p_end:
        check(abs(p - x0[la.P1]) <= 5e3, f"held run's chamber pressure {p / 1e6:.4f} MPa, the "
              f"linear model's settled pressure {x0[la.P1] / 1e6:.4f} MPa")


def free_play_construction(tmp):
    folder, rows = run_study(tmp, "free-play.json", 'grid=[{"key": '
                             '"parameters.contact.clearance", "values": [5e-4]}]')
    study = open_study(folder)
    for case in study.cases():
        g = input_figures.loop_construction(case, study.summary)
        metric = float(study.summary["free_play"][case.row])
        print(f"free-play: the figure's lines {g['free_play'] * 1e3:.4f} mrad, the metric "
              f"{metric * 1e3:.4f} mrad; peak to peak {g['peak_to_peak'] * 1e3:.3f} mrad")
        check(abs(g["free_play"] / metric - 1) <= 1e-4,
              f"the figure's free-play {g['free_play']} against the metric {metric}")
        for sign, side in ((1, "positive"), (-1, "negative")):
            k = float(study.summary[f"stiffness_{side}"][case.row])
            check(abs(g["lines"][sign][1] / k - 1) <= 2e-5,
                  f"the figure's {side} branch stiffness {g['lines'][sign][1]} against {k}")
        check(g["peak_to_peak"] > g["free_play"], "the ringing's peak to peak is not above "
              "the free-play: nothing to mark")


def intercept():
    ls, secant = la.hertz_intercept()
    x = np.linspace(0.2, 0.9, 700001)
    slope, icpt = np.polyfit(x, x ** (2 / 3), 1)
    print(f"intercept: closed form {ls:.5f}, numerical {icpt:.5f}, secant {secant:.5f}")
    check(abs(ls - icpt) < 1e-6 and round(ls, 3) == 0.204 and round(secant, 3) == 0.173,
          f"intercepts: least squares {ls} (numerical {icpt}), secant {secant}")


def main():
    model = la.Model(la.load_parameters())
    intercept()
    with tempfile.TemporaryDirectory() as tmp:
        frequency_response(tmp, la.Linear(model, "mid"))
        settled_pressure(tmp, model)
        free_play_construction(tmp)
    finish("plots_inputs")


main()
