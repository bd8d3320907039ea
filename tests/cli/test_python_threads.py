"""The Python module under threads and interrupts (issue 37 item 5), each check in a child
interpreter with a time limit, so that a deadlock or a crash is a failure, not a hang:

- two threads calling rodend.run_case first, right after the import, both finish (3 tries;
  a deadlock on the first call hung every try before the module initialised itself at import);
- run_study's thread count is checked as on the command line: 0, 4097 and 100000 raise
  InputError, "2", 2.0 and True raise TypeError, and nothing is run;
- a `set=` value nested 100,000 levels deep raises InputError (dict and "key=value" forms),
  and so does run_case's `parameters=`: never a crash from a recursive conversion;
- after two overlapping run_study calls in two threads, SIGINT raises KeyboardInterrupt in
  Python (the interpreter's handler is back), whichever call ends first (the order is made by
  the calls' progress callbacks, not by their lengths).
"""
import os
import signal
import subprocess
import sys
import tempfile
import textwrap

from common import check, finish, write_study

PY = sys.executable


def child(code, timeout, cwd):
    """Runs `code` in a child interpreter; (exit code or 'timeout', stdout + stderr)."""
    try:
        r = subprocess.run([PY, "-c", textwrap.dedent(code)], capture_output=True, text=True,
                           timeout=timeout, cwd=cwd)
        return r.returncode, r.stdout + r.stderr
    except subprocess.TimeoutExpired as e:
        out = (e.stdout or b"") + (e.stderr or b"")
        return "timeout", out.decode(errors="replace") if isinstance(out, bytes) else out


FIRST_CALLS = """
    import threading, rodend
    out = []
    def one():
        c = rodend.run_case("gravity-drop", time={"end": 0.01, "sample_interval": 1e-3})
        out.append(c.status)
    ts = [threading.Thread(target=one) for _ in range(2)]
    for t in ts: t.start()
    for t in ts: t.join()
    print("statuses", sorted(out))
"""

THREAD_COUNTS = """
    import rodend
    for bad, kind in ((0, rodend.InputError), (4097, rodend.InputError),
                      (100000, rodend.InputError), ("2", TypeError), (2.0, TypeError),
                      (True, TypeError)):
        try:
            rodend.run_study("study.json", threads=bad, results_root="res")
            print("accepted", repr(bad))
        except kind as e:
            print("refused", repr(bad), type(e).__name__, e)
    import os
    print("ran", os.path.exists("res"))
"""

DEEP = """
    import rodend
    deep = 0.0
    for _ in range(100000):
        deep = [deep]
    text = "[" * 100000 + "0" + "]" * 100000
    # a top-level key is copied whole (recursively) before the loader checks it
    for what, call in (
            ("set dict", lambda: rodend.load_study("study.json", set={"description": deep})),
            ("set string", lambda: rodend.load_study("study.json", set=["description=" + text])),
            ("run_study set", lambda: rodend.run_study("study.json", results_root="res",
                                                       set=["grid=" + text])),
            ("run_case parameters",
             lambda: rodend.run_case("gravity-drop", {"contact.clearance": deep}))):
        try:
            call()
            print(what, "accepted")
        except Exception as e:  # noqa: BLE001  (which one is the check)
            print(what, type(e).__name__, str(e)[:200])
"""

SIGINT_AFTER = """
    import signal, threading, rodend
    # Two run_study calls overlap: B starts once A's first case is complete (A's run holds its
    # signal scope then), and each order of their ends is made by the progress callbacks, which
    # hold one run until the other has ended: A ends last, then A ends first (before the fix:
    # A restored Python's handler, then B what it had replaced, rodend's, which swallowed the
    # next SIGINT).
    def study(name, progress):
        rodend.run_study("slow.json", threads=1, results_root="res-" + name, progress=progress)
    for a_last in (True, False):
        a_in, b_in, a_done, b_done = (threading.Event() for _ in range(4))
        def on_a(p, a_last=a_last, a_in=a_in, b_in=b_in, b_done=b_done):
            a_in.set()
            (b_done if a_last else b_in).wait(300)
        def on_b(p, a_last=a_last, b_in=b_in, a_done=a_done):
            b_in.set()
            if not a_last:
                a_done.wait(300)
        a = threading.Thread(target=study, args=("a%d" % a_last, on_a))
        b = threading.Thread(target=study, args=("b%d" % a_last, on_b))
        a.start(); a_in.wait(300); b.start()
        if a_last:
            b.join(); b_done.set(); a.join()
        else:
            a.join(); a_done.set(); b.join()
        try:
            signal.raise_signal(signal.SIGINT)  # handled in this thread before it returns
            print("SIGINT ignored")
        except KeyboardInterrupt:
            print("KeyboardInterrupt")
    print("handler", signal.getsignal(signal.SIGINT) is signal.default_int_handler)
"""


def main():
    with tempfile.TemporaryDirectory(prefix="rodend-pythreads-") as tmp:
        write_study(os.path.join(tmp, "study.json"), {
            "name": "pythreads", "scene": "gravity-drop",
            "time": {"end": 0.02, "sample_interval": 1e-3},
            "grid": [{"key": "parameters.contact.clearance", "values": [2e-4, 4e-4]}]})
        write_study(os.path.join(tmp, "slow.json"), {
            "name": "slow", "scene": "rod-end-kinematic",
            "time": {"end": 0.5, "sample_interval": 1e-3},
            "grid": [{"key": "parameters.contact.clearance", "values": [2e-4, 4e-4]}]})

        for k in range(3):
            rc, out = child(FIRST_CALLS, 30, tmp)
            check(rc == 0 and "statuses ['ok', 'ok']" in out,
                  f"two threads calling run_case first (try {k + 1}): {rc} {out[-500:]}")

        rc, out = child(THREAD_COUNTS, 60, tmp)
        check(rc == 0, f"thread counts: exit {rc} {out[-800:]}")
        for bad, kind in (("0", "InputError"), ("4097", "InputError"), ("100000", "InputError"),
                          ("'2'", "TypeError"), ("2.0", "TypeError"), ("True", "TypeError")):
            check(f"refused {bad} {kind}" in out, f"threads={bad}: expected {kind}: {out[-800:]}")
        check("threads" in out and "4096" in out, f"thread count message: {out[-800:]}")
        check("ran False" in out, f"a refused thread count ran the study: {out[-300:]}")

        rc, out = child(DEEP, 60, tmp)
        check(rc == 0, f"100,000 levels: exit {rc} {out[-800:]}")
        for what in ("set dict", "set string", "run_study set", "run_case parameters"):
            check(f"{what} InputError" in out, f"100,000 levels, {what}: {out[-800:]}")

        rc, out = child(SIGINT_AFTER, 120, tmp)
        check(rc == 0 and out.count("KeyboardInterrupt") == 2 and "handler True" in out,
              f"SIGINT after overlapping run_study calls: exit {rc} {out[-800:]}")
    finish("python_threads")


main()
