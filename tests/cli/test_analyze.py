"""rodend.analyze (issue 30, the analysis of a designed study) on synthetic results folders
whose answers are known (tests/cli/analyze_fixtures.py writes design.json and the summary in
the layout of docs/results.md; the design points are drawn here with OpenTURNS and numpy).

- Ishigami (a = 7, b = 0.1, X_i ~ U(-pi, pi)) through a saltelli design (N = 2000, seed 7):
  the published S1 = (0.3139, 0.4424, 0), ST = (0.5576, 0.4424, 0.2437) lie within the bootstrap
  intervals, and the intervals are narrower than 0.25 (an interval of everything cannot pass);
  through the chaos (saltelli's A+B blocks, and a monte-carlo design of 1000 points): Q² (LOO) >
  0.999 and every index within 0.01 of the published value. Why 0.01: the chaos is a smooth
  fit of a smooth function; the variance it leaves out, (1 - Q²) var Y < 0.001 var Y, bounds
  what it can move between factors, and the rest is the sampling error of its coefficients:
  `bench/analyze.py --widths` measured a largest index error of 0.0001 at 1000 monte-carlo
  points (seeds 1..5, least squares), 0.0018 at 500 and 0.0055 at 100 (LARS); with least
  squares alone, 0.036 at 200 (Q² 0.946); 0.01 keeps a margin
  without hiding a wrong index (the nearest wrong answer, S1 and ST of x3 swapped, is 0.24
  away).
- every distribution of design.json (uniform, normal, truncated-normal, lognormal by the
  variable's mean and std, triangular, discrete with weights), drawn with numpy: the chaos of
  y = sum a_i x_i has S_i = ST_i = a_i² var_i / sum_j a_j² var_j with the variances in
  closed form (the chaos's degree-1 coefficient is a_i times the std of the distribution it
  was given, so a misread parameter shows), to 1e-6.
  At 150 cases the chaos's auto method keeps sparse LARS (least squares on a whole basis
  leaves Q² < 0.9 there: 0.64) and meets the same bounds.
- the exact LOO: the hat-matrix Q² equals leave-one-out refits done one by one.
- failed cases of a saltelli design remove their whole row groups, counted; too few left:
  a ValueError naming the count.
- Morris: y = sum a_i x_i, x_i ~ U(l_i, u_i): every effect is a_i (u_i - l_i), sigma = 0;
  y = x1 x2 on U(0,1)^2: the effect of x1 is the value of x2 at that step (and conversely), so
  mu* and sigma are the mean and standard deviation of those values, read off the design.
- y = x, x ~ U(0,1) (monte-carlo, 2000 points): P(y > 0.9) = 0.1 within its Clopper–Pearson
  interval, the 5/50/95 % quantiles, mean 1/2 and std 1/sqrt(12) within theirs; two grid points
  analysed apart (y = x + 10 at the second). At 99.9 %: six intervals checked at 95 % would
  miss one in four samples by chance (this sample's mean is 2.6 standard errors low, and
  its median misses its 95 % interval); at 99.9 % a miss is a bug, and the width bound on P
  keeps the check able to fail.
- history bands: s(t) = x t with x = 0, 0.01, ..., 1 (101 ok cases, one failed case with
  x = 100 left out): the bands are exactly t (0.05, 0.5, 0.95), per component for a vector;
  the same with every third case on a coarser time grid (interpolated: exact for a line).
- bad input: no design.json, an unknown metric (the nearest names), a bad threshold, broken
  Morris points: ValueError; the command line prints it and exits 2.
"""
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile

import h5py
import numpy as np

from common import check, finish
import analyze_fixtures as fx

import rodend  # noqa: E402  (PYTHONPATH=<repo>/python)
from rodend.analysis import chaos as chaos_mod

S1 = (0.3139, 0.4424, 0.0)
ST = (0.5576, 0.4424, 0.2437)


def ishigami_design(n, method="saltelli", seed=7):
    fs = [fx.uniform(f"parameters.x{i}", -fx.PI, fx.PI, "rad") for i in (1, 2, 3)]
    if method == "saltelli":
        x = fx.saltelli_points(fs, n, seed)
    else:
        x = fx.mc_points(fs, n, seed)
    d = {"method": method, "size": n, "seed": seed, "points": len(x), "factors": fs}
    if method == "saltelli":
        d["base"] = "monte-carlo"
    return d, x


def test_ishigami_saltelli(tmp):
    d, x = ishigami_design(2000)
    folder = fx.write_folder(os.path.join(tmp, "ishigami"), d, x, {"y": fx.ishigami(x)},
                             units={"y": "N"})
    doc = rodend.analyze(folder, bootstrap=200, quiet=True)
    r = doc["groups"][0]["metrics"]["y"]
    check(r["units"] == "N", f"units {r['units']}")
    s = r["sobol"]
    for i in range(3):
        for name, want in (("first_order", S1[i]), ("total", ST[i])):
            lo, hi = s[name + "_interval"][i]
            check(lo <= want <= hi, f"ishigami {name}[{i}]: {want} not in [{lo}, {hi}] "
                                    f"(estimate {s[name][i]})")
            check(hi - lo < 0.25, f"ishigami {name}[{i}]: interval [{lo}, {hi}] too wide")
    _check_chaos(r["chaos"], "saltelli A+B")
    check(r["chaos"]["points"] == 4000, f"chaos on A+B: {r['chaos']['points']} points")
    with open(os.path.join(folder, "analysis", "analysis.json")) as fh:
        check(json.load(fh)["groups"][0]["metrics"]["y"]["sobol"]["groups"] == 2000, "json")
    for kind in ("indices", "cdf", "chaos"):
        check(os.path.isfile(os.path.join(folder, "plots", f"analysis-y-{kind}.png")), kind)


def _check_chaos(c, what):
    check(c["q2_loo"] > 0.999, f"{what}: chaos Q2 {c['q2_loo']}")
    for i in range(3):
        check(abs(c["first_order"][i] - S1[i]) < 0.01, f"{what}: chaos S1[{i}] "
                                                       f"{c['first_order'][i]} vs {S1[i]}")
        check(abs(c["total"][i] - ST[i]) < 0.01, f"{what}: chaos ST[{i}] {c['total'][i]}")


def test_ishigami_chaos_mc(tmp):
    d, x = ishigami_design(1000, "monte-carlo", seed=3)
    folder = fx.write_folder(os.path.join(tmp, "ishigami-mc"), d, x, {"y": fx.ishigami(x)})
    r = rodend.analyze(folder, quiet=True, plots=False)["groups"][0]["metrics"]["y"]
    check("sobol" not in r, "a monte-carlo design has no pick-freeze indices")
    _check_chaos(r["chaos"], "monte-carlo")
    # 150 cases: least squares on a whole basis cannot fit Ishigami (Q² < 0.9), sparse LARS
    # can: auto keeps it
    d, x = ishigami_design(150, "monte-carlo", seed=3)
    folder = fx.write_folder(os.path.join(tmp, "ishigami-150"), d, x, {"y": fx.ishigami(x)})
    c = rodend.analyze(folder, quiet=True, plots=False)["groups"][0]["metrics"]["y"]["chaos"]
    tried = c.get("q2_loo_tried", {})
    check(c["method"] == "lars" and tried.get("least-squares", 1) < 0.9, f"auto at 150: {tried}")
    _check_chaos(c, "monte-carlo, 150 cases, lars")


def test_exact_loo():
    rng = np.random.default_rng(5)
    psi = np.column_stack([np.ones(30), rng.normal(size=(30, 4))])
    y = psi @ rng.normal(size=5) + 0.3 * rng.normal(size=30)
    q2, pred = chaos_mod.loo(psi, y)
    brute = np.empty(30)
    for i in range(30):
        m = np.arange(30) != i
        brute[i] = psi[i] @ np.linalg.lstsq(psi[m], y[m], rcond=None)[0]
    check(np.allclose(pred, brute, rtol=1e-10, atol=1e-12), "LOO predictions != refits")
    want = 1 - np.sum((y - brute) ** 2) / np.sum((y - y.mean()) ** 2)
    check(abs(q2 - want) < 1e-12, f"Q2 {q2} vs {want}")


def _truncated_normal_var(m, s, a, b):
    phi = lambda z: math.exp(-z * z / 2) / math.sqrt(2 * math.pi)  # noqa: E731
    cdf = lambda z: 0.5 * (1 + math.erf(z / math.sqrt(2)))        # noqa: E731
    al, be = (a - m) / s, (b - m) / s
    z = cdf(be) - cdf(al)
    return s * s * (1 + (al * phi(al) - be * phi(be)) / z - ((phi(al) - phi(be)) / z) ** 2)


def test_distributions(tmp):
    rng = np.random.default_rng(4)
    n = 2000
    sig = math.sqrt(math.log(1 + (0.5 / 2.0) ** 2))
    tn = rng.normal(1.0, 2.0, size=8 * n)
    tn = tn[(tn > 0.0) & (tn < 3.0)][:n]
    vals, w = np.array([1.0, 2.0, 5.0]), np.array([0.2, 0.5, 0.3])
    a, c, b = 0.0, 1.0, 4.0
    factors = [
        (fx.uniform("parameters.u", 2.0, 6.0), rng.uniform(2, 6, n), 16 / 12),
        ({"key": "parameters.n", "distribution": "normal", "mean": 1.0, "std": 0.3},
         rng.normal(1, 0.3, n), 0.09),
        ({"key": "parameters.t", "distribution": "truncated-normal", "mean": 1.0, "std": 2.0,
          "lower": 0.0, "upper": 3.0}, tn, _truncated_normal_var(1.0, 2.0, 0.0, 3.0)),
        ({"key": "parameters.l", "distribution": "lognormal", "mean": 2.0, "std": 0.5},
         rng.lognormal(math.log(2.0) - sig * sig / 2, sig, n), 0.25),
        ({"key": "parameters.r", "distribution": "triangular", "lower": a, "mode": c,
          "upper": b}, rng.triangular(a, c, b, n), (a * a + b * b + c * c - a * b - a * c - b * c) / 18),
        ({"key": "parameters.k", "distribution": "discrete", "values": vals.tolist(),
          "weights": w.tolist()}, rng.choice(vals, n, p=w), float(w @ vals ** 2 - (w @ vals) ** 2))]
    coef = np.array([1.0, 3.0, -0.7, 2.0, 0.8, 0.5])
    x = np.column_stack([f[1] for f in factors])
    var = coef ** 2 * np.array([f[2] for f in factors])
    d = {"method": "monte-carlo", "size": n, "seed": 4, "points": n,
         "factors": [f[0] for f in factors]}
    folder = fx.write_folder(os.path.join(tmp, "kinds"), d, x, {"y": x @ coef})
    c = rodend.analyze(folder, quiet=True, plots=False)["groups"][0]["metrics"]["y"]["chaos"]
    want = var / var.sum()
    check(np.allclose(c["first_order"], want, atol=1e-6), f"S1 {c['first_order']} vs {want}")
    check(np.allclose(c["total"], want, atol=1e-6), f"ST {c['total']} vs {want}")


def test_saltelli_failures(tmp):
    n = 200
    d, x = ishigami_design(n)
    y = fx.ishigami(x)
    status = np.array(["ok"] * len(x), dtype=object)
    bad = [5, n + 5, 2 * n + 17, 4 * n + 17, 3 * n + 33]      # groups 5, 17, 33
    status[bad] = "step_budget_exhausted"
    y[bad] = np.nan
    folder = fx.write_folder(os.path.join(tmp, "failures"), d, x, {"y": y}, status=status)
    g = rodend.analyze(folder, quiet=True, plots=False)["groups"][0]
    s = g["metrics"]["y"]["sobol"]
    check(g["failed"] == 5 and g["metrics"]["y"]["failed"] == 5, f"failed {g['failed']}")
    check(s["groups"] == n - 3 and s["removed_groups"] == 3, f"groups {s['groups']}")
    check(g["metrics"]["y"]["distribution"]["n"] == 2 * n - 2, "iid A+B without 2 failures")
    status[:] = "non_finite_state"
    status[[0, n, 2 * n, 3 * n, 4 * n]] = "ok"                # one complete group left
    folder = fx.write_folder(os.path.join(tmp, "failures2"), d, x, {"y": y}, status=status)
    try:
        rodend.analyze(folder, quiet=True, plots=False)
        check(False, "saltelli with one complete row group: no error")
    except ValueError as e:
        check("1 of 200 row groups" in str(e) and "metric y" in str(e), f"message: {e}")


def morris_folder(tmp, name, factors, f, n=20, levels=4, seed=3):
    unit, delta = fx.morris_unit_points(len(factors), n, levels, seed)
    lo = np.array([q["lower"] for q in factors])
    hi = np.array([q["upper"] for q in factors])
    x = lo + unit * (hi - lo)                                 # uniform: the inverse CDF
    d = {"method": "morris", "size": n, "seed": seed, "levels": levels, "delta": delta,
         "points": len(x), "factors": factors, "unit_points": unit.tolist()}
    return fx.write_folder(os.path.join(tmp, name), d, x, {"y": f(x)}), unit


def test_morris(tmp):
    a = np.array([2.0, -3.0, 0.5])
    fs = [fx.uniform("parameters.a", 0, 1), fx.uniform("parameters.b", 1, 3),
          fx.uniform("parameters.c", -10, 10)]
    folder, _ = morris_folder(tmp, "morris-linear", fs, lambda x: x @ a)
    m = rodend.analyze(folder, quiet=True)["groups"][0]["metrics"]["y"]["morris"]
    want = a * np.array([1, 2, 20])
    check(np.allclose(m["mu"], want, rtol=1e-9), f"linear mu {m['mu']} vs {want}")
    check(np.allclose(m["mu_star"], np.abs(want), rtol=1e-9), f"linear mu* {m['mu_star']}")
    check(np.allclose(m["sigma"], 0, atol=1e-9 * np.abs(want).max()), f"sigma {m['sigma']}")
    check(m["effects"] == [20, 20, 20], f"effects {m['effects']}")
    check(os.path.isfile(os.path.join(folder, "plots", "analysis-y-morris.png")), "figure")

    fs = [fx.uniform("parameters.p", 0, 1), fx.uniform("parameters.q", 0, 1)]
    folder, unit = morris_folder(tmp, "morris-product", fs, lambda x: x[:, 0] * x[:, 1], n=30)
    m = rodend.analyze(folder, quiet=True)["groups"][0]["metrics"]["y"]["morris"]
    for i in (0, 1):
        other = []                                           # the other factor at each step
        for t in range(30):
            for k in (1, 2):
                step = unit[3 * t + k] - unit[3 * t + k - 1]
                if abs(step[i]) > 0:
                    other.append(unit[3 * t + k, 1 - i])
        other = np.array(other)
        check(abs(m["mu_star"][i] - np.abs(other).mean()) < 1e-12, f"product mu*[{i}]")
        check(abs(m["sigma"][i] - other.std(ddof=1)) < 1e-12 and m["sigma"][i] > 0.1,
              f"product sigma[{i}] {m['sigma'][i]} vs {other.std(ddof=1)}")


def test_exceedance(tmp):
    fs = [fx.uniform("parameters.u", 0, 1)]
    x = fx.mc_points(fs, 2000, 11)
    d = {"method": "monte-carlo", "size": 2000, "seed": 11, "points": 2000, "factors": fs}
    xx = np.vstack([x, x])
    grid = {"parameters.offset": np.repeat([0.0, 10.0], 2000)}
    y = xx[:, 0] + grid["parameters.offset"]
    folder = fx.write_folder(os.path.join(tmp, "uniform"), d, xx, {"y": y}, grid=grid)
    doc = rodend.analyze(folder, thresholds={"y": [0.9, 10.9]}, confidence=0.999, quiet=True)
    check(len(doc["groups"]) == 2, f"{len(doc['groups'])} groups")
    for g, off in zip(doc["groups"], (0.0, 10.0)):
        check(g["grid"] == {"parameters.offset": off}, f"grid {g['grid']}")
        r = g["metrics"]["y"]
        e = r["exceedance"][0 if off == 0 else 1]
        lo, hi = e["interval"]
        check(lo <= 0.1 <= hi and hi - lo < 0.05, f"P(y > {e['threshold']}) interval {lo, hi}")
        dist = r["distribution"]
        for p in ("0.05", "0.5", "0.95"):
            lo, hi = dist["quantile_intervals"][p]
            check(lo <= off + float(p) <= hi, f"quantile {p}: [{lo}, {hi}]")
        check(dist["mean_interval"][0] <= off + 0.5 <= dist["mean_interval"][1], "mean")
        lo, hi = dist["std_interval"]
        check(lo <= 12 ** -0.5 <= hi, f"std [{lo}, {hi}]")
    check(os.path.isfile(os.path.join(folder, "plots", "analysis-y-cdf-g1.png")), "cdf g1")


def test_scene_axis(tmp):
    """A scene axis has no column but scene: its grid points are still analysed apart."""
    fs = [fx.uniform("parameters.u", 0, 1)]
    x = fx.mc_points(fs, 500, 2)
    d = {"method": "monte-carlo", "size": 500, "seed": 2, "points": 500, "factors": fs}
    xx = np.vstack([x, x, x, x])
    scene = np.repeat(["gravity-drop", "rod-end-actuator"], 1000)
    grid = {"parameters.contact.clearance": np.tile(np.repeat([1e-4, 2e-4], 500), 2)}
    y = xx[:, 0] * grid["parameters.contact.clearance"] * np.where(scene == "gravity-drop", 1, -1)
    folder = fx.write_folder(os.path.join(tmp, "scenes"), d, xx, {"y": y}, grid=grid,
                             scene=scene)
    doc = rodend.analyze(folder, quiet=True)
    got = [(g["grid"]["scene"], g["grid"]["parameters.contact.clearance"],
            g["metrics"]["y"]["distribution"]["mean"]) for g in doc["groups"]]
    want = [(s, c, sign * c / 2) for s, sign in (("gravity-drop", 1), ("rod-end-actuator", -1))
            for c in (1e-4, 2e-4)]
    check(len(got) == 4 and all(g[:2] == w[:2] and abs(g[2] - w[2]) < 0.1 * w[1]
                                for g, w in zip(got, want)), f"scene axis groups {got}")
    check(os.path.isfile(os.path.join(folder, "plots", "analysis-y-cdf-g3.png")), "figure g3")


def test_bands(tmp):
    xs = np.append(np.linspace(0, 1, 101), 100.0)
    fs = [fx.uniform("parameters.k", 0, 100)]
    d = {"method": "monte-carlo", "size": 102, "seed": 1, "points": 102, "factors": fs}
    status = ["ok"] * 101 + ["penetration_limit"]
    folder = fx.write_folder(os.path.join(tmp, "bands"), d, xs[:, None], {"y": xs},
                             status=status)
    t = np.linspace(0, 0.5, 51)
    for i, k in enumerate(xs):
        fx.write_case(folder, f"c{i:06d}", t, {"s": k * t, "v": np.outer(k * t, [1, 2, -1])},
                      {"s": "m", "v": "N"})
    _check_bands(folder, t, resampled=False)
    for i, k in enumerate(xs):                   # every third case on a coarser time grid
        tc = t if i % 3 else np.linspace(0, 0.5, 26)
        fx.write_case(folder, f"c{i:06d}", tc, {"s": k * tc, "v": np.outer(k * tc, [1, 2, -1])},
                      {"s": "m", "v": "N"})
    _check_bands(folder, t, resampled=True)


def _check_bands(folder, t, resampled):
    rodend.analyze(folder, histories=["s", "v"], quiet=True)
    with h5py.File(os.path.join(folder, "analysis", "bands.h5")) as f:
        s, v = f["g0/s"], f["g0/v"]
        want = np.outer([0.05, 0.5, 0.95], t)
        check(np.allclose(s["quantiles"][()], want, atol=1e-12), "scalar bands")
        check(s["quantiles"].attrs["units"] == "m" and s["time"].attrs["units"] == "s", "units")
        check(int(s.attrs["cases"]) == 101, f"cases {s.attrs['cases']}")
        check(bool(s.attrs["resampled"]) == resampled, f"resampled {s.attrs['resampled']}")
        q = v["quantiles"][()]
        check(np.allclose(q[:, :, 1], 2 * want, atol=1e-12), "vector component 1")
        check(np.allclose(q[:, :, 2], -want[::-1], atol=1e-12), "vector component 2")
    check(os.path.isfile(os.path.join(folder, "plots", "analysis-v-bands.png")), "band figure")


def test_bad_input(tmp):
    empty = os.path.join(tmp, "empty")
    os.makedirs(empty)
    _expect_error(lambda: rodend.analyze(empty, quiet=True), "design.json", "no design")
    d, x = ishigami_design(50, "monte-carlo")
    folder = fx.write_folder(os.path.join(tmp, "bad"), d, x,
                             {"max_contact_force": fx.ishigami(x)})
    _expect_error(lambda: rodend.analyze(folder, metrics=["max_contact_forse"], quiet=True),
                  "nearest: max_contact_force", "typo")
    _expect_error(lambda: rodend.analyze(folder, thresholds=["max_contact_force>3"],
                                         quiet=True), "METRIC=VALUE", "threshold")
    _expect_error(lambda: rodend.analyze(folder, thresholds={"max_contact_force": "x"},
                                         quiet=True), "finite number", "threshold value")
    fs = [fx.uniform("parameters.p", 0, 1), fx.uniform("parameters.q", 0, 1)]
    mfolder, unit = morris_folder(tmp, "morris-bad", fs, lambda x: x[:, 0])
    with open(os.path.join(mfolder, "design.json")) as fh:
        dd = json.load(fh)
    dd["unit_points"][1] = [0.5, 0.5]
    with open(os.path.join(mfolder, "design.json"), "w") as fh:
        json.dump(dd, fh)
    _expect_error(lambda: rodend.analyze(mfolder, quiet=True), "expected one factor moved",
                  "morris points")
    r = subprocess.run([sys.executable, "-m", "rodend.analyze", folder, "--threshold", "y"],
                       capture_output=True, text=True)
    check(r.returncode == 2 and "expected METRIC=VALUE" in r.stderr,
          f"CLI: rc {r.returncode}, stderr {r.stderr!r}")
    r = subprocess.run([sys.executable, "-m", "rodend.analyze", folder, "--no-plots",
                        "--bootstrap", "50"], capture_output=True, text=True)
    check(r.returncode == 0 and "chaos" in r.stdout, f"CLI ok: {r.returncode} {r.stderr}")


def test_ranking(tmp):
    """y = 3 x1 + x2 + 0.1 x3 on U(0, 1)^3 (monte-carlo, 2000 points): SRC_i = a_i / sqrt(sum
    a_j^2) exactly for a linear y of independent factors of equal spread (0.948, 0.316, 0.032),
    within 0.02 (the sample correlations' standard error, about 1/sqrt(2000) = 0.022 times
    1 - SRC^2); the bootstrap interval at 99.9 % holds it (at 95 %, three intervals would miss
    one in seven samples by chance); the numpy formulas of the intervals give the
    OpenTURNS values on the full sample to 1e-10; the ranking is x1, x2, x3 by the chaos's total
    index (Q² = 1: a linear metric). With design.correlation in design.json the chaos is
    skipped and the ranking is by |PRCC|. The printed table labels every column."""
    from rodend.analysis import ranking as rk
    fs = [fx.uniform(f"parameters.x{i}", 0, 1) for i in (1, 2, 3)]
    x = fx.mc_points(fs, 2000, 9)
    a = np.array([3.0, 1.0, 0.1])
    d = {"method": "monte-carlo", "size": 2000, "seed": 9, "points": 2000, "factors": fs}
    folder = fx.write_folder(os.path.join(tmp, "linear"), d, x, {"y": x @ a}, units={"y": "rad"})
    doc = rodend.analyze(folder, quiet=True, plots=False, confidence=0.999)
    r = doc["groups"][0]["metrics"]["y"]
    want = a / np.sqrt(np.sum(a ** 2))
    c = r["correlation"]
    check(np.allclose(c["src"], want, atol=0.02), f"SRC {c['src']} vs {want}")
    for i in range(3):
        lo, hi = c["src_interval"][i]
        check(lo <= want[i] <= hi, f"SRC[{i}] interval [{lo}, {hi}] misses {want[i]}")
    src, prcc, spear = rk._from_matrices(x, x @ a + 0.3 * np.sin(7 * x[:, 1]))
    c2 = rk.correlations(x, x @ a + 0.3 * np.sin(7 * x[:, 1]), bootstrap=0)
    for name, mine in (("src", src), ("prcc", prcc), ("spearman", spear)):
        check(np.allclose(mine, c2[name], atol=1e-10), f"{name}: numpy {mine} vs OT {c2[name]}")
    order = [f["factor"] for f in r["ranking"]["factors"]]
    check(order == [f["key"] for f in fs] and r["ranking"]["measure"] == "chaos_total",
          f"ranking {r['ranking']}")
    check(r["shown"] == {"units": "mrad", "factor": 1000.0}, f"shown {r['shown']}")
    text = rodend.analysis.output.table(doc)
    check("y [mrad]" in text and "factors ranked by total Sobol' index (polynomial chaos" in text
          and "SRC" in text and "PRCC" in text and "95 % quantile" in text and
          "99.9 % interval" in text, text)
    d["correlation"] = {"kind": "spearman", "matrix": np.eye(3).tolist()}
    folder = fx.write_folder(os.path.join(tmp, "correlated"), d, x, {"y": x @ a})
    r = rodend.analyze(folder, quiet=True, plots=False)["groups"][0]["metrics"]["y"]
    check("skipped" in r["chaos"] and r["ranking"]["measure"] == "abs_prcc" and
          [f["factor"] for f in r["ranking"]["factors"]] == [f["key"] for f in fs],
          f"correlated: chaos {r['chaos']}, ranking {r['ranking']}")


def test_morris_spread(tmp):
    """A Morris design's spread over its points: y = x on U(0, 1) with 4 levels takes the
    values 0, 1/3, 2/3, 1 equally often, so the mean is 1/2 and P(y > 0.5) = 1/2 up to the
    draw; the intervals (a bootstrap over the 40 trajectories) hold them; intervals over
    trajectories are wider than those an independent-points formula would give (the points of
    a trajectory are dependent)."""
    fs = [fx.uniform("parameters.p", 0, 1), fx.uniform("parameters.q", 0, 1)]
    folder, unit = morris_folder(tmp, "morris-spread", fs, lambda x: x[:, 0], n=40)
    r = rodend.analyze(folder, thresholds={"y": 0.5}, quiet=True, plots=False)
    r = r["groups"][0]["metrics"]["y"]
    dist, e = r["distribution"], r["exceedance"][0]
    check(dist["trajectories"] == 40 and "Morris" in dist["sample"], f"{dist}")
    check(abs(dist["mean"] - unit[:, 0].mean()) < 1e-12, "mean over the points")
    lo, hi = dist["mean_interval"]
    check(lo <= 0.5 <= hi, f"mean interval [{lo}, {hi}]")
    lo, hi = e["interval"]
    check(lo <= 0.5 <= hi and e["n"] == 120, f"P(y > 0.5) {e}")
    check(r["ranking"]["measure"] == "mu_star" and
          r["ranking"]["factors"][0]["factor"] == "parameters.p", f"ranking {r['ranking']}")


def _expect_error(fn, text, what):
    try:
        fn()
        check(False, f"{what}: no ValueError")
    except ValueError as e:
        check(text in str(e), f"{what}: message {e!r} lacks {text!r}")


def main():
    tmp = tempfile.mkdtemp(prefix="rodend-analyze-")
    try:
        test_exact_loo()
        test_ishigami_saltelli(tmp)
        test_ishigami_chaos_mc(tmp)
        test_distributions(tmp)
        test_saltelli_failures(tmp)
        test_morris(tmp)
        test_exceedance(tmp)
        test_scene_axis(tmp)
        test_bands(tmp)
        test_ranking(tmp)
        test_morris_spread(tmp)
        test_bad_input(tmp)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    finish("analyze")


if __name__ == "__main__":
    main()
