#!/usr/bin/env python3
"""Messages and progress where a Python user looks (issue 35 item 3): rodend.run_study's
messages go to the logger "rodend" and its progress to Python's sys.stderr (a tqdm bar where
tqdm is installed, else the progress line) or to a callback; nothing reaches file descriptor 2,
where a notebook's kernel would swallow it. Before, the runner wrote everything on descriptor 2:
`contextlib.redirect_stderr` captured nothing and `logging` saw nothing.

Each check runs in a child Python whose descriptor 2 is a file the test reads afterwards."""
import json
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


def main():
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
