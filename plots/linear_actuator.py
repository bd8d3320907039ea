#!/usr/bin/python3
"""The linearised rod-end-actuator: transfer functions, poles and -3 dB bandwidth.

    /usr/bin/python3 plots/linear_actuator.py [--rodend PATH | --params FILE.json]
                                              [--pressure settled|mid] [--freq F ...]

Reads the scene's default parameters (`rodend params rod-end-actuator --json`; the executable
from --rodend, else $RODEND, else build/rodend), writes the actuator's equations as they are
documented (docs/model.md, docs/inputs.md#the-linearised-actuator-and-linkage: PI controller,
LVDT, jet pipe eq. 6.2, spool eq. 6.3 with the flow forces, the regularised orifices eq. 6.4-6.6,
the chambers eq. 6.11-6.12, the piston eq. 6.13) together with the zero-clearance linkage (two
springs along the crank's tangent, the spheres between them, the surface's inertia), and
linearises them numerically (central differences) about an operating point:

- `settled`: the equilibrium of the held actuator at zero command, found by Newton's method:
  the chambers settle below the mid pressure, where the valve's leak openings feed the rod-seal
  leakage (about 8.57 MPa at the defaults);
- `mid`: both chambers at (P_s + P_r)/2, the valve centred (not an equilibrium of the pressures'
  sum, which the motion does not see).

Prints the poles, the gains and phases at the chosen frequencies, the -3 dB bandwidths of the
piston (piston/command) and of the surface (surface angle / rigid-linkage angle of the command)
at both operating points, and the intercept the free-play metric's branch lines leave at zero
load for a Hertz contact (docs/inputs.md#the-geometric-free-play). Gravity (2.9 N of sphere
weight, 6 kPa across the piston) and the spheres' rotational springs (below 1 % of the chain's
stiffness) are left out. Only numpy.
"""
import argparse
import json
import math
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
# the states: 0 LVDT, 1 integral of the error, 2 jet, 3 jet rate, 4 spool, 5 spool rate,
# 6 P1, 7 P2, 8 piston u, 9 piston rate, 10 spheres y_b, 11 their rate, 12 crank end y_c,
# 13 its rate (y_b, y_c along the crank's tangent at the command's zero)
L, INT, XJ, VJ, XS, VS, P1, P2, U, V, YB, VB, YC, VC, N = range(15)
# the scale of each state for the difference quotients (as the scene's state_scale)
SCALE = np.array([1e-4, 1e-5, 1e-6, 1e-3, 1e-5, 1e-2, 1e5, 1e5, 1e-4, 1e-2,
                  1e-4, 1e-2, 1e-4, 1e-2])
DEFAULT_FREQS = (0.5, 1, 2, 4, 8, 12, 16, 24, 32)


def load_parameters(rodend=None, params_file=None):
    """The scene's parameters, key -> value, from a `rodend params --json` file or run."""
    if params_file:
        with open(params_file) as f:
            doc = json.load(f)
    else:
        exe = rodend or os.environ.get("RODEND") or os.path.join(HERE, os.pardir, "build", "rodend")
        out = subprocess.run([exe, "params", "rod-end-actuator", "--json"], check=True,
                             capture_output=True, text=True).stdout
        doc = json.loads(out)
    return {k: v["value"] for k, v in doc.items()}


class Model:
    """The documented equations of rod-end-actuator at zero clearance, right-hand side f(x, c)."""

    def __init__(self, p, eq_6_3_as_printed=False):
        self.p = p
        # the feedback wire's deflection on the spool: x_s + x_j as in eq. 6.2 (the code), or
        # x_j - x_s as eq. 6.3 prints it (docs/thesis-deviations.md#eq-6-3-feedback-wire-sign)
        self.wire_on_spool = (lambda xs, xj: xj - xs) if eq_6_3_as_printed else (
            lambda xs, xj: xs + xj)
        s, t, l0 = p["geometry.crank"], p["geometry.frame"], p["geometry.rod"]
        cos_phi = (s * s + t * t - l0 * l0) / (2 * s * t)    # law of cosines, eq. 4.1
        self.r = s * t * math.sqrt(1 - cos_phi ** 2) / l0     # dl/dtheta at zero [m/rad]
        self.cos_a = self.r / s                               # rod direction . crank tangent
        self.m_b = p["ball.mass"] + p["socket.mass"]
        inertia = p["surface.mass"] * (s / 3) ** 2 + p["surface.inertia"]   # eq. 4.16
        self.m_c = inertia / s ** 2                           # referred to the crank end
        self.c_c = p["surface.damping"] / s ** 2
        self.crank = s

    def orifice(self, area, dp):
        """Eq. 6.6 regularised below the transition pressure: C_d a sqrt(2/rho) g(dp)."""
        a, pt = self.p, self.p["actuator.transition_pressure"]
        return (a["actuator.discharge_coefficient"] * area * math.sqrt(2 / a["actuator.density"])
                * dp / (dp * dp + pt * pt) ** 0.25)

    def valve(self, xs, p1, p2):
        """Chamber flows q1 (into 1), q2 (out of 2; eq. 6.4-6.5) and the flow force [N]."""
        a = self.p
        ps, pr, w, e = (a["actuator.supply_pressure"], a["actuator.return_pressure"],
                        a["actuator.port_width"], a["actuator.leak_opening"])
        a_pos = w * 0.5 * (xs + math.sqrt(xs * xs + e * e))     # edges open for x_s > 0
        a_neg = w * 0.5 * (-xs + math.sqrt(xs * xs + e * e))
        q1 = self.orifice(a_pos, ps - p1) - self.orifice(a_neg, p1 - pr)
        q2 = self.orifice(a_pos, p2 - pr) - self.orifice(a_neg, ps - p2)
        k = 2 * a["actuator.discharge_coefficient"] * math.cos(a["actuator.jet_angle"])
        force = -k * (a_pos * (abs(ps - p1) + abs(p2 - pr)) - a_neg * (abs(ps - p2) + abs(p1 - pr)))
        return q1, q2, force

    def servo(self, x, c, dx):
        """Controller, LVDT, jet pipe (eq. 6.2) and spool (eq. 6.3) into dx."""
        a = lambda k: self.p["actuator." + k]    # noqa: E731
        lim = a("current_limit")
        i = lim * math.tanh((a("proportional_gain") * (c - x[L])
                             + a("integral_gain") * x[INT]) / lim)
        dx[L] = (x[U] - x[L]) / a("lvdt_time_constant")
        dx[INT] = c - x[L]
        dx[XJ] = x[VJ]
        dx[VJ] = (a("motor_gain") * i - a("jet_stiffness") * x[XJ] - a("jet_damping") * x[VJ]
                  - a("wire_stiffness") * (x[XS] + x[XJ])) / a("jet_mass")
        span = a("supply_pressure") - a("return_pressure")
        jet_dp = span * math.tanh(a("jet_pressure_gain") * x[XJ] / span)
        flow_force = self.valve(x[XS], x[P1], x[P2])[2]
        dx[XS] = x[VS]
        wire = a("wire_stiffness") * self.wire_on_spool(x[XS], x[XJ])
        dx[VS] = (a("spool_area") * jet_dp - wire + flow_force
                  - a("spool_damping") * x[VS]) / a("spool_mass")

    def cylinder(self, x, dx):
        """Chambers (eq. 6.11-6.12), piston (eq. 6.13) and the linkage into dx."""
        a = lambda k: self.p["actuator." + k]    # noqa: E731
        q1, q2, _ = self.valve(x[XS], x[P1], x[P2])
        area, beta, pr = a("piston_area"), a("bulk_modulus"), a("return_pressure")
        v1 = a("dead_volume") + area * (a("half_stroke") + x[U])
        v2 = a("dead_volume") + area * (a("half_stroke") - x[U])
        inner = a("internal_leakage") * (x[P1] - x[P2])
        dx[P1] = beta / v1 * (q1 - area * x[V] - inner - a("external_leakage") * (x[P1] - pr))
        dx[P2] = beta / v2 * (-q2 + area * x[V] + inner - a("external_leakage") * (x[P2] - pr))
        p = self.p
        k1, c1 = p["slider_spring.stiffness"], p["slider_spring.damping"]
        k2, c2 = p["crank_spring.stiffness"], p["crank_spring.damping"]
        # the rod end moves along the crank's tangent by u / cos(alpha); the piston feels the
        # slider spring's force projected on the rod, cos(alpha) F_1
        f1 = k1 * (x[U] / self.cos_a - x[YB]) + c1 * (x[V] / self.cos_a - x[VB])
        f2 = k2 * (x[YB] - x[YC]) + c2 * (x[VB] - x[VC])
        dx[U] = x[V]
        dx[V] = (area * (x[P1] - x[P2]) - a("piston_friction") * x[V]
                 - self.cos_a * f1) / a("piston_mass")
        dx[YB] = x[VB]
        dx[VB] = (f1 - f2) / self.m_b
        dx[YC] = x[VC]
        dx[VC] = (f2 - self.c_c * x[VC]) / self.m_c

    def rhs(self, x, c=0.0):
        dx = np.zeros(N)
        self.servo(x, c, dx)
        self.cylinder(x, dx)
        return dx


def jacobian(fun, x0):
    """Central differences, step 1e-4 of each state's scale (truncation error ~1e-8)."""
    cols = []
    for j in range(len(x0)):
        h = 1e-4 * SCALE[j]
        e = np.zeros(len(x0))
        e[j] = h
        cols.append((fun(x0 + e) - fun(x0 - e)) / (2 * h))
    return np.array(cols).T


def operating_point(model, pressure):
    """The state about which to linearise, zero command: `mid` or `settled` (Newton)."""
    a = model.p
    x = np.zeros(N)
    x[P1] = x[P2] = 0.5 * (a["actuator.supply_pressure"] + a["actuator.return_pressure"])
    if pressure == "mid":
        return x
    for _ in range(50):
        f = model.rhs(x)
        jac = jacobian(model.rhs, x)      # columns scaled below: states span 1e-6 to 1e7
        step = np.linalg.solve(jac * SCALE, -f) * SCALE
        x = x + step
        if np.all(np.abs(step) < 1e-12 * SCALE):
            break
    else:
        raise RuntimeError("the operating point did not converge")
    return x


class Linear:
    """x' = A x + B c about an operating point; transfer functions at frequencies [Hz]."""

    def __init__(self, model, pressure="settled"):
        self.model = model
        self.x0 = operating_point(model, pressure)
        self.a = jacobian(model.rhs, self.x0)
        self.b = (model.rhs(self.x0, 1e-6) - model.rhs(self.x0, -1e-6)) / 2e-6

    def poles(self):
        return np.linalg.eigvals(self.a)

    def response(self, f):
        """(piston/command, surface angle / rigid-linkage angle of the command) at f [Hz]."""
        x = np.linalg.solve(2j * math.pi * f * np.eye(N) - self.a, self.b)
        return x[U], x[YC] / self.model.crank * self.model.r

    def bandwidth(self, which=0, lo=0.1, hi=200.0):
        """The lowest frequency [Hz] at which |H| falls to 1/sqrt(2) (bisection on log f)."""
        g = lambda f: abs(self.response(f)[which]) - 1 / math.sqrt(2)    # noqa: E731
        fs = np.geomspace(lo, hi, 400)
        k = next(i for i in range(len(fs)) if g(fs[i]) < 0)
        a, b = fs[k - 1], fs[k]
        for _ in range(60):
            m = math.sqrt(a * b)
            a, b = (m, b) if g(m) > 0 else (a, m)
        return math.sqrt(a * b)


def hertz_intercept(lo=0.2, hi=0.9, exponent=2 / 3):
    """(least-squares, secant) intercepts at x = 0 of lines fitted to x^n on [lo, hi], n = 2/3:
    the Hertz penetration the free-play metric's branch lines leave at zero load, in units of
    the penetration at the largest load. The least-squares line over a uniform x (the moment is
    a triangle, linear in time), exact: intercept = mean(y) - slope mean(x)."""
    n = exponent
    width = hi - lo
    mean_x = (lo + hi) / 2
    mean_y = (hi ** (n + 1) - lo ** (n + 1)) / ((n + 1) * width)
    mean_xy = (hi ** (n + 2) - lo ** (n + 2)) / ((n + 2) * width)
    var_x = width ** 2 / 12
    slope = (mean_xy - mean_x * mean_y) / var_x
    secant = (hi ** n - lo ** n) / width
    return mean_y - slope * mean_x, lo ** n - secant * lo


def report(p, pressure, freqs, eq_6_3_as_printed=False):
    model = Model(p, eq_6_3_as_printed)
    lin = {k: Linear(model, k) for k in ("settled", "mid")}
    main = lin[pressure]
    print(f"operating point ({pressure}): P1 = {main.x0[P1] / 1e6:.4f} MPa, "
          f"P2 = {main.x0[P2] / 1e6:.4f} MPa, spool {main.x0[XS] * 1e6:.4f} um")
    poles = sorted(main.poles(), key=lambda z: (abs(z), z.imag))
    print("poles [rad/s]: " + ", ".join(f"{z.real:.4g}{z.imag:+.4g}i" if abs(z.imag) > 1e-9
                                         else f"{z.real:.4g}" for z in poles))
    print("| f [Hz] | " + " | ".join(f"{f:g}" for f in freqs) + " |")
    print("|---|" + "---|" * len(freqs))
    rows = [main.response(f) for f in freqs]
    for name, which in (("piston", 0), ("surface", 1)):
        print(f"| {name} gain | " + " | ".join(f"{abs(r[which]):.3f}" for r in rows) + " |")
        print(f"| {name} phase [°] | "
              + " | ".join(f"{math.degrees(np.angle(r[which])):.1f}" for r in rows) + " |")
    for k, m in lin.items():
        print(f"-3 dB bandwidth at the {k} pressure ({m.x0[P1] / 1e6:.2f} MPa): "
              f"piston {m.bandwidth(0):.2f} Hz, surface {m.bandwidth(1):.2f} Hz")
    ls, sec = hertz_intercept()
    print(f"intercept at zero load of a line fitted to x^(2/3) on [0.2, 0.9]: "
          f"least squares {ls:.4f}, secant {sec:.4f}")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rodend", help="the rodend executable (default $RODEND, else build/rodend)")
    ap.add_argument("--params", help="a file of `rodend params rod-end-actuator --json`")
    ap.add_argument("--pressure", choices=("settled", "mid"), default="settled",
                    help="the operating point of the poles and the table (default settled)")
    ap.add_argument("--freq", type=float, nargs="+", default=DEFAULT_FREQS,
                    help="frequencies of the table [Hz]")
    ap.add_argument("--eq-6-3-as-printed", action="store_true",
                    help="the feedback wire on the spool as the thesis's eq. 6.3 prints it, "
                         "-(x_j - x_s) k_W, instead of eq. 6.2's -(x_s + x_j) k_W")
    args = ap.parse_args(argv)
    report(load_parameters(args.rodend, args.params), args.pressure, args.freq,
           args.eq_6_3_as_printed)
    return 0


if __name__ == "__main__":
    sys.exit(main())
