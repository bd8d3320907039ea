#!/usr/bin/env python3
"""Messages and progress where a Python user looks: rodend.run_study's
messages go to the logger "rodend" and its progress to Python's sys.stderr (a tqdm bar where
tqdm is installed, else the progress line) or to a callback; nothing reaches file descriptor 2,
where a notebook's kernel would swallow it. Before, the runner wrote everything on descriptor 2:
`contextlib.redirect_stderr` captured nothing and `logging` saw nothing.

Each check runs in a child Python whose descriptor 2 is a file the test reads afterwards.

The displays themselves (display_checks): the tqdm bar's rate is the run's (a bar made when the
first case ends used to show one case over the microseconds since it was made: "69905 case/s"),
and a message (the stop after Ctrl-C) starts on a line of its own, not glued to the updating
progress line or the bar."""
import io
import json
import logging
import os
import subprocess
import sys
import tempfile

from common import check, finish

CHILD = r"""
import contextlib, io, json, logging, os, signal, sys
what, root = sys.argv[1], sys.argv[2]
if what == "no-tqdm":
    sys.modules["tqdm"] = None          # as if python3-tqdm were not installed
import rodend
records = []
class Keep(logging.Handler):
    def emit(self, r):
        records.append([r.levelname, r.getMessage()])
logging.getLogger("rodend").addHandler(Keep())
logging.getLogger("rodend").setLevel(logging.INFO)
study = {"name": "drop", "scene": "gravity-drop", "time": {"end": 0.02, "sample_interval": 1e-3},
         "grid": [{"key": "parameters.contact.clearance", "values": [1e-4, 2e-4, 3e-4]}]}
seen, out = [], {}
if what == "callback":
    rodend.run_study(study, results_root=root, progress=seen.append)
    out["progress"] = [list(p) for p in seen]
elif what == "interrupt":
    def stop(p):                        # Ctrl-C while the first case is written
        seen.append(list(p))
        os.kill(os.getpid(), signal.SIGINT)
    try:
        rodend.run_study(study, results_root=root, progress=stop)
    except KeyboardInterrupt as e:
        out["interrupt"] = str(e)
else:
    buf = io.StringIO()
    with contextlib.redirect_stderr(buf):
        rodend.run_study(study, results_root=root, progress=True)
        rodend.run_study(study, results_root=root, progress=True)   # all complete: a message
    out["stderr"] = buf.getvalue()
out["records"] = records
print(json.dumps(out))
"""


def child(what, root):
    with tempfile.TemporaryFile("w+") as fd2:
        r = subprocess.run([sys.executable, "-c", CHILD, what, root], stdout=subprocess.PIPE,
                           stderr=fd2, text=True, timeout=300)
        fd2.seek(0)
        err = fd2.read()
    if r.returncode != 0:
        check(False, f"{what}: the child failed ({r.returncode}): {err[-800:]}")
        finish("python_messages")
    check(err == "", f"{what}: written on file descriptor 2 (a notebook would not show it): "
          f"{err[-500:]!r}")
    return json.loads(r.stdout.strip().splitlines()[-1])


class Terminal(io.StringIO):
    def isatty(self):
        return True


def shown(make, progresses, message):
    """What a display shows on a terminal for these Progress tuples, then a runner message
    (through the logger "rodend", whose handler writes to the same terminal)."""
    from rodend.progress import Progress, Reporter
    term, old = Terminal(), sys.stderr
    handler = logging.StreamHandler(term)
    handler.setFormatter(logging.Formatter("rodend: %(message)s"))
    log = logging.getLogger("rodend")
    log.addHandler(handler)
    sys.stderr = term
    try:
        rep = Reporter(True)
        rep.shown = make()
        for p in progresses:
            rep.progress(*Progress(*p))
        rep.message(message)
        rep.close()
    finally:
        sys.stderr = old
        log.removeHandler(handler)
    return term.getvalue()


def display_checks():
    sys.path.insert(0, os.environ.get("PYTHONPATH", "").split(os.pathsep)[0])
    from rodend.progress import Bar, TextLine
    from tqdm import tqdm
    stop = "stopped by SIGINT: 2 of 10 case(s) complete"
    for name, make in (("text line", TextLine), ("tqdm bar", lambda: Bar(tqdm))):
        out = shown(make, [(1, 10, 0, 0.5, 4.5), (2, 10, 0, 5.0, 20.0)], stop)
        before = out.split("rodend: " + stop)[0]
        check(before.endswith("\n") and ("rodend: " + stop) in out,
              f"{name}: the stop message is not on a line of its own: {out!r}")
    # two cases in 5 s of the run: 2.50 s per case (tqdm inverts a rate below 1 per second)
    check("2.50s/case" in out and "case/s," not in out.split("\r")[-1],
          f"the tqdm bar's rate is not the run's (2 cases in 5 s): {out!r}")


def main():
    display_checks()
    with tempfile.TemporaryDirectory() as root:
        out = child("callback", os.path.join(root, "a"))
        done = [p[0] for p in out["progress"]]
        check(done == [1, 2, 3] and all(p[1] == 3 and p[2] == 0 for p in out["progress"]),
              f"the callback's Progress (done, total, failed, ...): {out['progress']}")
        check(all(p[3] >= 0 and p[4] >= 0 for p in out["progress"]) and
              out["progress"][-1][4] == 0, f"elapsed and ETA: {out['progress']}")

        out = child("tqdm", os.path.join(root, "b"))
        check("3/3" in out["stderr"] and "case" in out["stderr"],
              f"progress=True with tqdm: no bar on sys.stderr: {out['stderr']!r}")
        check(["INFO", "3 of 3 cases already complete, 0 to run"] in out["records"],
              f"the resume message did not reach logging: {out['records']}")

        out = child("no-tqdm", os.path.join(root, "c"))
        check("rodend: 3/3 cases done, 0 failed" in out["stderr"],
              f"progress=True without tqdm: no progress line on sys.stderr: {out['stderr']!r}")

        out = child("interrupt", os.path.join(root, "d"))
        check("interrupt" in out, f"no KeyboardInterrupt: {out}")
        stops = [m for lvl, m in out["records"] if lvl == "WARNING" and "stopped by SIGINT" in m]
        check(len(stops) == 1 and "Resume with: rodend run" in stops[0] and
              "--results-root" in stops[0], f"the stop message in logging: {out['records']}")
        # a study given as a dict: the hint names the study.json the results folder keeps, not
        # the temporary file the run read (removed by then)
        kept = os.path.join(root, "d", "drop", "study.json")
        check(f"rodend run {kept} " in stops[0] and ".rodend-study-" not in stops[0],
              f"the resume hint names a file that is gone: {stops[0]}")
        print("callback, tqdm bar, text line, logging and the stop message: ok")
    finish("python_messages")


if __name__ == "__main__":
    main()
