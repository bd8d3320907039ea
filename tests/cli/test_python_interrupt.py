#!/usr/bin/env python3
"""Ctrl-C interrupts rodend from Python (issue 35 item 2): SIGINT sent to a Python process inside
`rodend.run_case` raises KeyboardInterrupt (the case in flight stops at its next sample; nothing is
written), and inside `rodend.run_study` raises KeyboardInterrupt once the cases in flight are
finished and written, after which the same call resumes the study to every case ok.

The signal is sent in a state, not after a time: inside run_case once the child sees rodend's
handler installed for SIGINT (the case is running), inside run_study once its first case is
complete (its progress callback, which then holds the run until the handler has run, so that
exactly one case is complete). Timeouts only bound a failure."""
import json
import os
import signal
import subprocess
import sys
import tempfile

from common import check, finish

CHILD = r"""
import ctypes, json, os, signal, sys, threading, time, rodend
what, root = sys.argv[1], sys.argv[2]
libc = ctypes.CDLL(None, use_errno=True)

def sigint_handler():
    # the C-level handler of SIGINT (struct sigaction starts with it), not Python's record
    buf = ctypes.create_string_buffer(256)
    libc.sigaction(signal.SIGINT, None, buf)
    return ctypes.c_void_p.from_buffer(buf).value

python_handler = sigint_handler()

def announce_when_installed():
    while sigint_handler() == python_handler:
        time.sleep(0.005)
    print("running", flush=True)

def on_progress(p):
    if p.done == 1:
        print("one case complete", flush=True)
        # rodend's handler resets SIGINT to the default action once it has recorded the stop
        while sigint_handler() not in (None, 0):
            time.sleep(0.005)

try:
    if what == "case":
        threading.Thread(target=announce_when_installed, daemon=True).start()
        # rk4 at 1 us over 1000 s: 1e9 steps, far longer than any test's time limit
        rodend.run_case("gravity-drop", {}, time={"end": 1000.0, "sample_interval": 0.01},
                        integrator={"method": "rk4", "step": 1e-6, "max_steps": 10**12},
                        write=root + "/case.h5")
    else:
        rodend.run_study(root + "/study.json", results_root=root, progress=on_progress)
    print("returned", flush=True)
except KeyboardInterrupt as e:
    print("KeyboardInterrupt", e, flush=True)
"""


def interrupt(what, root, state):
    p = subprocess.Popen([sys.executable, "-c", CHILD, what, root], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True)
    line = p.stdout.readline().strip()
    check(line == state, f"{what}: the child did not reach '{state}': {line!r}")
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=600)
    return out, err


with tempfile.TemporaryDirectory() as root:
    out, err = interrupt("case", root, "running")
    check("KeyboardInterrupt" in out and "returned" not in out,
          f"run_case: no KeyboardInterrupt: {out!r} {err[-300:]!r}")
    check(not os.path.exists(os.path.join(root, "case.h5")), "run_case wrote its case file")

    # four cases of 2e5 rk4 steps each, one at a time (run_study's default)
    study = {"name": "slow", "scene": "gravity-drop",
             "integrator": {"method": "rk4", "step": 1e-6, "max_steps": 10**12},
             "time": {"end": 0.2, "sample_interval": 0.01},
             "grid": [{"key": "parameters.contact.clearance",
                       "values": [1e-4, 2e-4, 3e-4, 4e-4]}]}
    with open(os.path.join(root, "study.json"), "w") as f:
        json.dump(study, f)
    out, err = interrupt("study", root, "one case complete")
    check("KeyboardInterrupt" in out, f"run_study: no KeyboardInterrupt: {out!r} {err[-300:]!r}")
    done = len(os.listdir(os.path.join(root, "slow", "cases")))
    check(done == 1, f"run_study: {done} of 4 case files after the interrupt (expected the one "
          "complete when the signal came, and no case started after it)")
    r = subprocess.run([sys.executable, "-c", "import rodend, sys; "
                        "print(rodend.run_study(sys.argv[1] + '/study.json', "
                        "results_root=sys.argv[1])[0])", root],
                       capture_output=True, text=True, timeout=600)
    check(r.stdout.strip() == "0", f"the resumed study: {r.stdout!r} {r.stderr[-300:]!r}")
finish("python interrupt")
