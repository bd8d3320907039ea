#!/usr/bin/python3
"""Benchmark of rodend analyze (not a test): the time and peak memory of the analysis
of a synthetic 1e4-case results folder, and the interval widths the Ishigami function gets
with the number of cases (the table of docs/uncertainty.md).

    RODEND_BUILD_DIR=build PYTHONPATH=python /usr/bin/python3 bench/analyze.py [--cases 10000]
        [--bootstrap 200] [--widths] [--keep DIR]

Timing: two folders of --cases cases, written first (not timed): a saltelli design over 6
uniform factors (N = cases / 8) and a monte-carlo design over 8; three metrics each (an
Ishigami-like function plus linear terms, a product with an interaction, and a metric with
2 % failed cases) and one threshold each. `python3 -m rodend.analyze FOLDER` runs in a child
process; its wall time, CPU time (user + system: less sensitive to a busy machine) and peak
resident memory (getrusage of the child) are printed, figures included.

--widths: the Ishigami function (3 factors) through saltelli designs of N = 100 .. 4000 (5 N
cases): the mean width of the 95 % intervals of S1 and ST and how often they hold the published
values (seeds 1..20); and through the chaos of monte-carlo designs of 50 .. 2000 cases: the
smallest Q² (LOO) and the largest error of its six indices (seeds 1..5).
"""
import argparse
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tests", "cli"))
import analyze_fixtures as fx  # noqa: E402


def metrics(x, rng):
    y1 = fx.ishigami(x[:, :3]) + 0.5 * x[:, 3:].sum(axis=1)
    y2 = x[:, 0] * x[:, 1] + np.cos(x[:, 2]) * x[:, 3]
    y3 = np.exp(0.2 * x[:, 0]) + x[:, -1] ** 2
    failed = rng.random(len(x)) < 0.02
    y3[failed] = np.nan
    return {"y1": y1, "y2": y2, "y3": y3}, np.where(failed, "step_budget_exhausted", "ok")


def make(folder, method, d, cases, seed=7):
    fs = [fx.uniform(f"parameters.x{i}", -fx.PI, fx.PI, "rad") for i in range(1, d + 1)]
    if method == "saltelli":
        n = cases // (d + 2)
        x = fx.saltelli_points(fs, n, seed)
    else:
        n = cases
        x = fx.mc_points(fs, n, seed)
    design = {"method": method, "size": n, "seed": seed, "points": len(x), "factors": fs}
    if method == "saltelli":
        design["base"] = "monte-carlo"
    ys, status = metrics(x, np.random.default_rng(seed))
    fx.write_folder(folder, design, x, ys, status=status,
                    units={"y1": "N", "y2": "J", "y3": "rad"})
    return folder, x


def write_histories(folder, x, samples):
    """A case file per case: time (samples over 1 s), a scalar signal s = x1 sin(2 pi t) + x2 t
    [m] and a vector v = (s, 2 s, x3) [N]."""
    t = np.linspace(0.0, 1.0, samples)
    for i, row in enumerate(x):
        s = row[0] * np.sin(2 * np.pi * t) + row[1] * t
        fx.write_case(folder, f"c{i:06d}", t,
                      {"s": s, "v": np.column_stack([s, 2 * s, np.full_like(t, row[2])])},
                      {"s": "m", "v": "N"})


def timed(folder, bootstrap, histories=False):
    env = dict(os.environ, MPLBACKEND="Agg")
    extra = ["--history", "s", "--history", "v"] if histories else []
    t0 = time.perf_counter()
    r = subprocess.run([sys.executable, "-m", "rodend.analyze", folder, "--bootstrap",
                        str(bootstrap), "--threshold", "y1=10", "--threshold", "y2=5",
                        "--threshold", "y3=5"] + extra, capture_output=True, text=True, env=env)
    wall = time.perf_counter() - t0
    if r.returncode:
        sys.exit(f"analysis failed: {r.stderr}")
    use = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = use.ru_utime + use.ru_stime - timed.cpu
    timed.cpu += cpu
    return f"{wall:.1f} s wall, {cpu:.1f} s CPU", use.ru_maxrss / 1024, r.stdout


timed.cpu = 0.0


def _ishigami_design(method, n, seed):
    fs = [fx.uniform(f"x{i}", -fx.PI, fx.PI) for i in (1, 2, 3)]
    x = fx.saltelli_points(fs, n, seed) if method == "saltelli" else fx.mc_points(fs, n, seed)
    return {"method": method, "size": n, "points": len(x), "factors": fs}, x


def widths(bootstrap):
    """Saltelli: mean interval widths and the coverage of the 6 published indices over seeds
    1..20; chaos on monte-carlo points: the smallest Q² and the largest index error over seeds
    1..5."""
    from rodend.analysis.run import analyze_arrays
    s1, st = np.array([0.3139, 0.4424, 0.0]), np.array([0.5576, 0.4424, 0.2437])
    print("| cases | saltelli N | mean 95 % width S1 | mean 95 % width ST | coverage of the "
          "6 indices (20 seeds) |")
    print("|---|---|---|---|---|")
    for n in (100, 250, 500, 1000, 2000, 4000):
        w1, wt, inside = [], [], 0
        for seed in range(1, 21):
            d, x = _ishigami_design("saltelli", n, seed)
            r = analyze_arrays(d, x, fx.ishigami(x), np.ones(len(x), bool), bootstrap=bootstrap,
                               seed=seed)["sobol"]
            w1.append(np.mean([b - a for a, b in r["first_order_interval"]]))
            wt.append(np.mean([b - a for a, b in r["total_interval"]]))
            for want, ivs in ((s1, r["first_order_interval"]), (st, r["total_interval"])):
                inside += sum(a <= v <= b for v, (a, b) in zip(want, ivs))
        print(f"| {5 * n} | {n} | {np.mean(w1):.3f} | {np.mean(wt):.3f} | "
              f"{inside / 120:.2f} |", flush=True)
    print("\n| cases (monte-carlo) | chaos terms | smallest Q² (LOO) | largest index error |")
    print("|---|---|---|---|")
    for n in (50, 100, 200, 500, 1000, 2000):
        q2, err, terms, withheld = [], [], [], 0
        for seed in range(1, 6):
            d, x = _ishigami_design("monte-carlo", n, seed)
            c = analyze_arrays(d, x, fx.ishigami(x), np.ones(n, bool), bootstrap=0)["chaos"]
            q2.append(c["q2_loo"])
            terms.append(c["terms"])
            if "first_order" not in c:  # withheld: the surrogate failed its validation
                withheld += 1
                continue
            err.append(max(np.max(np.abs(np.array(c["first_order"]) - s1)),
                           np.max(np.abs(np.array(c["total"]) - st))))
        largest = f"{np.max(err):.4f}" if err else "-"
        print(f"| {n} | {min(terms)}-{max(terms)} | {np.min(q2):.4f} | {largest}"
              + (f" ({withheld} of 5 withheld)" if withheld else "") + " |", flush=True)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--cases", type=int, default=10000)
    p.add_argument("--bootstrap", type=int, default=200)
    p.add_argument("--widths", action="store_true")
    p.add_argument("--keep", help="write the folders here and keep them")
    p.add_argument("--histories", type=int, default=0, metavar="SAMPLES",
                   help="also write a case file per case of the saltelli folder (a scalar and "
                        "a vector signal of SAMPLES samples) and time the bands with them")
    a = p.parse_args()
    if a.widths:
        widths(a.bootstrap)
        return
    root = a.keep or tempfile.mkdtemp(prefix="rodend-bench-analyze-")
    try:
        folders = {}
        for method, d in (("saltelli", 6), ("monte-carlo", 8)):
            folder, x = folders[method] = make(os.path.join(root, f"{method}-{d}"), method, d,
                                               a.cases)
            wall, peak, out = timed(folder, a.bootstrap)
            print(f"{method}, {d} factors, {a.cases} cases, 3 metrics, bootstrap {a.bootstrap}: "
                  f"{wall}, peak RSS {peak:.0f} MB (largest child so far), "
                  f"load average {os.getloadavg()[0]:.2f}", flush=True)
        if a.histories:
            folder, x = folders["saltelli"]
            write_histories(folder, x, a.histories)
            wall, peak, out = timed(folder, a.bootstrap, histories=True)
            print(f"saltelli again, with the bands of 2 signals (a scalar, a vector of 3) of "
                  f"{a.histories} samples from {len(x)} case files: {wall}, peak RSS "
                  f"{peak:.0f} MB (largest child so far), load average "
                  f"{os.getloadavg()[0]:.2f}", flush=True)
    finally:
        if not a.keep:
            shutil.rmtree(root, ignore_errors=True)


if __name__ == "__main__":
    main()
