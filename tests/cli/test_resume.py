"""Crash safety: kill -9 a running study at several moments, rerun the same command, and get
results equal to an uninterrupted run, case by case; no incomplete file under a final name.

The moments are states of the run, held by the rename hook (tests/faults/pause_rename.c): 0, 2
and 4 of its 6 case files renamed into place, the next ones written to their temporary names and
held before their rename, so the kill finds the run where the test means it to on any machine.
With the argument `random` (scripts/faults-long.sh) the kills come instead at 15, 40 and 70 % of
an uninterrupted run's wall time, wherever the run is then."""
import glob
import os
import signal
import subprocess
import tempfile
import sys
import time

import h5py

from common import (Pause, assert_same_results, check, finish, read_summary, rodend_path, run,
                    write_study)

RANDOM = sys.argv[1:] == ["random"]

with tempfile.TemporaryDirectory() as tmp:
    study = write_study(os.path.join(tmp, "resume.json"), {
        "name": "resume",
        "scene": "rod-end-kinematic",
        "integrator": {"method": "dopri5", "abs_tol": 1e-7, "rel_tol": 1e-7, "max_step": 1e-3},
        "time": {"end": 1.2, "sample_interval": 1e-4},
        "grid": [{"key": "parameters.contact.clearance", "linspace": [1e-4, 6e-4, 6]}],
    })
    ref = os.path.join(tmp, "ref")
    t0 = time.monotonic()
    r = run(["run", study, "--results-root", ref, "-q", "--threads", "2"])
    full = time.monotonic() - t0
    check(r.returncode == 0, f"reference run failed: {r.stderr}")
    for i, (frac, after) in enumerate([(0.15, 0), (0.4, 2), (0.7, 4)]):
        root = os.path.join(tmp, f"k{i}")
        hold = Pause(tmp, after)
        p = subprocess.Popen([rodend_path(), "run", study, "--results-root", root, "-q", "--threads", "2"],
                             env=None if RANDOM else hold.env())
        if RANDOM:
            time.sleep(frac * full)
        else:
            check(hold.wait(alive=lambda: p.poll() is None), f"kill {i}: the run was not held")
        p.send_signal(signal.SIGKILL)
        p.wait()
        done = glob.glob(os.path.join(root, "resume", "cases", "*.h5"))
        for path in done:  # every file under its final name opens and is complete
            with h5py.File(path, "r") as f:
                check(f.attrs["status"] in ("ok",), f"{path}: status {f.attrs['status']}")
        r = run(["run", study, "--results-root", root, "--threads", "2"])
        check(r.returncode == 0, f"resume {i}: {r.stderr}")
        check(RANDOM or len(done) == after, f"kill {i}: {len(done)} case files, {after} expected")
        check(f"{len(done)} of 6 cases already complete" in r.stderr or len(done) == 0,
              f"resume {i} did not reuse the {len(done)} complete cases: {r.stderr}")
        assert_same_results(os.path.join(ref, "resume"), os.path.join(root, "resume"), f"kill {i}")
        leftovers = [f for f in os.listdir(os.path.join(root, "resume", "cases")) if not f.endswith(".h5")]
        # temporary files of the killed run stay hidden; they are never read as results
        check(all(f.startswith(".") for f in leftovers), f"unexpected files {leftovers}")
    check(len(read_summary(os.path.join(ref, "resume"))) == 6, "reference summary rows")
finish("resume")
