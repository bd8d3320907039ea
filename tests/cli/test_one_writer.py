"""One writer per results folder (issue 37 item 6), each run bounded by a timeout:

- a full run and `--shard 1/2` of the same study on the same folder exclude each other, in
  either order (exit 2 naming the lock's holder), and so do a merge and a running shard, and
  shards of different splits (1/3 beside 1/2); shards 1/2 and 2/2 still run side by side (before: the full run and a shard each took a lock
  file of its own and computed the same cases at once);
- case files deleted by another process during a run are noticed before the summary is
  written: exit 2 naming them, no summary, and the resume reruns them (before: exit 0 and a
  summary whose rows named files that no longer existed);
- a case file held open by h5py in "r+" mode is reported as locked (exit 2 from run, 1 from
  merge), not moved to .corrupt and rerun; once closed, the resume finds every case complete.

The first run of each pair is held by the rename hook (tests/faults/pause_rename.c) after its
first case files, until the test has done what it does beside it: the two overlap however loaded
the machine is.
"""
import glob
import os
import subprocess
import tempfile

import h5py

from common import Pause, check, finish, read_summary, rodend_path, run, write_study


def slow_study(path, name, n=6):
    """A study of n cases of about 0.4 s each."""
    return write_study(path, {
        "name": name, "scene": "rod-end-kinematic",
        "integrator": {"method": "dopri5", "abs_tol": 1e-7, "rel_tol": 1e-7, "max_step": 1e-3},
        "time": {"end": 3.0, "sample_interval": 1e-3},
        "grid": [{"key": "parameters.contact.clearance", "linspace": [1e-4, 6e-4, n]}]})


def start(args, env=None):
    return subprocess.Popen([rodend_path()] + args, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=env)


def exclusion(tmp):
    study = slow_study(os.path.join(tmp, "excl.json"), "excl", n=8)
    root = os.path.join(tmp, "excl-root")
    cases = os.path.join(root, "excl", "cases", "*.h5")
    # (first, second, what the second says: None = it runs beside the first)
    for first, second, says in ((["--shard", "1/2"], [], ".rodend.lock"),
                                ([], ["--shard", "1/2"], ".rodend.lock"),
                                (["--shard", "2/2"], ["--shard", "1/2"], None),
                                (["--shard", "1/2"], ["--shard", "1/3"], "another split")):
        hold = Pause(tmp, 1)
        p = start(["run", study, "-q", "-j", "1", "--results-root", root] + first, hold.env())
        check(hold.wait(alive=lambda: p.poll() is None), f"{first}: the run was not held")
        r = run(["run", study, "-q", "-j", "1", "--results-root", root] + second, timeout=300)
        if says is None:  # two shards of one split: side by side
            check(r.returncode == 0, f"shard {second} beside {first}: exit {r.returncode} "
                                     f"{r.stderr[-400:]}")
        else:
            check(r.returncode == 2 and says in r.stderr,
                  f"{second or 'full run'} while {first or 'full run'} runs: exit "
                  f"{r.returncode} {r.stderr[-400:]}")
        if first == ["--shard", "1/2"] and not second:
            m = run(["merge", study, "--results-root", root], timeout=300)
            check(m.returncode == 2 and "holds" in m.stderr,
                  f"merge while a shard runs: exit {m.returncode} {m.stderr[-300:]}")
        hold.release()
        check(p.wait(timeout=300) in (0, 1), f"{first}: the first run failed: {p.stderr.read()}")
        for f in glob.glob(cases):
            os.remove(f)


def deleted_files(tmp):
    study = slow_study(os.path.join(tmp, "del.json"), "del", n=6)
    root = os.path.join(tmp, "del-root")
    folder = os.path.join(root, "del")
    hold = Pause(tmp, 2)
    p = start(["run", study, "-q", "-j", "1", "--results-root", root], hold.env())
    check(hold.wait(alive=lambda: p.poll() is None), "deleted: the run was not held")
    gone = sorted(glob.glob(os.path.join(folder, "cases", "*.h5")))[0]
    os.remove(gone)
    hold.release()
    _, err = p.communicate(timeout=300)
    check(p.returncode == 2 and "disappeared" in err and gone in err and "Resume with" in err,
          f"a deleted case file: exit {p.returncode} {err[-600:]}")
    check(not os.path.exists(os.path.join(folder, "summary.csv")),
          "a summary was written for a deleted case file")
    r = run(["run", study, "-q", "-j", "1", "--results-root", root], timeout=300)
    check(r.returncode == 0 and os.path.exists(gone), f"resume: exit {r.returncode} {r.stderr}")
    rows = read_summary(folder) if r.returncode == 0 else []
    check(len(rows) == 6 and all(os.path.exists(os.path.join(folder, "cases", x["case_id"] + ".h5"))
                                 for x in rows), "resume: the summary's case files")


def locked_file(tmp):
    study = write_study(os.path.join(tmp, "lock.json"), {
        "name": "lock", "scene": "gravity-drop", "time": {"end": 0.02, "sample_interval": 1e-3},
        "grid": [{"key": "parameters.contact.clearance", "values": [2e-4, 4e-4]}]})
    root = os.path.join(tmp, "lock-root")
    folder = os.path.join(root, "lock")
    r = run(["run", study, "-q", "--results-root", root], timeout=300)
    check(r.returncode == 0, f"locked: first run {r.stderr}")
    path = sorted(glob.glob(os.path.join(folder, "cases", "*.h5")))[0]
    with h5py.File(path, "r+"):
        r = run(["run", study, "-q", "--results-root", root], timeout=300)
        check(r.returncode == 2 and "locked" in r.stderr and path in r.stderr,
              f"run beside h5py r+: exit {r.returncode} {r.stderr[-400:]}")
        m = run(["merge", study, "--results-root", root], timeout=300)
        check(m.returncode == 1 and "locked" in m.stderr,
              f"merge beside h5py r+: exit {m.returncode} {m.stderr[-400:]}")
    check(not glob.glob(os.path.join(folder, "cases", "*.corrupt*")),
          "a locked case file was moved aside as corrupt")
    r = run(["run", study, "--results-root", root], timeout=300)
    check(r.returncode == 0 and "2 of 2 cases already complete" in r.stderr,
          f"after h5py closed it: exit {r.returncode} {r.stderr[-400:]}")


def main():
    os.environ.pop("HDF5_USE_FILE_LOCKING", None)  # h5py must lock what it opens
    with tempfile.TemporaryDirectory(prefix="rodend-writer-") as tmp:
        exclusion(tmp)
        deleted_files(tmp)
        locked_file(tmp)
    finish("one_writer")


main()
