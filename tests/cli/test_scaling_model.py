#!/usr/bin/python3
"""bench/scaling_model.py's node model: its simulation of dynamic scheduling against closed forms.

- n equal cases of cost c on T threads, s(k) busy-dependent: every full round of T cases takes
  c s(T), the last round of r = n mod T cases c s(r); the first thread finds no case left after
  the full rounds, so the tail is c s(r); the cases' CPU is the sum of k c s(k) over the rounds.
- one long case L among short ones (s = 1): last in grid order it starts when the short ones are
  done and ends at their rounds + L; taken first (longest first) the run ends at L when the others
  fit on the remaining threads.
- s(k) from measured points: s(1) = 1, linear between points, constant past the last.
- the command line on a small node figures file: runs and prints the predictions.
Costs are binary fractions (0.5, 0.25), so the sums are exact and the tolerances round-off only.
"""
import json
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
BENCH = os.path.join(os.path.dirname(os.path.dirname(HERE)), "bench")
sys.path.insert(0, BENCH)
import scaling_model as sm  # noqa: E402

FAILURES = []


def close(name, got, want, rel=1e-12):
    if abs(got - want) > rel * abs(want):
        FAILURES.append(f"{name}: {got!r}, expected {want!r}")


def main():
    s = sm.slowdown_of({16: 1.3})
    close("s(1)", s(1), 1.0)
    close("s(8) linear", s(8), 1.0 + 0.3 * 7 / 15)
    close("s(32) constant past the last point", s(32), 1.3)
    s2 = sm.slowdown_of({"2": 1.5, "4": 1.7})
    close("s(3) between points", s2(3), 1.6)

    c, n, T = 0.5, 37, 8
    lin = sm.slowdown_of({8: 1.35})  # s(k) = 1 + 0.05 (k - 1)
    end, cpu, idle = sm.simulate([c] * n, T, lin)
    full, r = divmod(n, T)
    close("equal costs: end", end, full * c * lin(T) + c * lin(r))
    close("equal costs: first idle thread", idle, full * c * lin(T))
    close("equal costs: CPU", cpu, full * T * c * lin(T) + r * c * lin(r))
    end, _, idle = sm.simulate([c] * 32, T, lin)  # no partial round: no tail
    close("equal costs, n = 4T: end", end, 4 * c * lin(T))
    if end != idle:
        FAILURES.append(f"equal costs, n = 4T: tail {end - idle!r}, expected none")

    one = sm.slowdown_of({})
    short, L = [0.25] * 20, 10.0
    end, _, idle = sm.simulate(short + [L], 4, one)
    close("long case last in grid order: end", end, 20 * 0.25 / 4 + L)
    close("long case last: tail is its cost", end - idle, L)
    cases = [{"cost_s": x, "h": x} for x in short + [L]]
    end, _, _ = sm.simulate(sm.ordered(cases, "longest", None), 4, one)
    close("long case first: end", end, L)
    end, _, _ = sm.simulate(sm.ordered(cases, "predicted", "h"), 4, one)
    close("long case first by its predictor: end", end, L)

    with tempfile.TemporaryDirectory() as tmp:
        doc = {"study": "x.json", "set": [], "load_average_before": [0, 0, 0],
               "slowdown": [{"k": 1, "cpu_ratio": 1.0, "wall_ratio": 1.0},
                            {"k": 2, "cpu_ratio": 1.2, "wall_ratio": 1.3}],
               "costs": {"serial_cpu_s": 0.25,
                         "cases": [{"cost_s": 0.5, "h": 1.0} for _ in range(5)]}}
        path = os.path.join(tmp, "node.json")
        with open(path, "w") as f:
            json.dump(doc, f)
        r = subprocess.run([sys.executable, os.path.join(BENCH, "scaling_model.py"), "--node", path,
                            "--threads", "2", "--measured", "2:2.0"], capture_output=True, text=True)
        # 5 cases of 0.5 s on 2 threads, s(2) = 1.2: 2 rounds at 0.6 s, the last case alone 0.5 s
        want = f"{0.25 + 2 * 0.6 + 0.5:14.3f}"
        if r.returncode != 0 or want not in r.stdout:
            FAILURES.append(f"command line: exit {r.returncode}, no '{want.strip()}' in:\n"
                            f"{r.stdout}{r.stderr}")
    for f in FAILURES:
        print("FAIL", f)
    print("cli.scaling_model:", "FAILED" if FAILURES else "ok")
    return 1 if FAILURES else 0


if __name__ == "__main__":
    sys.exit(main())
