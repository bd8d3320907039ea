"""The trends the thesis states in §5.2, §5.3 and §6.3, asserted on study outputs
(docs/thesis-trends.md: one row per statement; the row id is printed beside each check).

    test_thesis_trends.py GROUP STUDIES_DIR

GROUP is one of scenes (tests/studies/trends-scenes.json: §5.2 on both scenes, §6.3 and
§6.3.1), two-cycles (§5.2 fig. 5.17, the second ascent), first-impact (§5.2 fig. 5.13-5.14,
sampled finely), misalignment (§5.3) and hinge (§6.3.2). Each runs its short study under tests/studies/ and checks the rows
of its group. Tolerances are stated with each check and justified by the measured values in
docs/thesis-trends.md."""
import json
import os
import sys
import tempfile

import h5py
import numpy as np

from common import check, finish, read_summary, run

group, studies = sys.argv[1], sys.argv[2]
STUDY = {"scenes": "trends-scenes", "two-cycles": "trends-two-cycles",
         "first-impact": "trends-first-impact",
         "misalignment": "trends-misalignment", "hinge": "trends-hinge"}[group]

# the command profile of every trend study: +60 mm in 1 s, hold 0.2 s, -60 mm in 1 s, hold 0.2 s
EXTENSION = (0.05, 0.95)      # [s] well inside the extension stroke
RETRACTION = (1.35, 2.05)     # [s] well inside the retraction stroke (after the reversal)


class Case:
    def __init__(self, folder, row):
        self.row = row
        self.scene = row.get("scene", "")
        self.path = os.path.join(folder, "cases", row["case_id"] + ".h5")
        with h5py.File(self.path, "r") as f:
            self.coordinates = json.loads(f.attrs["coordinates_json"])
            self.scene = self.scene or f.attrs["scene"]
            self.s = {k: f["signals"][k][()] for k in f["signals"]}
        self.t = self.s["time"]

    def m(self, name):
        return float(self.row[name])

    def coordinate(self, key):
        return self.coordinates[key]

    def window(self, lo_hi):
        return (self.t > lo_hi[0]) & (self.t < lo_hi[1])


def increasing(values):
    return all(b > a for a, b in zip(values, values[1:]))


def decreasing(values):
    return all(b < a for a, b in zip(values, values[1:]))


def row(rid, cond, what, values):
    """One trend row: print the measured values, assert the condition."""
    print(f"{rid}: {what}: {values}")
    check(cond, f"{rid}: {what}: {values}")


def fmt(values, f="%.4g"):
    return [f % v for v in values]


def circular_mean(angles):
    return float(np.angle(np.mean(np.exp(1j * np.asarray(angles)))))


def contact_direction(c, window):
    """Mean direction [rad] of the contact (relative position) while touching in the window."""
    sel = c.window(window) & (c.s["contact_force"] > 0)
    r = c.s["relative_position"][sel]
    return circular_mean(np.arctan2(r[:, 1], r[:, 0])), int(sel.sum())


def angle_between(a, b):
    return abs((a - b + np.pi) % (2 * np.pi) - np.pi)


def reestablished(c, t_reverse):
    """After the stroke reversal at t_reverse: the time the contact, having opened, closes again
    (the ball has crossed the clearance to the driving side)."""
    t, f = c.t, c.s["contact_force"]
    opened = np.nonzero((t > t_reverse) & (f == 0))[0]
    if not opened.size:
        return np.inf
    again = np.nonzero((t > t[opened[0]]) & (f > 0))[0]
    return float(t[again[0]]) if again.size else np.inf


def rough(x):
    """RMS of the second difference: how much a sampled signal oscillates."""
    return float(np.sqrt(np.mean(np.diff(x, 2) ** 2)))


with tempfile.TemporaryDirectory() as root:
    r = run(["run", os.path.join(studies, STUDY + ".json"), "--results-root", root, "-q",
             "--threads", "2"])
    check(r.returncode == 0, f"{STUDY}: run failed ({r.returncode}): {r.stderr}")
    folder = os.path.join(root, STUDY)
    rows = read_summary(folder)
    check(all(x["status"] == "ok" for x in rows), f"{STUDY}: statuses {[x['status'] for x in rows]}")
    cases = [Case(folder, x) for x in rows]

    if group in ("scenes", "two-cycles", "first-impact"):
        def by_clearance(scene):
            cs = [c for c in cases if c.scene == scene]
            return sorted(cs, key=lambda c: c.coordinate("parameters.contact.clearance"))

    if group == "scenes":
        kin, act = by_clearance("rod-end-kinematic"), by_clearance("rod-end-actuator")
        check(len(kin) == 3 and len(act) == 3, "expected 3 clearances per scene")
        for label, cs in (("kinematic", kin), ("actuator", act)):
            # §5.2 on the kinematic scene; the same on the full system (thesis §6.3.1 refers to
            # chapter 5 for these)
            v = [c.m("eccentricity_ptp_after_first_contact") for c in cs]
            row("5.2-a", increasing(v), f"{label}: eccentricity ptp after first contact [m] vs clearance", fmt(v))
            v = [c.m("first_contact_time") for c in cs]
            row("5.2-b", increasing(v), f"{label}: first contact time [s] vs clearance", fmt(v))
            v = [c.m("first_impact_speed") for c in cs]
            row("5.2-c", increasing(v), f"{label}: first impact speed [m/s] vs clearance", fmt(v))
            # the socket moves identically before any contact: its speed at half the earliest
            # first-contact time is the same in every case (to 1e-6 relative)
            t_probe = 0.5 * min(c.m("first_contact_time") for c in cs)
            v = [float(np.linalg.norm(c.s["socket_velocity"][np.searchsorted(c.t, t_probe)]))
                 for c in cs]
            row("5.2-c", max(v) - min(v) <= 1e-6 * max(v),
                f"{label}: socket speed [m/s] at t = {t_probe:.3f} s (before any contact)", fmt(v, "%.9g"))
            v = [c.m("first_impact_dissipated_energy") for c in cs]
            row("5.2-d", increasing(v), f"{label}: first-impact damping loss [J] vs clearance", fmt(v))
            v = [c.m("first_impact_peak_force") for c in cs]
            row("5.2-e", increasing(v), f"{label}: first-impact peak force [N] vs clearance", fmt(v))
            v = [c.m("surface_motion_onset_time") for c in cs]
            row("5.2-g", increasing(v), f"{label}: surface motion onset [s] vs clearance", fmt(v))
            v = [c.m("max_surface_angle") for c in cs]
            row("5.2-h", decreasing(v), f"{label}: largest surface angle [rad] vs clearance", fmt(v, "%.6g"))
            # the return (fig. 5.17, third graph): from 1.2 s the piston retracts. The
            # extension-side contact unloads first (theta leaves its peak by 1 mrad at the same
            # time for every clearance: the elastic preload of the chain), then the ball crosses
            # the clearance: the contact that drives theta down is established earlier with the
            # smaller clearance
            v = [reestablished(c, 1.2) for c in cs]
            row("5.2-i", increasing(v), f"{label}: return: time the driving contact is re-established [s] vs clearance", fmt(v))

        # §6.3 (0.5 mm): the same input with and without the actuator (fig. 6.11): the piston
        # lags its command by less than 5 mm of the 120 mm stroke (measured 4.9 mm)
        k5 = next(c for c in kin if c.coordinate("parameters.contact.clearance") == 5e-4)
        a5 = next(c for c in act if c.coordinate("parameters.contact.clearance") == 5e-4)
        lag = float(np.max(np.abs(a5.s["actuator_position"] - k5.s["actuator_position"])))
        row("6.3-a", lag < 0.05 * 0.12, "largest |x_actuator - x_kinematic| [m] (stroke 0.12 m)", fmt([lag]))
        # the full system reflects the kinematic one (fig. 6.12): the same largest surface
        # angles within 2 %, contact within the clearance plus 1 %
        v = [k5.m("max_surface_angle"), a5.m("max_surface_angle"),
             k5.m("min_surface_angle"), a5.m("min_surface_angle")]
        row("6.3-b", abs(v[0] - v[1]) < 0.02 * abs(v[0]) and abs(v[2] - v[3]) < 0.02 * abs(v[2]),
            "largest / smallest surface angle [rad], kinematic vs actuator", fmt(v))
        v = [k5.m("max_eccentricity"), a5.m("max_eccentricity")]
        row("6.3-b", max(v) < 1.01 * 5e-4, "largest eccentricity [m], kinematic vs actuator", fmt(v))
        # the components respect the direction of the force (fig. 6.13-6.14, as §5.1): the
        # outer spring is compressed (positive) while extending, stretched while retracting;
        # the inner spring the reverse (its sign: tension positive); in at least 90 % of the
        # samples of each stroke
        for label, c in (("kinematic", k5), ("actuator", a5)):
            ext, ret = c.window(EXTENSION), c.window(RETRACTION)
            fo, fi = c.s["slider_spring_axial_force"], c.s["crank_spring_axial_force"]
            v = [np.mean(fo[ext] > 0), np.mean(fo[ret] < 0), np.mean(fi[ext] < 0), np.mean(fi[ret] > 0)]
            row("6.3-e", min(v) >= 0.9,
                f"{label}: fractions outer>0 ext, outer<0 ret, inner<0 ext, inner>0 ret", fmt(v, "%.3f"))
        # the polar plot with the actuator (fig. 6.15): contact on the same side of the socket
        # as without it in each stroke (mean contact directions within 10 deg)
        for stroke, w in (("extension", EXTENSION), ("retraction", RETRACTION)):
            (dk, nk), (da, na) = contact_direction(k5, w), contact_direction(a5, w)
            row("6.3-f", nk > 0 and na > 0 and angle_between(dk, da) < np.radians(10),
                f"{stroke}: mean contact direction [deg] kinematic vs actuator",
                fmt([np.degrees(dk), np.degrees(da)]))
        # measured for the table (the other developer's fig. 6.12 investigation): roughness
        v = [rough(k5.s["contact_force"]), rough(a5.s["contact_force"]),
             rough(k5.s["slider_spring_axial_force"]), rough(a5.s["slider_spring_axial_force"])]
        print("6.3-c/d (measured, not asserted): RMS second difference of contact force and "
              "outer spring force, kinematic vs actuator:", fmt(v))

        # §6.3.1 on the full system
        ext = [c.window(EXTENSION) for c in act]
        ret = [c.window(RETRACTION) for c in act]
        p = [c.s["chamber_pressures"] for c in act]
        q = [c.s["chamber_flows"] for c in act]
        xs = [c.s["spool_position"] for c in act]
        fe = [c.s["actuator_external_force"] for c in act]
        v = [(float(np.mean(pi[e, 0])), float(np.mean(pi[r_, 0]))) for pi, e, r_ in zip(p, ext, ret)]
        row("6.3.1-a", all(a > b for a, b in v),
            "rear-chamber pressure, mean over extension > mean over retraction [Pa]", v)
        v = [(float(np.mean(f[e] < 0)), float(np.mean(f[r_] > 0))) for f, e, r_ in zip(fe, ext, ret)]
        row("6.3.1-c", all(a >= 0.9 and b >= 0.9 for a, b in v),
            "external force: fraction < 0 while extending, > 0 while retracting", v)
        # the external force carries the contact force (fig. 6.17): its largest magnitude grows
        # with the clearance as the contact-force peaks do
        v = [float(np.max(np.abs(f))) for f in fe]
        row("6.3.1-d", increasing(v), "largest |external force| [N] vs clearance", fmt(v))
        v = [(float(np.mean(pi[e, 0] - pi[e, 1])), float(np.mean(pi[r_, 0] - pi[r_, 1])))
             for pi, e, r_ in zip(p, ext, ret)]
        row("6.3.1-f", all(a > 0 > b for a, b in v),
            "mean p1 - p2 [Pa] while extending (> 0) and retracting (< 0)", v)
        v = [(float(np.mean(qi[e, 0] > 0)), float(np.mean(qi[r_, 0] < 0))) for qi, e, r_ in zip(q, ext, ret)]
        row("6.3.1-g", all(a >= 0.95 and b >= 0.95 for a, b in v),
            "rear-chamber flow: fraction > 0 while extending, < 0 while retracting", v)
        # hardly any difference with clearance (fig. 6.20, 6.22): the extreme flows and spool
        # positions of the three clearances agree to 1e-4 relative (measured 2e-7)
        for rid, name, arrs in (("6.3.1-h", "rear-chamber flow", [qi[:, 0] for qi in q]),
                                ("6.3.1-j", "spool position", xs)):
            hi = [float(np.max(a_)) for a_ in arrs]
            lo = [float(np.min(a_)) for a_ in arrs]
            spread = max((max(hi) - min(hi)) / max(hi), (max(lo) - min(lo)) / abs(min(lo)))
            row(rid, spread < 1e-4, f"{name}: relative spread of the extremes over clearances",
                fmt([spread]))
        v = [(float(np.mean(x[e] > 0)), float(np.mean(x[r_] < 0)),
              float(np.corrcoef(x, qi[:, 0])[0, 1])) for x, qi, e, r_ in zip(xs, q, ext, ret)]
        row("6.3.1-k", all(a >= 0.95 and b >= 0.95 and cc > 0.95 for a, b, cc in v),
            "spool: fraction > 0 extending, < 0 retracting, correlation with the rear flow", v)
        # measured for the table (the other developer's fig. 6.16/6.18 investigation)
        print("6.3.1-b/e (measured, not asserted): largest p1, largest p2 [Pa] vs clearance:",
              [(float(np.max(pi[:, 0])), float(np.max(pi[:, 1]))) for pi in p])

    if group == "two-cycles":
        cs = by_clearance("rod-end-kinematic")
        # the second ascent (fig. 5.17, fourth graph): from 2.4 s the piston extends again; as
        # on the return (5.2-i) the contact that drives the surface is re-established earlier
        # with the smaller clearance
        v = [reestablished(c, 2.4) for c in cs]
        row("5.2-j", increasing(v), "second ascent: time the driving contact is re-established [s] vs clearance", fmt(v))

    if group == "first-impact":
        cs = sorted(cases, key=lambda c: c.coordinate("parameters.contact.clearance"))
        # fig. 5.13-5.14: a lower impact speed, a lower force and a smaller penetration; the
        # first impact lasts about 0.15 ms, so this study samples at 5 us
        v = []
        for c in cs:
            t0 = c.m("first_contact_time")
            sel = (c.t >= t0) & (c.t <= t0 + c.m("first_impact_duration") + 1e-4)
            v.append(float(np.max(c.s["penetration"][sel])))
        row("5.2-f", increasing(v), "first-impact penetration [m] vs clearance", fmt(v))

    if group == "misalignment":
        cs = sorted(cases, key=lambda c: c.coordinate("parameters.socket.misalignment_z"))
        c_ = 5e-4
        v = [c.m("max_penetration_fraction") for c in cs]
        row("5.3-a", max(v) < 0.01, "largest penetration / clearance (the constraint holds)", fmt(v))
        # narrower in the xy-plane with a larger z offset: the largest in-plane radius while in
        # contact decreases, and stays within 2 % of sqrt(c^2 - z^2) at the z of that sample
        v, w = [], []
        for c in cs:
            r_ = c.s["relative_position"]
            sel = c.s["contact_force"] > 0
            rxy = np.hypot(r_[sel, 0], r_[sel, 1])
            k = int(np.argmax(rxy))
            v.append(float(rxy[k]))
            w.append(float(np.sqrt(c_ ** 2 - r_[sel][k, 2] ** 2)))
        row("5.3-b", decreasing(v) and all(abs(a - b) < 0.02 * b for a, b in zip(v, w)),
            "largest xy radius in contact [m] vs misalignment (sqrt(c^2 - z^2) beside)",
            fmt(v) + ["|"] + fmt(w))
        # xz-plane: z stays at its initial level until the first contact (to 1 nm), then bends
        for c in cs[1:]:
            z = c.s["relative_position"][:, 2]
            t0 = c.m("first_contact_time")
            before = float(np.max(np.abs(z[c.t < t0] - z[0])))
            after = float(np.max(np.abs(z[c.t >= t0] - z[0])))
            row("5.3-c", before < 1e-9 and after > 1e-6,
                f"misalignment {c.coordinate('parameters.socket.misalignment_z')}: "
                "largest |z - z0| [m] before / after the first contact", fmt([before, after]))

    if group == "hinge":
        const = sorted([c for c in cases if c.coordinate("parameters.hinge.kind") == "constant"],
                       key=lambda c: -c.coordinate("parameters.hinge.constant_moment"))
        prop = [c for c in cases if c.coordinate("parameters.hinge.kind") == "proportional"]
        # fig. 6.23: the largest position reached decreases as the opposing moment grows, by
        # far less than the stroke (below 1 % of the 60 mm extension)
        v = [float(np.max(c.s["actuator_position"])) for c in const]
        row("6.3.2-a", decreasing(v) and v[0] - v[-1] < 0.01 * 0.06,
            "largest actuator position [m] vs |M| = 100, 200, 400 N m", fmt(v, "%.7g"))
        # more disturbance at the start (the moment is a step): the largest deviation of the
        # piston velocity from the command rate in the first 0.1 s grows with |M|
        v = []
        for c in const:
            sel = c.t < 0.1
            rate = np.gradient(c.s["actuator_command"], c.t)
            v.append(float(np.max(np.abs(c.s["actuator_velocity"][sel] - rate[sel]))))
        row("6.3.2-b", increasing(v), "largest |v - v_command| in the first 0.1 s [m/s] vs |M|", fmt(v))
        # fig. 6.24: with a constant moment the contact never opens after the first 10 ms, not
        # even at the reversal
        for c in const:
            sel = c.t > 0.01
            frac = float(np.mean(c.s["contact_force"][sel] > 0))
            row("6.3.2-c", frac == 1.0, f"M = {c.coordinate('parameters.hinge.constant_moment')} N m: "
                "fraction of samples in contact after 10 ms", [frac])
        # fig. 6.25: the proportional moment always opposes the deflection
        for c in prop:
            prod = c.s["hinge_moment"] * c.s["surface_angle"]
            row("6.3.2-e", float(np.max(prod)) <= 0.0, "largest M * theta [N m rad] (proportional)",
                fmt([float(np.max(prod))]))
            # fig. 6.25-6.26: when theta changes sign the contact moves to the other half of
            # the socket (mean contact directions 0.2 s before and after the zero crossing of
            # the retraction differ by more than 90 deg)
            th = c.s["surface_angle"]
            k = np.nonzero((c.t > 1.2) & (th < 0))[0][0]
            tz = float(c.t[k])
            (d0, n0), (d1, n1) = contact_direction(c, (tz - 0.2, tz - 0.02)), contact_direction(c, (tz + 0.02, tz + 0.2))
            row("6.3.2-d", n0 > 0 and n1 > 0 and angle_between(d0, d1) > np.radians(90),
                f"proportional: contact direction [deg] before / after theta = 0 at t = {tz:.3f} s",
                fmt([np.degrees(d0), np.degrees(d1)]))
        # fig. 6.24, 6.26: a larger moment, a larger eccentricity (penetration)
        v = [c.m("max_eccentricity") for c in const]
        row("6.3.2-f", increasing(v), "largest eccentricity [m] vs |M|", fmt(v, "%.7g"))
        # fig. 6.29: with a constant moment the contact (so the wear) stays in one half of the
        # socket, and the largest contact force is at the same angle for every moment (within
        # one 5 deg bin)
        peaks = []
        for c in const:
            sel = c.s["contact_force"] > 0
            r_ = c.s["relative_position"][sel]
            ang = np.arctan2(r_[:, 1], r_[:, 0])
            d = circular_mean(ang)
            spread = float(np.max(angle_between(ang, d)))
            row("6.3.2-i", spread < np.pi / 2,
                f"M = {c.coordinate('parameters.hinge.constant_moment')} N m: contact directions "
                "within [deg] of their mean (< 90: one half)", fmt([np.degrees(spread)]))
            peaks.append(float(np.degrees(ang[int(np.argmax(c.s["contact_force"][sel]))])))
        row("6.3.2-j", max(peaks) - min(peaks) < 5.0, "angle of the largest contact force [deg] vs |M|",
            fmt(peaks))
finish(f"thesis trends ({group})")
