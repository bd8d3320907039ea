"""What `rodend run` says when a signal stops it (docs/testing.md, "Faults"):

- one SIGINT: the cases in flight finish, then "stopped by SIGINT: N of M case(s) complete ...
  no summary written. Resume with: ..." and exit 130; no "results in ..." line after it (that
  line is for runs that wrote a summary);
- a second SIGINT while a case is still in flight: the process ends at once, by the signal,
  after printing the count of complete cases and the resume command.

Each waits for a state, not a time: a case file on the disk (the handler is installed and the
next case is in flight), the "stopping" notice on stderr (the first signal was taken). The case
in flight at the second signal is made to last minutes, so it is still running whatever the load.

    RODEND=build/rodend /usr/bin/python3 tests/cli/test_signal_messages.py"""
import glob
import os
import signal
import subprocess
import tempfile
import time

from common import check, finish, rodend_path, write_study


def wait_for_files(pattern, count, timeout=120.0):
    t0 = time.monotonic()
    while time.monotonic() - t0 < timeout:
        if len(glob.glob(pattern)) >= count:
            return True
        time.sleep(0.02)
    return False


def study(path, ends):
    """A case per end time, run in this order with -j 1."""
    return write_study(path, {
        "name": os.path.basename(path)[:-5], "scene": "rod-end-kinematic",
        "integrator": {"method": "dopri5", "abs_tol": 1e-7, "rel_tol": 1e-7, "max_step": 1e-3},
        "time": {"end": 0.3, "sample_interval": 1e-3},
        "grid": [{"key": "time.end", "values": ends}]})


with tempfile.TemporaryDirectory() as tmp:
    # --- one SIGINT: the count and the resume command, no "results in"
    s = study(os.path.join(tmp, "once.json"), [0.05, 0.3, 0.31, 0.32])
    root = os.path.join(tmp, "once")
    p = subprocess.Popen([rodend_path(), "run", s, "--results-root", root, "-q", "-j", "1"],
                         stderr=subprocess.PIPE, text=True)
    check(wait_for_files(os.path.join(root, "once", "cases", "*.h5"), 1), "once: no case file")
    p.send_signal(signal.SIGINT)
    _, err = p.communicate(timeout=300)
    check(p.returncode == 130, f"once: exit {p.returncode} ({err!r})")
    check("stopped by SIGINT" in err and "no summary written" in err and
          "Resume with: rodend run" in err, f"once: message {err!r}")
    check("results in" not in err, f"once: 'results in' after a run without summary: {err!r}")

    # --- a second SIGINT: at once, with the count and the resume command
    s = study(os.path.join(tmp, "twice.json"), [0.05, 600.0])
    root = os.path.join(tmp, "twice")
    p = subprocess.Popen([rodend_path(), "run", s, "--results-root", root, "-q", "-j", "1"],
                         stderr=subprocess.PIPE, text=True)
    check(wait_for_files(os.path.join(root, "twice", "cases", "*.h5"), 1), "twice: no case file")
    p.send_signal(signal.SIGINT)
    seen = ""
    while "rodend: stopping" not in seen:  # the first signal taken
        line = p.stderr.readline()
        if not line:
            break
        seen += line
    check("rodend: stopping" in seen, f"twice: no stopping notice: {seen!r}")
    p.send_signal(signal.SIGINT)
    try:
        rest, _ = p.communicate(timeout=60)[1], None
    except subprocess.TimeoutExpired:
        p.kill()
        rest = ""
        check(False, "twice: the second SIGINT did not end the run at once")
    err = seen + (rest or "")
    check(p.returncode in (-signal.SIGINT, 130), f"twice: exit {p.returncode} ({err!r})")
    check("stopped at once by SIGINT: 1 of 2 case(s) complete in " in err and
          "Resume with: rodend run" in err and s in err, f"twice: message {err!r}")
    check("results in" not in err, f"twice: 'results in' printed: {err!r}")
finish("signal messages")
