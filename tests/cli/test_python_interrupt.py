#!/usr/bin/env python3
"""Ctrl-C interrupts rodend from Python (issue 35 item 2): SIGINT sent to a Python process inside
`rodend.run_case` raises KeyboardInterrupt within 2 s (the case in flight stops at its next
sample; nothing is written), and inside `rodend.run_study` raises KeyboardInterrupt once the
cases in flight are finished and written, after which the same call resumes the study to every
case ok."""
import json
import os
import signal
import subprocess
import sys
import tempfile
import time

from common import check, finish

CHILD = r"""
import json, sys, rodend
what, root = sys.argv[1], sys.argv[2]
print("started", flush=True)
try:
    if what == "case":
        # rk4 at 1 us over 100 s: 1e8 steps, minutes on any machine, so SIGINT finds it running
        rodend.run_case("gravity-drop", {}, time={"end": 100.0, "sample_interval": 0.01},
                        integrator={"method": "rk4", "step": 1e-6, "max_steps": 10**12},
                        write=root + "/case.h5")
    else:
        rodend.run_study(root + "/study.json", results_root=root)
    print("returned", flush=True)
except KeyboardInterrupt as e:
    print("KeyboardInterrupt", e, flush=True)
"""


def interrupt(what, root, delay):
    p = subprocess.Popen([sys.executable, "-c", CHILD, what, root], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True)
    check(p.stdout.readline().strip() == "started", f"{what}: the child did not start")
    time.sleep(delay)
    sent = time.monotonic()
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=120)
    return out, err, time.monotonic() - sent


with tempfile.TemporaryDirectory() as root:
    out, err, after = interrupt("case", root, 2.0)
    check("KeyboardInterrupt" in out, f"run_case: no KeyboardInterrupt: {out!r} {err[-300:]!r}")
    check(after < 2.0 + 1.0, f"run_case: the child ended {after:.1f} s after SIGINT (limit 2 s "
          "plus 1 s for the interpreter to start and end)")
    check(not os.path.exists(os.path.join(root, "case.h5")), "run_case wrote its case file")

    # four cases of 2e6 rk4 steps each (seconds each), one at a time (run_study's default)
    study = {"name": "slow", "scene": "gravity-drop",
             "integrator": {"method": "rk4", "step": 1e-6, "max_steps": 10**12},
             "time": {"end": 2.0, "sample_interval": 0.01},
             "grid": [{"key": "parameters.contact.clearance",
                       "values": [1e-4, 2e-4, 3e-4, 4e-4]}]}
    with open(os.path.join(root, "study.json"), "w") as f:
        json.dump(study, f)
    out, err, after = interrupt("study", root, 1.0)
    check("KeyboardInterrupt" in out, f"run_study: no KeyboardInterrupt: {out!r} {err[-300:]!r}")
    done = len(os.listdir(os.path.join(root, "slow", "cases")))
    check(0 < done < 4, f"run_study: {done} of 4 case files after the interrupt (expected the "
          "one in flight finished and written, and not every case run)")
    r = subprocess.run([sys.executable, "-c", "import rodend, sys; "
                        "print(rodend.run_study(sys.argv[1] + '/study.json', "
                        "results_root=sys.argv[1])[0])", root],
                       capture_output=True, text=True, timeout=600)
    check(r.stdout.strip() == "0", f"the resumed study: {r.stdout!r} {r.stderr[-300:]!r}")
finish("python interrupt")
