#!/usr/bin/python3
"""Speed-up of a sweep on P cores or ranks, predicted from measured per-case costs
(bench/scaling_measure.py's JSON), checked against the runs this machine can do, extrapolated to
8, 64 and 1,000 cores/ranks for bench-32-like cases and the thesis cycle.

The model (every figure per case, from one-thread runs; docs/performance.md, "Scaling model"):
  t   CPU time of one case, writing included: (cpu_1t - fixed_cpu) / cases
  s   the part of t under the process's HDF5 lock (RODEND_LOCK_STATS=1, the holder's CPU): one
      process runs its locked sections one at a time (Amdahl), each MPI rank has its own lock
  L   the lock's time held once per run (the case-file template, the summary): the lock's time
      of the run of one case alone (--shard 1/N) less s; serial, outside t
  F   fixed cost of a run (start, load, resolve the cases: `rodend run --dry-run`)
  F_mpi  Open MPI's start and shut-down (mpirun around a run with nothing to do, minus plain)
  m   the manager's time per request, when requests queue (oversubscribed tiny cases): the
      manager hands out at most 1/m cases per second
  b   bytes of one case file; k = 3 metadata operations per case on the results file system
      (create the temporary, rename it, rank 0's lstat at the end)

  X(T)  cases per second of one process with T threads: a closed queue (exact mean-value
        analysis) of T threads, each computing t - s unlocked then queueing for the lock held s:
        X = T / t while the lock is seldom busy, 1 / s when it is always busy (Amdahl's limit)
  one process, T threads:  W = F + L + N / X(T)
  R ranks x T threads:     W = F + L + F_mpi + max(ceil(N / (R T)) T / X(T),
                                               N m, N k / M_fs, N b / B_fs)
where the first term is the cases of one rank (rounded up: the last round) at its rate; each
rank has its own lock. Speed-up = W(1 thread) / W.

M_fs (metadata operations per second) and B_fs (bytes per second) of a shared parallel file
system are not measured here: they are assumptions (--fs-metadata-ops, --fs-bandwidth), stated
with every prediction that they limit. Set them to your file system's figures.

  /usr/bin/python3 bench/scaling_model.py FIGURES.json [--lock-s-scale 0.05]
--lock-s-scale re-evaluates the model with the locked time per case scaled (e.g. after the HDF5
lock is cut by another change: measure again instead when you can).

The node model (--node NODE.json, from bench/scaling_node.py) adds what the model above leaves
out: the node's own slowdown with its cores busy, and the end of a run, when the last cases run
on few threads. Inputs:
  c_i   the cost of case i on one thread of an otherwise idle node (its integration and its
        file), in grid order
  F     the serial part of a run: start, study loading, resolving the cases (the summary is a
        few ms and counted in c_i)
  s(k)  the node's slowdown with k cores busy: how much longer a case takes while k - 1 other
        threads (or processes) run; s(1) = 1, interpolated linearly between measured points
        and constant past the last (with only s(N) known: linear in k, an assumption)
The run is simulated as OpenMP's schedule(dynamic, 1) runs it: each thread that is free takes the
next case in order (grid order, or longest first when asked), and every running case advances at
1/s(k) of its one-thread speed while k cases run. W(T) = F + the time the last case ends. The
HDF5 lock is left out (0.6 % of a one-thread run since the case files are written outside it).
  /usr/bin/python3 bench/scaling_model.py --node NODE.json --threads 8 16 \
      [--slowdown 16:1.30] [--one-thread-wall 9.58] [--measured 8:1.61 16:0.918] \
      [--order grid|longest|predicted --predictor KEY]
--slowdown replaces the measured s(k) (points k:s); --one-thread-wall scales the measured costs
and F together to another node's one-thread wall time (the relative costs assumed to carry over).
"""
import argparse
import json
import math


def per_case(st):
    """Per-case costs; the lock's time split into what each case holds it for (s) and what a run
    holds it for once (L: the case-file template, the summary), from the run of one case alone
    when the figures have it (older figures: all of it per case)."""
    n = st["cases"]
    t = (st["cpu_1t_s"] - st["fixed_cpu_s"]) / n
    lock = st["lock_cpu_s"]
    one = st.get("lock_one_case_cpu_s")
    s = lock / n if one is None or n < 2 else max(0.0, (lock - one) / (n - 1))
    L = max(0.0, lock - n * s)
    return {"n": n, "t": t - L / n, "s": min(s, t), "L": L, "F": st["fixed_wall_s"],
            "b": st["case_file_bytes"]}


def rate(c, threads):
    """Cases per second of one process of `threads` threads sharing one lock (mean-value
    analysis of a closed network: the lock a queue with service s, the rest a delay t - s)."""
    t, s = c["t"], c["s"]
    queue = 0.0
    x = 0.0
    for k in range(1, threads + 1):
        response = s * (1.0 + queue)
        x = k / (response + t - s)
        queue = x * response
    return x


def wall(c, n, ranks, threads, mpi, fs=None):
    """Predicted wall time [s] of n cases on `ranks` ranks x `threads` threads (mpi: the MPI
    runner's costs apply; fs: (metadata ops/s, bytes/s) of a shared file system, or None)."""
    if not mpi:  # one process: its lock is shared by every thread
        return c["F"] + c["L"] + n / rate(c, threads)
    per_rank = math.ceil(n / (ranks * threads)) * threads  # the last round included
    limits = [per_rank / rate(c, threads), n * mpi["m"]]
    if fs:
        limits += [n * 3 / fs[0], n * c["b"] / fs[1]]
    return c["F"] + c["L"] + mpi["F_mpi"] + max(limits)


def check(doc, c, mpi):
    """Predicted against measured for what runs here (bench-32, 2 cores)."""
    n = c["n"]
    cases = {"1 thread": (1, 1, None), "2 threads": (1, 2, None),
             "mpirun -np 1": (1, 1, None), "mpirun -np 2": (2, 1, mpi)}
    print(f"\nbench-32 on this machine ({doc.get('cpus')} cores; load average "
          f"{doc['load_average_before'][0]:.1f} before, {doc['load_average_after'][0]:.1f} after):")
    print(f"{'run':14} {'predicted [s]':>14} {'measured [s]':>13} {'error':>7}  measured CPU [s]")
    for name, run in doc["runs"].items():
        r, th, m = cases[name]
        p = wall(c, n, r, th, m)
        if name == "mpirun -np 1":  # the one-process code after MPI_Init
            p += mpi["F_mpi"]
        e = (p - run["wall_s"]) / run["wall_s"]
        print(f"{name:14} {p:14.3f} {run['wall_s']:13.3f} {e:+7.1%}  {run['cpu_s']:.3f}")
    base = doc["runs"]["1 thread"]["cpu_s"]
    for name in ("2 threads", "mpirun -np 2"):
        if name in doc["runs"]:
            print(f"  CPU of {name} over 1 thread: {doc['runs'][name]['cpu_s'] - base:+.3f} s")


def extrapolate(name, c, mpi, fs, per_core=100):
    print(f"\n{name}: t = {c['t'] * 1e3:.1f} ms per case, s = {c['s'] * 1e3:.1f} ms locked "
          f"({c['s'] / c['t']:.1%}), L = {c['L'] * 1e3:.1f} ms locked once per run, "
          f"b = {c['b'] / 1e6:.1f} MB per case file; "
          f"{per_core} cases per core")
    print(f"{'cores':>6} {'layout':26} {'speed-up':>9} {'with the file system':>21}  limited by")
    for cores, layouts in [(8, [(1, 8), (8, 1)]), (64, [(1, 64), (8, 8), (64, 1)]),
                           (1000, [(125, 8), (1000, 1)])]:
        n = per_core * cores
        w1 = wall(c, n, 1, 1, None)
        for ranks, threads in layouts:
            m = mpi if ranks > 1 else None
            w = wall(c, n, ranks, threads, m)
            wf = wall(c, n, ranks, threads, m, fs) if m else w
            lay = f"{threads} threads" if ranks == 1 else f"{ranks} ranks x {threads} thread(s)"
            why = limiter(c, n, ranks, threads, m, fs)
            print(f"{cores:6} {lay:26} {w1 / w:8.1f}x {w1 / wf:20.1f}x  {why}")


def limiter(c, n, ranks, threads, mpi, fs):
    t, s = c["t"], c["s"]
    locked = rate(c, threads) < 0.9 * threads / t  # the lock costs more than 10 %
    if not mpi:
        return "the HDF5 lock" if locked else "compute"
    compute = math.ceil(n / (ranks * threads)) * threads / rate(c, threads)
    terms = {"compute": compute, "the manager": n * mpi["m"],
             "file-system metadata": n * 3 / fs[0], "file-system bandwidth": n * c["b"] / fs[1]}
    top = max(terms, key=terms.get)
    if top == "compute" and locked:
        return "compute, each rank's HDF5 lock"
    return top


def slowdown_of(points):
    """s(k) from measured points {k: s}: s(1) = 1, linear between points, constant past the last."""
    pts = sorted({1: 1.0, **{int(k): float(v) for k, v in points.items()}}.items())

    def s(k):
        for (k0, s0), (k1, s1) in zip(pts, pts[1:]):
            if k <= k1:
                return s0 + (s1 - s0) * (k - k0) / (k1 - k0)
        return pts[-1][1]
    return s


def simulate(costs, threads, s):
    """Dynamic scheduling of `costs` (one-thread costs, in the order the threads take them) on
    `threads` threads, each running case advancing at 1/s(k) while k run. Returns (the time the
    last case ends, the CPU time of the cases, the time the first thread found no case left)."""
    n, nxt, t, cpu, idle_from = len(costs), 0, 0.0, 0.0, None
    running = []
    while nxt < n and len(running) < threads:
        running.append(costs[nxt])
        nxt += 1
    while running:
        k, m = len(running), min(running)
        dt = m * s(k)
        t += dt
        cpu += k * dt
        left = [r - m for r in running if r - m > 1e-12 * m]
        for _ in range(k - len(left)):  # each thread that finished takes the next case
            if nxt < n:
                left.append(costs[nxt])
                nxt += 1
            elif idle_from is None:
                idle_from = t
        running = left
    return t, cpu, t if idle_from is None else idle_from


def ordered(cases, order, predictor):
    """The one-thread costs in the order the threads take them."""
    if order == "grid":
        return [c["cost_s"] for c in cases]
    if order == "longest":
        return sorted((c["cost_s"] for c in cases), reverse=True)
    keyed = sorted(cases, key=lambda c: -abs(c[predictor]))  # stable: grid order among equals
    return [c["cost_s"] for c in keyed]


def node_model(a):
    with open(a.node) as f:
        doc = json.load(f)
    c = doc["costs"]
    costs_sum = sum(x["cost_s"] for x in c["cases"])
    serial = c["serial_cpu_s"]
    scale = 1.0 if a.one_thread_wall is None else a.one_thread_wall / (serial + costs_sum)
    cases = [dict(x, cost_s=x["cost_s"] * scale) for x in c["cases"]]
    serial *= scale
    if a.slowdown:
        points, source = dict(p.split(":") for p in a.slowdown), "given (--slowdown)"
    else:
        key = "wall_ratio" if a.slowdown_from == "wall" else "cpu_ratio"
        points = {r["k"]: r[key] for r in doc["slowdown"]}
        source = f"measured ({key}, load average {doc['load_average_before'][0]:.1f})"
    s = slowdown_of(points)
    measured = dict((int(k), float(v)) for k, v in (p.split(":") for p in a.measured or []))
    costs_one = [x["cost_s"] for x in cases]
    mean = costs_sum * scale / len(cases)
    print(f"{doc['study']} {' '.join(doc['set'])}: {len(cases)} cases, mean cost {mean:.4f} s, "
          f"max/mean {max(costs_one) / mean:.2f}, min/mean {min(costs_one) / mean:.2f}; "
          f"serial F = {serial:.3f} s; one thread {serial + mean * len(cases):.3f} s "
          f"(scaled x{scale:.3f}); s(k) {source}: "
          + ", ".join(f"s({k})={v}" for k, v in sorted(points.items(), key=lambda p: int(p[0]))))
    print(f"{'threads':>7} {'order':9} {'s(T)':>6} {'predicted [s]':>14} {'CPU [s]':>8} "
          f"{'tail [s]':>8} {'measured [s]':>13} {'error':>7}")
    for threads in a.threads:
        for order in a.order:
            end, cpu, idle = simulate(ordered(cases, order, a.predictor), threads, s)
            w = serial + end
            meas = measured.get(threads)
            err = f"{(w - meas) / meas:+7.1%}" if meas and order == "grid" else ""
            shown = f"{meas:13.3f}" if meas and order == "grid" else f"{'':13}"
            print(f"{threads:7d} {order:9} {s(threads):6.3f} {w:14.3f} {serial + cpu:8.2f} "
                  f"{end - idle:8.3f} {shown} {err}")


def main():
    ap = argparse.ArgumentParser(description="the lock/manager/file-system model on FIGURES "
                                 "(bench/scaling_measure.py), or with --node the node model")
    ap.add_argument("figures", nargs="?")
    ap.add_argument("--node", help="bench/scaling_node.py's JSON: the node model")
    ap.add_argument("--fs-metadata-ops", type=float, default=20000.0,
                    help="metadata operations per second of the shared file system (assumed)")
    ap.add_argument("--fs-bandwidth", type=float, default=20e9,
                    help="write bandwidth of the shared file system [bytes/s] (assumed)")
    ap.add_argument("--lock-s-scale", type=float, default=1.0)
    ap.add_argument("--threads", type=int, nargs="+", default=[1, 2, 4, 8, 16])
    ap.add_argument("--slowdown", nargs="+", help="k:s points replacing the measured s(k)")
    ap.add_argument("--slowdown-from", choices=["cpu", "wall"], default="cpu")
    ap.add_argument("--one-thread-wall", type=float,
                    help="scale costs and F to this one-thread wall time [s] (another node)")
    ap.add_argument("--measured", nargs="+", help="threads:wall [s] to compare with")
    ap.add_argument("--order", nargs="+", choices=["grid", "longest", "predicted"],
                    default=["grid"])
    ap.add_argument("--predictor", help="case column whose magnitude ranks the cases "
                    "(--order predicted), e.g. parameters.hinge.constant_moment")
    a = ap.parse_args()
    if a.node:
        return node_model(a)
    if not a.figures:
        ap.error("FIGURES or --node is required")
    with open(a.figures) as f:
        doc = json.load(f)
    tiny = max(doc["dispatch_tiny"], key=lambda d: d["requests"] / max(d["wall_s"], 1e-9))
    mpi = {"F_mpi": max(doc["mpi_fixed_wall_s"], 0.0),
           "m": max(d["serve_wall_us"] for d in doc["dispatch_tiny"]) * 1e-6}
    b32, thesis = per_case(doc["bench-32"]), per_case(doc["thesis-cycle"])
    for c in (b32, thesis):
        c["s"] *= a.lock_s_scale
    print(f"measured at git {doc['git']}: F = {b32['F']:.3f} s, F_mpi = {mpi['F_mpi']:.3f} s, "
          f"manager m = {mpi['m'] * 1e6:.0f} us per request (max over -np "
          f"{', '.join(str(d['ranks']) for d in doc['dispatch_tiny'])} on tiny cases; "
          f"{tiny['bytes_per_request']:.0f} bytes per request there, "
          f"{doc['dispatch_bench-32']['bytes_per_request']:.0f} on bench-32)")
    check(doc, b32, mpi)
    fs = (a.fs_metadata_ops, a.fs_bandwidth)
    print(f"\nshared file system assumed: {fs[0]:.0f} metadata operations/s, "
          f"{fs[1] / 1e9:.0f} GB/s (not measured: set yours with --fs-metadata-ops, --fs-bandwidth)")
    extrapolate("bench-32-like cases", b32, mpi, fs)
    extrapolate("thesis-cycle cases", thesis, mpi, fs)


if __name__ == "__main__":
    main()
