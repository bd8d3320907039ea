#!/usr/bin/python3
"""Measures what bench/scaling_model.py's node model (`--node`) needs: the node's own slowdown
with k cores busy, and the costs of a study's cases. Writes one JSON document (stdout, or --out).

1. The node's slowdown s(k): k identical one-thread processes started at once, each running the
   same shard of the study (`rodend run STUDY --shard 1/SHARDS -j 1`, every process into its own
   results root, so they share nothing but the machine), against one process alone; for
   k = 1 .. --max-procs (default: the core count), --repeats rounds, the rounds of every k
   interleaved. Per round and k: the mean over the processes of each one's wall time (start to
   exit) and CPU time (user + sys, from wait4). s(k) is the median over rounds of that mean over
   k = 1's. On a quiet node the wall ratio is the slowdown; on a node other jobs share, wall time
   includes the waits for a core, and the CPU ratio is the measure (what the node costs a busy
   core: clock, caches, memory bandwidth).
2. The case costs, by default from CPU times, which barely depend on what else the machine
   runs: the CPU time C of one one-thread run of the whole study (or --total-cpu of one you
   already have), F that of `rodend run --dry-run` (start, study loading, resolving every case:
   the serial part), and every case run by itself (`--shard K/n` for K = 1 .. n, n the study's
   case count: shard K is the case of index K - 1; --workers at a time), its process's CPU time
   a_i (user + sys, from wait4). A process of one case also pays a start, HDF5's and the results
   folder's set-up, o each: o = (sum a_i - (C - F)) / n, and case i costs a_i - o, so that the
   costs add up to the whole run's C - F. Per case: `cost_s`, its rhs_calls and the study's
   factor columns (`parameters.*`, from the dry run's table of cases).
   With --from-summary instead: one one-thread run of the whole study (`rodend run STUDY -j 1`), or the
   summary of one you already have (--summary FOLDER, with that run's --total-wall and --total-cpu).
   Per case in grid order (case_index): `wall_time_s` from the summary, its rhs_calls, and the
   study's factor columns (`parameters.*`). `wall_time_s` covers the integration only; writing
   the case file comes after it. On a shared node a case's wall time includes its waits for a
   core, so its integration's CPU is estimated as wall_time_s x (process CPU / process wall)
   (the load assumed even over the run). The serial part F is the CPU time of
   `rodend run --dry-run` (start, study loading, resolving every case); the rest of the process's
   CPU, less F and the integrations, is spread evenly over the cases as the writing of their
   files (every case of a study records the same signals at the same samples; the summary, a few
   ms, is counted there too). A case's `cost_s` = its integration + that write share. On a
   node whose load changes during the run this share drifts: measured at load average 14-17,
   tolerance.json's cost per right-hand-side call fell by half from its first cases to its last.

  /usr/bin/python3 bench/scaling_node.py --study studies/bench-256.json --set time.end=1.2 \\
      --shards 16 --max-procs 2 --repeats 3 --out node.json
  /usr/bin/python3 bench/scaling_model.py --node node.json --threads 1 2
"""
import argparse
import glob
import json
import os
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


def run_base(a, root):
    cmd = [RODEND, "run", a.study, "-j", "1", "-q", "--results-root", root]
    for s in a.set or []:
        cmd += ["--set", s]
    return cmd


def together(a, tmp, k):
    """k identical one-thread shard runs started at once: (mean wall, mean CPU) per process."""
    procs = {}
    t0 = time.monotonic()
    for p in range(k):
        root = os.path.join(tmp, f"p{p}")
        shutil.rmtree(root, ignore_errors=True)
        cmd = run_base(a, root) + ["--shard", f"1/{a.shards}"]
        proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        procs[proc.pid] = (cmd, proc)  # the Popen kept: subprocess reaps dropped ones
    walls, cpus = [], []
    while procs:
        pid, status, ru = os.wait4(-1, 0)
        if pid not in procs:
            continue
        walls.append(time.monotonic() - t0)
        cpus.append(ru.ru_utime + ru.ru_stime)
        procs[pid][1].returncode = os.waitstatus_to_exitcode(status)
        if procs[pid][1].returncode not in (0, 1):
            sys.exit(f"{' '.join(procs[pid][0])} exited {status}")
        del procs[pid]
    return statistics.mean(walls), statistics.mean(cpus)


def slowdown(a, tmp):
    ks = list(range(1, a.max_procs + 1))
    rounds = {k: [] for k in ks}
    for _ in range(a.repeats):
        for k in ks:
            rounds[k].append(together(a, tmp, k))
    one_w = statistics.median(w for w, _ in rounds[1])
    one_c = statistics.median(c for _, c in rounds[1])
    return [{"k": k, "wall_s": [w for w, _ in rounds[k]], "cpu_s": [c for _, c in rounds[k]],
             "wall_ratio": statistics.median(w for w, _ in rounds[k]) / one_w,
             "cpu_ratio": statistics.median(c for _, c in rounds[k]) / one_c} for k in ks]


def one_thread_run(a, tmp):
    """The whole study on one thread: (results folder, process wall, process CPU)."""
    root = os.path.join(tmp, "costs")
    shutil.rmtree(root, ignore_errors=True)
    before = os.times()
    t0 = time.monotonic()
    r = subprocess.run(run_base(a, root), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                       text=True)
    wall = time.monotonic() - t0
    after = os.times()
    if r.returncode not in (0, 1):
        sys.exit(f"the one-thread run exited {r.returncode}: {r.stderr}")
    cpu = (after.children_user - before.children_user) + (after.children_system - before.children_system)
    return os.path.dirname(glob.glob(os.path.join(root, "*", "summary.h5"))[0]), wall, cpu


def dry_run_cpu(a):
    """CPU time [s] of `rodend run --dry-run`: the serial start of a run."""
    before = os.times()
    cmd = [RODEND, "run", a.study, "--dry-run"] + [x for s in a.set or [] for x in ("--set", s)]
    subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
    after = os.times()
    return (after.children_user - before.children_user) + (after.children_system - before.children_system)


def alone(a, tmp, k, n):
    """Starts case k - 1 alone (`--shard k/n`) into its own results root."""
    root = os.path.join(tmp, f"case{k}")
    cmd = run_base(a, root) + ["--shard", f"{k}/{n}"]
    return subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL), root


def case_table(a):
    """The study's cases (`rodend run --dry-run`'s table): index -> {column: value}."""
    cmd = [RODEND, "run", a.study, "--dry-run"] + [x for s in a.set or [] for x in ("--set", s)]
    out = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout.splitlines()
    head = next(i for i, line in enumerate(out) if line.startswith("case\t") or
                line.startswith("index\t"))
    cols = out[head].split("\t")
    rows = [dict(zip(cols, line.split("\t"))) for line in out[head + 1:] if "\t" in line]
    return cols, rows


def costs_alone(a, tmp, whole_cpu):
    """Each case's CPU time run alone, less a one-case process's overhead (see the module's
    docstring); whole_cpu: the CPU time of a one-thread run of the whole study."""
    serial = dry_run_cpu(a)
    cols, rows = case_table(a)
    n = len(rows)
    factors = [c for c in cols if c.startswith("parameters.")]
    cpu, running, nxt = {}, {}, 1
    while nxt <= n or running:
        while nxt <= n and len(running) < a.workers:
            proc, root = alone(a, tmp, nxt, n)  # the Popen kept: subprocess reaps dropped ones
            running[proc.pid] = (nxt, root, proc)
            nxt += 1
        pid, status, ru = os.wait4(-1, 0)
        if pid not in running:
            continue
        k, root, proc = running.pop(pid)
        proc.returncode = os.waitstatus_to_exitcode(status)
        if os.waitstatus_to_exitcode(status) not in (0, 1):
            sys.exit(f"case {k - 1} alone exited {status}")
        cpu[k - 1] = ru.ru_utime + ru.ru_stime
        rhs = read_rhs_calls(root)
        shutil.rmtree(root, ignore_errors=True)
        cpu[k - 1] = (cpu[k - 1], rhs)
    overhead = (sum(cpu[i][0] for i in range(n)) - (whole_cpu - serial)) / n
    cases = [{"case_index": i, "cpu_alone_s": cpu[i][0], "cost_s": cpu[i][0] - overhead,
              "rhs_calls": cpu[i][1], **{c: float(rows[i][c]) for c in factors}}
             for i in range(n)]
    return {"method": "each case alone (CPU) less a one-case process's overhead",
            "process_cpu_s": whole_cpu, "serial_cpu_s": serial,
            "overhead_per_process_cpu_s": overhead, "factors": factors, "cases": cases}


def read_rhs_calls(root):
    """rhs_calls of the one case file under root (read by the package's reader, which checks
    it first; None without h5py)."""
    try:
        from rodend.casefiles import CaseFiles
    except ImportError:
        return None
    files = glob.glob(os.path.join(root, "*", "cases", "*.h5"))
    if len(files) != 1:
        return None
    folder = os.path.dirname(os.path.dirname(files[0]))
    with CaseFiles(folder, [os.path.basename(files[0])[:-3]]).open(0) as f:
        v = f.attrs.get("rhs_calls")
    return None if v is None else int(v)


def costs(a, summary, wall, cpu):
    if os.path.isfile(summary):  # summary.h5 or summary.csv named: its folder
        summary = os.path.dirname(os.path.abspath(summary))
    rows = sorted(summary_rows(summary), key=lambda r: int(r["case_index"]))
    share = cpu / wall
    serial = dry_run_cpu(a)
    integration = sum(float(r["wall_time_s"]) for r in rows) * share
    write = (cpu - serial - integration) / len(rows)
    factors = [c for c in rows[0] if c.startswith("parameters.")]
    cases = [{"case_index": int(r["case_index"]), "status": r["status"],
              "wall_time_s": float(r["wall_time_s"]),
              "cost_s": float(r["wall_time_s"]) * share + write,
              "rhs_calls": int(r["rhs_calls"]), **{c: float(r[c]) for c in factors}} for r in rows]
    return {"process_wall_s": wall, "process_cpu_s": cpu, "cpu_share": share,
            "serial_cpu_s": serial, "write_cpu_s_per_case": write, "factors": factors,
            "cases": cases}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--study", required=True)
    ap.add_argument("--set", action="append", help="passed to `rodend run --set` (repeatable)")
    ap.add_argument("--shards", type=int, default=16,
                    help="the slowdown's processes each run shard 1 of this many")
    ap.add_argument("--max-procs", type=int, default=os.cpu_count())
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--no-slowdown", action="store_true", help="case costs only")
    ap.add_argument("--no-costs", action="store_true", help="the slowdown only")
    ap.add_argument("--workers", type=int, default=1, help="cases run alone at a time")
    ap.add_argument("--from-summary", action="store_true",
                    help="the costs from one one-thread run's summary (quiet nodes only; "
                    "--summary: one you already have, with --total-wall and --total-cpu)")
    ap.add_argument("--summary", help="the results folder (or its summary.h5) of a one-thread "
                    "run you already have")
    ap.add_argument("--total-wall", type=float, help="that run's process wall time [s]")
    ap.add_argument("--total-cpu", type=float, help="that run's process CPU time [s]")
    ap.add_argument("--out")
    a = ap.parse_args()
    doc = {"study": a.study, "set": a.set or [], "cpus": os.cpu_count(),
           "load_average_before": os.getloadavg(),
           "git": subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"],
                                 capture_output=True, text=True).stdout.strip()}
    with tempfile.TemporaryDirectory(prefix="rodend-node-") as tmp:
        if not a.no_slowdown:
            doc["shards"] = a.shards
            doc["slowdown"] = slowdown(a, tmp)
        if not a.no_costs:
            if a.from_summary:
                doc["costs"] = (costs(a, a.summary, a.total_wall, a.total_cpu) if a.summary
                                else costs(a, *one_thread_run(a, tmp)))
            else:
                whole = a.total_cpu if a.total_cpu else one_thread_run(a, tmp)[2]
                doc["costs"] = costs_alone(a, tmp, whole)
    doc["load_average_after"] = os.getloadavg()
    text = json.dumps(doc, indent=1)
    if a.out:
        with open(a.out, "w") as f:
            f.write(text + "\n")
    else:
        print(text)


if __name__ == "__main__":
    main()
