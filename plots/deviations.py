#!/usr/bin/env python3
"""The numbers quoted in docs/thesis-deviations.md, from the results of the deviation studies.

    ./build/rodend run studies/deviation-rear-pressure.json
    /usr/bin/python3 plots/deviations.py rear-pressure [results/deviation-rear-pressure]

    ./build/rodend run studies/deviation-actuator-damping-kinematic.json
    ./build/rodend run studies/deviation-actuator-damping.json
    /usr/bin/python3 plots/deviations.py actuator-damping

    ./build/rodend run studies/deviation-hinge-signs.json
    /usr/bin/python3 plots/deviations.py hinge-signs

    ./build/rodend run studies/deviation-torque-motor-step.json
    ./build/rodend run studies/deviation-torque-motor.json
    /usr/bin/python3 plots/deviations.py torque-motor

Each prints one table (plain text). Only numpy and h5py (Debian's, under /usr/bin/python3).
"""
import os
import sys

import numpy as np

# the package rodend beside plots/ (its reader needs no compiled module), else an installed one
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "python"))
from rodend import open_study  # noqa: E402

# the default command profile of the rod-end scenes (core/scenes/parts/stroke.part.json)
EXTENSION_END = 1.0  # [s] end of the extension stroke
RETRACTION = (1.2, 2.2)  # [s] the retraction stroke
PISTON_AREA = 5e-4  # [m^2] actuator.piston_area


def rows(study):
    return [c for c in study.cases() if c.status == "ok"]


def window(t, lo, hi):
    return (t >= lo) & (t <= hi)


def rear_pressure(results):
    study = open_study(results)
    print("clearance | max P1 [MPa] at t [s] | max P1 during extension [MPa] | mean P1 over "
          "extension [MPa] | P1 at peak extension speed (t = 0.5 s) [MPa] | max |F_ext| during "
          "extension [N] | mean F_ext over extension [N] | F/(2 A) [MPa]")
    for c in rows(study):
        t = c.signal("time")
        p1 = c.signal("chamber_pressures").reshape(len(t), -1)[:, 0]
        f = c.signal("actuator_external_force")
        ext = window(t, 0.0, EXTENSION_END)
        k = int(np.argmax(p1))
        k5 = int(np.argmin(abs(t - 0.5)))
        fmax = float(np.max(abs(f[ext])))
        print(f"{c.parameter('contact.clearance') * 1e3:.1f} mm | {p1[k] / 1e6:.5f} at "
              f"{t[k]:.3f} | {np.max(p1[ext]) / 1e6:.5f} | {np.mean(p1[ext]) / 1e6:.5f} | "
              f"{p1[k5] / 1e6:.5f} | {fmax:.1f} | {np.mean(f[ext]):.2f} | "
              f"{fmax / (2 * PISTON_AREA) / 1e6:.4f}")


def roughness(x):
    """RMS of the second difference of a sampled signal (its unit)."""
    return float(np.sqrt(np.mean(np.diff(x, 2) ** 2)))


def actuator_damping(kinematic, actuator):
    print("case | RMS 2nd diff. of contact force [N] | of eccentricity [um] | contact-force "
          "RMS after 0.1 s [N] | impact_count | max contact force [N]")
    for label, results in (("kinematic", kinematic), ("actuator", actuator)):
        study = open_study(results)
        for c in rows(study):
            t = c.signal("time")
            f = c.signal("contact_force")
            e = c.signal("eccentricity")
            name = label if label == "kinematic" else \
                f"actuator, piston_friction {c.parameter('actuator.piston_friction'):g} N s/m"
            late = t > 0.1
            print(f"{name} | {roughness(f):.3f} | {roughness(e) * 1e6:.4f} | "
                  f"{np.sqrt(np.mean(f[late] ** 2)):.2f} | {study.summary['impact_count'][c.row]:.0f} | "
                  f"{study.summary['max_contact_force'][c.row]:.1f}")


def hinge_signs(results):
    study = open_study(results)
    print("M0 [N m] | slider spring F_x on socket: min, max [N] (share > 0) | slider spring "
          "moment M_z: min, max [N m] | crank spring F_x on ball: min, max [N] | contact "
          "always on after 0.05 s")
    for c in rows(study):
        t = c.signal("time")
        late = t > 0.05
        fs = c.signal("slider_spring_force").reshape(len(t), 3)[late]
        ms = c.signal("slider_spring_moment").reshape(len(t), 3)[late]
        fc = c.signal("crank_spring_force").reshape(len(t), 3)[late]
        on = np.all(c.signal("contact_force")[late] > 0)
        print(f"{c.parameter('hinge.constant_moment'):g} | {fs[:, 0].min():.1f}, "
              f"{fs[:, 0].max():.1f} ({np.mean(fs[:, 0] > 0):.3f}) | {ms[:, 2].min():.4f}, "
              f"{ms[:, 2].max():.4f} | {fc[:, 0].min():.1f}, {fc[:, 0].max():.1f} | {on}")
    print()
    print("M0 [N m] | stroke | contact force peak: t [s], angle [deg], value [N] | wear "
          "indicator peak: t [s], angle [deg], value [W] | slip speed there [mm/s] | force "
          "at the wear peak / force peak")
    for c in rows(study):
        t = c.signal("time")
        f = c.signal("contact_force")
        w = c.signal("wear_indicator")
        a = np.degrees(c.signal("contact_angle"))
        v = c.signal("slip_speed")
        for stroke, (lo, hi) in (("extension", (0.05, EXTENSION_END)), ("retraction", RETRACTION)):
            m = np.flatnonzero(window(t, lo, hi))
            kf = m[np.argmax(f[m])]
            kw = m[np.argmax(w[m])]
            print(f"{c.parameter('hinge.constant_moment'):g} | {stroke} | {t[kf]:.3f}, "
                  f"{a[kf]:.1f}, {f[kf]:.1f} | {t[kw]:.3f}, {a[kw]:.1f}, {w[kw]:.4f} | "
                  f"{v[kw] * 1e3:.2f} | {f[kw] / f[kf]:.3f}")


def torque_motor(step, cycle):
    print("calibration step (servo-actuator): motor | error at the end of the step's hold [um] | "
          "overshoot [%] | time to 95 % [ms] | largest |error| over the last 0.2 s of the hold [um]")
    for c in rows(open_study(step)):
        t = c.signal("time")
        x, cmd = c.signal("actuator_position"), c.signal("actuator_command")
        a = float(cmd.max())
        hold = np.flatnonzero(cmd >= a)  # the step's plateau
        t_on, last = t[hold[0]], hold[-1]
        k95 = hold[x[hold] >= 0.95 * a]
        tail = hold[t[hold] > t[last] - 0.2]
        print(f"{c.parameter('actuator.torque_motor')} | {(a - x[last]) * 1e6:.3f} | "
              f"{max(0.0, (x[hold].max() - a) / a * 100):.3f} | "
              f"{(t[k95[0]] - t_on) * 1e3 if len(k95) else float('nan'):.1f} | "
              f"{np.max(abs(a - x[tail])) * 1e6:.3f}")
    print()
    print("thesis cycle (rod-end-actuator): motor | hinge moment [N m] | max |command - position| "
          "[mm] | error at the end of the extension hold, of the run [um] | max P1, max P2 [MPa] | "
          "max |current| [mA]")
    for c in rows(open_study(cycle)):
        t = c.signal("time")
        x, cmd = c.signal("actuator_position"), c.signal("actuator_command")
        p = c.signal("chamber_pressures").reshape(len(t), -1)
        k = int(np.argmin(abs(t - 1.2)))
        print(f"{c.parameter('actuator.torque_motor')} | {c.parameter('hinge.constant_moment'):g} | "
              f"{np.max(abs(cmd - x)) * 1e3:.3f} | {(cmd[k] - x[k]) * 1e6:.2f}, "
              f"{(cmd[-1] - x[-1]) * 1e6:.2f} | {p[:, 0].max() / 1e6:.4f}, {p[:, 1].max() / 1e6:.4f} | "
              f"{np.max(abs(c.signal('controller_current'))) * 1e3:.3f}")


def main(argv):
    if len(argv) < 2 or argv[1] not in ("rear-pressure", "actuator-damping", "hinge-signs",
                                             "torque-motor"):
        print(__doc__)
        return 2
    what, rest = argv[1], argv[2:]
    if what == "rear-pressure":
        rear_pressure(rest[0] if rest else "results/deviation-rear-pressure")
    elif what == "actuator-damping":
        actuator_damping(rest[0] if rest else "results/deviation-actuator-damping-kinematic",
                         rest[1] if len(rest) > 1 else "results/deviation-actuator-damping")
    elif what == "torque-motor":
        torque_motor(rest[0] if rest else "results/deviation-torque-motor-step",
                     rest[1] if len(rest) > 1 else "results/deviation-torque-motor")
    else:
        hinge_signs(rest[0] if rest else "results/deviation-hinge-signs")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
