#!/usr/bin/python3
"""The flap linkage's figures (scene planar-linkage; studies/flap-linkage-*.json).

    /usr/bin/python3 plots/plot_flap_linkage.py RESULTS_DIR [--out DIR] [--dpi N]

Reads every case file RESULTS_DIR/cases/*.h5 (their recorded signals surface_angle,
surface_angle_command, surface_rate, ideal_surface_rate, surface_acceleration,
ideal_surface_acceleration) and draws, into RESULTS_DIR/plots/ (or --out), one line per case
labelled by its grid coordinates:

  flap_response.png  shaft angle, angular velocity and angular acceleration against time over
                     the last whole drive period, with the ideal linkage's (dashed, black)
  flap_phase.png     angular acceleration against angular velocity over the same period
  flap_spectrum.png  amplitude spectrum of the angular acceleration over the whole periods
                     after the first (the samples are uniform: the study's sample_interval)

A case's label names what differs between the cases: the joints with clearance, the flexible
bodies, any other grid key as name=value.

Prints one line per file written. Exit status 0 when drawn, 2 when RESULTS_DIR holds no case
file with those signals (one line, no traceback). Needs Debian's numpy, h5py, matplotlib.
"""
import argparse
import glob
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import h5py  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

NEEDED = ["surface_angle", "surface_angle_command", "surface_rate", "ideal_surface_rate",
          "surface_acceleration", "ideal_surface_acceleration"]
DRIVE_HZ = "motion.frequency"


def parts(coords):
    """A case's grid coordinates as short phrases: the joints with clearance ("clearance at
    joints 1+2"), the flexible bodies ("flexible: auxiliary_rod"), any other key as name=value
    (its last two parts)."""
    joints, flexible, other = [], [], []
    for key, value in coords.items():
        name = key.split(".")
        if key.startswith("parameters.linkage.joints.") and name[-1] == "model":
            if value == "clearance":
                joints.append(name[-2].replace("joint_", ""))
        elif key.startswith("parameters.linkage.bodies.") and name[-1] == "kind":
            if value == "flexible":
                flexible.append(name[-2])
        else:
            other.append(f"{'.'.join(name[-2:])}={value}")
    out = other
    if any(k.endswith(".model") for k in coords):
        out = ["clearance at joint" + ("s " if len(joints) > 1 else " ") + "+".join(joints)
               if joints else "no clearance"] + out
    if any(k.endswith(".kind") for k in coords):
        out.append("flexible: " + ", ".join(flexible) if flexible else "rigid")
    return out


def labels(all_coords):
    """One label per case: its phrases that are not the same in every case."""
    phrased = [parts(c) for c in all_coords]
    common = set.intersection(*(set(p) for p in phrased)) if len(phrased) > 1 else set()
    return [", ".join(x for x in p if x not in common) or "default" for p in phrased]


def read_cases(results):
    cases, coords = [], []
    for path in sorted(glob.glob(os.path.join(results, "cases", "*.h5"))):
        with h5py.File(path, "r") as h:
            if "signals" not in h or not all(n in h["signals"] for n in NEEDED):
                continue
            sig = {n: h["signals"][n][()] for n in NEEDED + ["time"]}
            params = json.loads(h.attrs["parameters_json"])
            freq = params.get(DRIVE_HZ, {})
            freq = freq.get("value", freq) if isinstance(freq, dict) else freq
            coords.append(json.loads(h.attrs["coordinates_json"]))
            cases.append((float(freq), sig))
    return [(lab, freq, sig) for lab, (freq, sig) in zip(labels(coords), cases)]


def last_period(sig, freq):
    t = sig["time"]
    T = 1.0 / freq
    end = np.floor(t[-1] / T + 1e-9) * T
    return (t >= end - T - 1e-12) & (t <= end + 1e-12)


def draw_response(cases, out, dpi):
    fig, axes = plt.subplots(3, 1, figsize=(8, 9), sharex=True)
    rows = [("surface_angle", "surface_angle_command", "shaft angle [deg]", np.degrees),
            ("surface_rate", "ideal_surface_rate", "angular velocity [deg/s]", np.degrees),
            ("surface_acceleration", "ideal_surface_acceleration",
             "angular acceleration [deg/s$^2$]", np.degrees)]
    for ax, (name, ideal, ylabel, conv) in zip(axes, rows):
        for i, (lab, freq, sig) in enumerate(cases):
            m = last_period(sig, freq)
            ax.plot(sig["time"][m], conv(sig[name][m]), lw=1.0, label=lab)
            if i == 0:
                ax.plot(sig["time"][m], conv(sig[ideal][m]), "k--", lw=1.0, label="ideal")
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)
    axes[0].legend(fontsize=7)
    axes[-1].set_xlabel("time [s]")
    return save(fig, out, "flap_response.png", dpi)


def draw_phase(cases, out, dpi):
    fig, ax = plt.subplots(figsize=(7, 6))
    for i, (lab, freq, sig) in enumerate(cases):
        m = last_period(sig, freq)
        ax.plot(np.degrees(sig["surface_rate"][m]), np.degrees(sig["surface_acceleration"][m]),
                lw=0.8, label=lab)
        if i == 0:
            ax.plot(np.degrees(sig["ideal_surface_rate"][m]),
                    np.degrees(sig["ideal_surface_acceleration"][m]), "k--", lw=1.0,
                    label="ideal")
    ax.set_xlabel("angular velocity [deg/s]")
    ax.set_ylabel("angular acceleration [deg/s$^2$]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7)
    return save(fig, out, "flap_phase.png", dpi)


def draw_spectrum(cases, out, dpi):
    fig, ax = plt.subplots(figsize=(8, 5))
    for lab, freq, sig in cases:
        t = sig["time"]
        T = 1.0 / freq
        end = np.floor(t[-1] / T + 1e-9) * T
        m = (t >= T - 1e-12) & (t < end - 1e-12)
        a = np.degrees(sig["surface_acceleration"][m])
        if a.size < 8:
            continue
        dt = float(np.median(np.diff(t[m])))
        amp = 2.0 * np.abs(np.fft.rfft(a)) / a.size
        f = np.fft.rfftfreq(a.size, dt)
        ax.semilogy(f[1:], amp[1:], lw=0.8, label=lab)
    ax.set_xlim(0, 100)
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("angular acceleration amplitude [deg/s$^2$]")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    return save(fig, out, "flap_spectrum.png", dpi)


def save(fig, out, name, dpi):
    path = os.path.join(out, name)
    fig.tight_layout()
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    print(path)
    return path


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("results")
    ap.add_argument("--out")
    ap.add_argument("--dpi", type=int, default=120)
    args = ap.parse_args()
    cases = read_cases(args.results)
    if not cases:
        print(f"{args.results}: no case file with the signals {', '.join(NEEDED)}",
              file=sys.stderr)
        return 2
    out = args.out or os.path.join(args.results, "plots")
    os.makedirs(out, exist_ok=True)
    draw_response(cases, out, args.dpi)
    draw_phase(cases, out, args.dpi)
    draw_spectrum(cases, out, args.dpi)
    return 0


if __name__ == "__main__":
    sys.exit(main())
