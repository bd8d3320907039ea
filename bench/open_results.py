"""Benchmark (not a test): rodend.open_results on a 10,000-case study.

Builds, or resumes, a 100 x 100 product grid over the gravity-drop scene (contact clearance x
restitution) with a tiny end time (2 ms sampled every 0.1 ms: 21 samples a case) through
rodend.run_study, then measures in a fresh Python process each:
  import     `import rodend` (numpy, the extension)
  open       `rodend.open_results(folder)` (summary.h5 and study.json; no case file)
  histories  `res.histories` (the lazy Dataset over both grid axes and time)
  one case   `res.histories["eccentricity"].isel(...)` of one grid point, loaded
  case()     `res.case(5000)`: one case's Dataset
and prints the wall time of each step and the process's peak RSS after it. The goal: open
within 5 s and peak RSS under 300 MB.

  PYTHONPATH=python RODEND_BUILD_DIR=build /usr/bin/python3 bench/open_results.py \
      [--folder /tmp/rodend-bench-open] [--side 100] [--threads 2] [--json out.json]

Building the study takes a few minutes on 2 cores (once: a second run finds it complete).
"""
import argparse
import json
import os
import subprocess
import sys
import time

MEASURE = r"""
import json, resource, sys, time
def rss_mb():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # kB on Linux
out = {}
t = time.perf_counter()
import rodend
out["import"] = (time.perf_counter() - t, rss_mb())
t = time.perf_counter()
res = rodend.open_results(sys.argv[1])
out["open"] = (time.perf_counter() - t, rss_mb())
t = time.perf_counter()
h = res.histories
out["histories"] = (time.perf_counter() - t, rss_mb())
t = time.perf_counter()
dims = [d for d in h["eccentricity"].dims if d != "time"]
one = h["eccentricity"].isel({d: h.sizes[d] // 2 for d in dims}).load()
out["one case"] = (time.perf_counter() - t, rss_mb())
t = time.perf_counter()
c = res.case(len(res.summary) // 2)
out["case()"] = (time.perf_counter() - t, rss_mb())
out["cases"] = len(res.summary)
out["dims"] = dict(h.sizes)
out["one case max eccentricity [m]"] = float(one.max())
print(json.dumps(out))
"""


def build(folder, side, threads):
    import rodend
    root, name = os.path.split(os.path.abspath(folder))
    study = {"name": name, "scene": "gravity-drop",
             "time": {"end": 2e-3, "sample_interval": 1e-4},
             "signals": ["eccentricity", "ball_position", "contact_force"],
             "grid": [{"key": "parameters.contact.clearance", "linspace": [1e-4, 5e-4, side]},
                      {"key": "parameters.contact.restitution", "linspace": [0.3, 0.9, side]}]}
    t = time.perf_counter()
    rc, out = rodend.run_study(study, threads=threads, results_root=root)
    if rc != 0:
        sys.exit(f"building the study failed (exit {rc})")
    return out, time.perf_counter() - t


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--folder", default="/tmp/rodend-bench-open")
    ap.add_argument("--side", type=int, default=100, help="grid points per axis (side^2 cases)")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--json", help="write the figures to this file")
    a = ap.parse_args()
    folder, built = build(a.folder, a.side, a.threads)
    print(f"study {folder}: built or resumed in {built:.1f} s", file=sys.stderr)
    r = subprocess.run([sys.executable, "-c", MEASURE, folder], capture_output=True, text=True,
                       env=os.environ)
    if r.returncode != 0:
        sys.exit(r.stderr)
    out = json.loads(r.stdout)
    print(f"{out['cases']} cases, dims {out['dims']}")
    print(f"{'step':<10} {'wall [s]':>9} {'peak RSS [MB]':>14}")
    for step in ("import", "open", "histories", "one case", "case()"):
        wall, rss = out[step]
        print(f"{step:<10} {wall:9.3f} {rss:14.1f}")
    ok = out["open"][0] <= 5.0 and max(out[s][1] for s in ("open", "one case")) < 300
    print(f"goal (open within 5 s, peak RSS under 300 MB): {'met' if ok else 'NOT met'}; load "
          f"average {os.getloadavg()[0]:.2f}")
    if a.json:
        with open(a.json, "w") as fh:
            json.dump(out, fh, indent=1)


if __name__ == "__main__":
    main()
