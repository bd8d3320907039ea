#!/usr/bin/python3
"""Measures the per-case costs that bench/scaling_model.py turns into speed-up predictions, and
the runs it checks them against. Writes one JSON document (stdout, or --out FILE).

Per study (bench-32; the thesis cycle: bench/scaling-thesis.json), from one-thread runs (medians
of REPEATS runs, taken before the checked configurations and apart from them):
  - cpu_1t_s, wall_1t_s: the whole process (user + sys of the process and its children);
  - fixed_cpu_s, fixed_wall_s: `rodend run --dry-run` (start, load, resolve every case): the
    part that does not grow with the cases run;
  - lock_cpu_s, lock_wall_s, lock_count: the HDF5 lock, the serial section of one process
    (RODEND_LOCK_STATS=1: the holder's CPU time and the wall time it was held);
  - lock_one_case_cpu_s: the same for the first case alone (`--shard 1/N`), which separates what
    a run holds the lock for once (template, summary) from what each case holds it for;
  - case_file_bytes: the mean size of a case file (what each case writes to the file system).
MPI (when mpirun is on PATH and the build has MPI), from RODEND_MPI_STATS=1 runs:
  - the manager's cost per request (wall, CPU), bytes per request, the workers' wait;
  - the same on the 400 cases of a few ms of bench/scaling-tiny.json with oversubscribed ranks
    (-np 2, 4, 6 on this machine): the manager's throughput when requests queue;
  - mpi_fixed_wall_s / mpi_fixed_cpu_s: `mpirun -np 2` around a run with nothing to do, minus
    the same plain run (start-up and shut-down of Open MPI).
Checked configurations (bench-32, REPEATS interleaved rounds, fresh folder, `sync` first):
  1 thread, 2 threads, `mpirun -np 1`, `mpirun -np 2`: median wall and CPU time.

  /usr/bin/python3 bench/scaling_measure.py --out /tmp/scaling.json   # REPEATS=3 by default
  /usr/bin/python3 bench/scaling_model.py /tmp/scaling.json
"""
import argparse
import glob
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

# the package rodend beside bench/ (its reader needs no compiled module), else an installed one
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "python"))
from rodend import summary_rows  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
RODEND = os.environ.get("RODEND", os.path.join(ROOT, "build", "rodend"))
MPIRUN = shutil.which("mpirun")
ENV = {k: v for k, v in os.environ.items() if not k.startswith(("OMPI_", "PMIX_", "PMI_"))}
MPI_ENV = dict(ENV, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")


def timed(cmd, env, extra_env=None):
    """Runs cmd; returns (wall s, CPU s of the process tree, stderr)."""
    env = dict(env, **(extra_env or {}))
    subprocess.run(["sync"])
    before = os.times()
    t0 = time.monotonic()
    r = subprocess.run(cmd, env=env, capture_output=True, text=True)
    wall = time.monotonic() - t0
    after = os.times()
    if r.returncode not in (0, 1):
        sys.exit(f"{' '.join(cmd)} exited {r.returncode}: {r.stderr}")
    cpu = (after.children_user - before.children_user) + (after.children_system - before.children_system)
    return wall, cpu, r.stderr


def run_cmd(study, root, how):
    base = [RODEND, "run", study, "--results-root", root, "-q"]
    if how == "1 thread":
        return base + ["--threads", "1"], ENV
    if how == "2 threads":
        return base + ["--threads", "2"], ENV
    n = how.split()[-1]
    return [MPIRUN, "--oversubscribe", "-np", n] + base + ["--threads", "1"], MPI_ENV


LOCK_RE = r"HDF5 lock held (\d+) times, ([\d.]+) s wall, ([\d.]+) s CPU"


def lock_of_one_case(study, tmp, cases):
    """The holder's CPU time of the HDF5 lock in a run of the study's first case alone
    (`--shard 1/N`): what a run holds the lock for once (the case-file template, the summary,
    HDF5's start) plus one case's share."""
    root = os.path.join(tmp, "shard")
    shutil.rmtree(root, ignore_errors=True)
    cmd = run_cmd(study, root, "1 thread")[0] + ["--shard", f"1/{cases}"]
    _, _, err = timed(cmd, ENV, {"RODEND_LOCK_STATS": "1"})
    return float(re.search(LOCK_RE, err).group(3))


def per_study(study, tmp, repeats):
    """One-thread figures of a study: wall and CPU time the medians of `repeats` runs (the
    model's inputs; one run's noise would move every prediction alike), the lock's from the
    last."""
    root = os.path.join(tmp, "one")
    walls, cpus = [], []
    for _ in range(max(1, repeats)):
        shutil.rmtree(root, ignore_errors=True)
        w, c, err = timed(run_cmd(study, root, "1 thread")[0], ENV, {"RODEND_LOCK_STATS": "1"})
        walls.append(w)
        cpus.append(c)
    wall, cpu = statistics.median(walls), statistics.median(cpus)
    m = re.search(LOCK_RE, err)
    files = glob.glob(os.path.join(root, "*", "cases", "*.h5"))
    rows = summary_rows(os.path.dirname(glob.glob(os.path.join(root, "*", "summary.h5"))[0]))
    fw, fc, _ = timed([RODEND, "run", study, "--dry-run"], ENV)
    return {
        "cases": len(rows), "wall_1t_s": wall, "cpu_1t_s": cpu,
        "integration_s": sum(float(r["wall_time_s"]) for r in rows),
        "fixed_wall_s": fw, "fixed_cpu_s": fc,
        "lock_count": int(m.group(1)), "lock_wall_s": float(m.group(2)), "lock_cpu_s": float(m.group(3)),
        "lock_one_case_cpu_s": lock_of_one_case(study, tmp, len(rows)),
        "case_file_bytes": statistics.mean(os.path.getsize(f) for f in files),
    }


def dispatch(study, tmp, ranks):
    root = os.path.join(tmp, "d")
    shutil.rmtree(root, ignore_errors=True)
    cmd, env = run_cmd(study, root, f"mpirun -np {ranks}")
    wall, cpu, err = timed(cmd, env, {"RODEND_MPI_STATS": "1"})
    m = re.search(r"(\d+) requests served, ([\d.]+) us wall and ([\d.]+) us CPU of the manager each, "
                  r"(\d+) bytes each .*?manager thread ([\d.]+) s CPU in all, (\d+) idle polls; "
                  r"a worker waited ([\d.]+) us per request", err, re.S)
    if m is None:
        sys.exit(f"no dispatch figures in: {err}")
    keys = ["requests", "serve_wall_us", "serve_cpu_us", "bytes_per_request", "manager_cpu_s",
            "idle_polls", "worker_wait_us"]
    out = {k: float(v) for k, v in zip(keys, m.groups())}
    out.update(ranks=ranks, wall_s=wall, cpu_s=cpu)
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out")
    ap.add_argument("--repeats", type=int, default=int(os.environ.get("REPEATS", "3")))
    a = ap.parse_args()
    bench32 = os.path.join(ROOT, "studies", "bench-32.json")
    thesis = os.path.join(HERE, "scaling-thesis.json")
    tiny = os.path.join(HERE, "scaling-tiny.json")
    doc = {"load_average_before": os.getloadavg(), "cpus": os.cpu_count(),
           "git": subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"],
                                 capture_output=True, text=True).stdout.strip()}
    with tempfile.TemporaryDirectory() as tmp:
        doc["bench-32"] = per_study(bench32, tmp, a.repeats)
        doc["thesis-cycle"] = per_study(thesis, tmp, a.repeats)
        configs = ["1 thread", "2 threads"] + (["mpirun -np 1", "mpirun -np 2"] if MPIRUN else [])
        runs = {c: [] for c in configs}
        for _ in range(a.repeats):
            for c in configs:
                root = os.path.join(tmp, "c")
                shutil.rmtree(root, ignore_errors=True)
                cmd, env = run_cmd(bench32, root, c)
                runs[c].append(timed(cmd, env)[:2])
        doc["runs"] = {c: {"wall_s": statistics.median(w for w, _ in v),
                           "cpu_s": statistics.median(u for _, u in v),
                           "walls": [w for w, _ in v]} for c, v in runs.items()}
        if MPIRUN:
            doc["dispatch_bench-32"] = dispatch(bench32, tmp, 2)
            doc["dispatch_tiny"] = [dispatch(tiny, tmp, n) for n in (2, 4, 6)]
            done = os.path.join(tmp, "done")  # a complete study: the run has nothing to do
            timed(run_cmd(tiny, done, "1 thread")[0], ENV)
            pw, pc, _ = timed(run_cmd(tiny, done, "1 thread")[0], ENV)
            cmd, env = run_cmd(tiny, done, "mpirun -np 2")
            mw, mc, _ = timed(cmd, env)
            doc["mpi_fixed_wall_s"], doc["mpi_fixed_cpu_s"] = mw - pw, mc - pc
    doc["load_average_after"] = os.getloadavg()
    text = json.dumps(doc, indent=1)
    if a.out:
        with open(a.out, "w") as f:
            f.write(text + "\n")
    print(text)


if __name__ == "__main__":
    main()
