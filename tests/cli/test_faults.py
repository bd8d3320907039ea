"""Faults around the results directory (issue 19): a foreign directory is refused and left
untouched; two runs of one study do not both compute (the second refuses, or waits with --wait);
SIGINT and SIGTERM stop the run cleanly (exit 130/143, no temporary file left, resume completes
it with results equal to an uninterrupted run); temporary files of dead writers are removed;
study paths that are not regular files are refused; a case file reused from another grid takes
this grid's case_index."""
import glob
import os
import signal
import socket
import subprocess
import tempfile

from common import (Pause, assert_same_results, check, finish, read_summary, read_until, rodend_path,
                    run, write_study)


def slow_study(path, name, n=6):
    """A study of n cases, each a few tenths of a second."""
    return write_study(path, {
        "name": name,
        "scene": "rod-end-kinematic",
        "integrator": {"method": "dopri5", "abs_tol": 1e-7, "rel_tol": 1e-7, "max_step": 1e-3},
        "time": {"end": 0.6, "sample_interval": 1e-3},
        "grid": [{"key": "parameters.contact.clearance", "linspace": [1e-4, 6e-4, n]}],
    })


def temporaries(d):
    return [p for p in glob.glob(os.path.join(d, "**", ".*.tmp.*"), recursive=True)]


with tempfile.TemporaryDirectory() as tmp:
    # --- a foreign, non-empty output directory is refused and nothing in it changes
    foreign = os.path.join(tmp, "mine")
    os.makedirs(foreign)
    for name, text in (("study.json", "my own notes\n"), ("summary.csv", "a,b\n1,2\n")):
        with open(os.path.join(foreign, name), "w") as f:
            f.write(text)
    s = write_study(os.path.join(tmp, "foreign.json"), {
        "scene": "gravity-drop", "time": {"end": 0.01, "sample_interval": 1e-3},
        "output": foreign})
    r = run(["run", s, "-q"])
    check(r.returncode == 2, f"foreign directory: exit {r.returncode} ({r.stderr})")
    check("not created by rodend" in r.stderr and "output" in r.stderr,
          f"foreign directory: message {r.stderr!r}")
    check(sorted(os.listdir(foreign)) == ["study.json", "summary.csv"],
          f"foreign directory changed: {os.listdir(foreign)}")
    check(open(os.path.join(foreign, "study.json")).read() == "my own notes\n",
          "foreign study.json overwritten")
    # an empty directory is taken (and marked)
    empty = os.path.join(tmp, "empty")
    os.makedirs(empty)
    s = write_study(os.path.join(tmp, "empty.json"), {
        "scene": "gravity-drop", "time": {"end": 0.01, "sample_interval": 1e-3}, "output": empty})
    r = run(["run", s, "-q"])
    check(r.returncode == 0, f"empty directory: {r.stderr}")
    check(os.path.exists(os.path.join(empty, ".rodend")), "no ownership marker written")

    # --- study paths that are not regular files
    fifo = os.path.join(tmp, "fifo.json")
    os.mkfifo(fifo)
    big = os.path.join(tmp, "big.json")
    with open(big, "wb") as f:
        f.truncate(17 * 1024 * 1024)
    for path, text in ((tmp, "is a directory"), (fifo, "not a regular file"),
                       ("/dev/zero", "not a regular file"), (big, "larger than 16 MiB"),
                       (os.path.join(tmp, "absent.json"), "no such file")):
        try:
            r = run(["run", path, "-q", "--results-root", os.path.join(tmp, "none")], timeout=120)
        except subprocess.TimeoutExpired:
            check(False, f"{path}: hangs")
            continue
        check(r.returncode == 2 and text in r.stderr and path in r.stderr,
              f"{path}: exit {r.returncode}, message {r.stderr!r}")
    check(not os.path.exists(os.path.join(tmp, "none")), "something was written for a bad path")

    # --- reference for the interrupted runs
    study = slow_study(os.path.join(tmp, "faults.json"), "faults")
    ref = os.path.join(tmp, "ref")
    r = run(["run", study, "--results-root", ref, "-q", "--threads", "2"])
    check(r.returncode == 0, f"reference run: {r.stderr}")

    # --- two runs of one study: the second refuses naming the holder; --wait queues behind.
    # The first is held after its first case file (tests/faults/pause_rename.c) until the second
    # has been refused, so the two overlap however the machine is loaded.
    root = os.path.join(tmp, "twice")
    hold = Pause(tmp, 1)
    a = subprocess.Popen([rodend_path(), "run", study, "--results-root", root, "-q", "-j", "1"],
                         stderr=subprocess.PIPE, text=True, env=hold.env())
    check(hold.wait(alive=lambda: a.poll() is None), "the first run was not held after a case")
    r = run(["run", study, "--results-root", root, "-q"], timeout=300)
    hold.release()
    a.wait(timeout=300)
    check(a.returncode == 0, f"first run: {a.returncode}")
    check(r.returncode == 2 and "another run of this study" in r.stderr and
          f"pid {a.pid}" in r.stderr, f"second run: exit {r.returncode}, {r.stderr!r}")
    assert_same_results(os.path.join(ref, "faults"), os.path.join(root, "faults"), "two runs")
    # --wait, against a holder this test controls (the lock is an flock on .rodend.lock): the
    # run says it waits, and is still waiting, when the test lets the lock go
    import fcntl
    with open(os.path.join(root, "faults", ".rodend.lock"), "r+") as holder:
        fcntl.flock(holder, fcntl.LOCK_EX)
        holder.truncate(0)
        holder.write(f"pid {os.getpid()} on test\n")
        holder.flush()
        w = subprocess.Popen([rodend_path(), "run", study, "--results-root", root, "--wait"],
                             stderr=subprocess.PIPE, text=True)
        before = "".join(read_until(w.stderr, "waiting for the run"))
        check("waiting for the run" in before and w.poll() is None,
              f"--wait did not wait for the lock: {w.poll()} {before!r}")
        fcntl.flock(holder, fcntl.LOCK_UN)
    _, err = w.communicate(timeout=300)
    err = before + err
    check(w.returncode == 0 and "waiting for the run" in err and f"pid {os.getpid()} on test" in err
          and "6 of 6 cases already complete" in err, f"--wait: {w.returncode} {err!r}")

    # --- SIGINT / SIGTERM: stop taking cases, finish those in flight, exit 128+signal. The run
    # is held with one case file renamed into place and its other cases in flight; the signal
    # is sent in that state, and the held cases go on once the run says it is stopping.
    for sig, code in ((signal.SIGINT, 130), (signal.SIGTERM, 143)):
        root = os.path.join(tmp, f"sig{code}")
        hold = Pause(tmp, 1)
        p = subprocess.Popen([rodend_path(), "run", study, "--results-root", root, "-q", "-j", "2"],
                             stderr=subprocess.PIPE, text=True, env=hold.env())
        check(hold.wait(alive=lambda: p.poll() is None), f"{sig.name}: the run was not held")
        p.send_signal(sig)
        before = "".join(read_until(p.stderr, "rodend: stop"))
        hold.release()
        _, err = p.communicate(timeout=300)
        err = before + err
        check(p.returncode == code, f"{sig.name}: exit {p.returncode}, expected {code} ({err})")
        check(f"stopped by {sig.name}" in err and "Resume with: rodend run" in err,
              f"{sig.name}: message {err!r}")
        done = len(glob.glob(os.path.join(root, "faults", "cases", "*.h5")))
        check(f" {done} of 6 case(s) complete" in err and 1 < done < 6,
              f"{sig.name}: {done} case files; message {err!r}")
        check(temporaries(root) == [], f"{sig.name}: temporary files left {temporaries(root)}")
        r = run(["run", study, "--results-root", root, "-j", "2"])
        check(r.returncode == 0, f"{sig.name}: resume {r.stderr}")
        assert_same_results(os.path.join(ref, "faults"), os.path.join(root, "faults"), sig.name)

    # --- temporary files of dead writers are removed at the next start; a live one is kept
    root = os.path.join(tmp, "stale")
    r = run(["run", study, "--results-root", root, "-q", "-j", "2"])
    dead = subprocess.Popen(["true"])
    dead.wait()
    cases = os.path.join(root, "faults", "cases")
    host = socket.gethostname()
    stale = [os.path.join(cases, f".0123456789abcdef.h5.tmp.{host}.{dead.pid}.3"),
             os.path.join(cases, f".0123456789abcdef.h5.tmp.{dead.pid}.0"),
             os.path.join(root, "faults", f".summary.csv.tmp.{host}.{dead.pid}.1")]
    live = os.path.join(cases, f".fedcba9876543210.h5.tmp.{host}.{os.getpid()}.0")
    other = os.path.join(cases, f".fedcba9876543210.h5.tmp.other-node.{dead.pid}.0")
    for path in stale + [live, other]:
        open(path, "w").close()
    r = run(["run", study, "--results-root", root])
    check(r.returncode == 0 and "removed 3 temporary file(s)" in r.stderr, f"stale: {r.stderr!r}")
    check(not any(os.path.exists(p) for p in stale), "stale temporary files remain")
    check(os.path.exists(live) and os.path.exists(other), "a live writer's file was removed")

    # --- a case file reused from another grid of the study takes this grid's case_index
    wide = slow_study(os.path.join(tmp, "reuse.json"), "reuse", n=6)
    root = os.path.join(tmp, "reuse")
    run(["run", wide, "--results-root", root, "-q", "-j", "2"])
    narrow = write_study(os.path.join(tmp, "reuse.json"), {
        "name": "reuse",
        "scene": "rod-end-kinematic",
        "integrator": {"method": "dopri5", "abs_tol": 1e-7, "rel_tol": 1e-7, "max_step": 1e-3},
        "time": {"end": 0.6, "sample_interval": 1e-3},
        "grid": [{"key": "parameters.contact.clearance", "values": [6e-4, 4e-4]}],
    })
    r = run(["run", narrow, "--results-root", root, "-q"])
    rows = read_summary(os.path.join(root, "reuse"))
    check(r.returncode == 0 and [row["case_index"] for row in rows] == ["0", "1"],
          f"reused case_index: {[row.get('case_index') for row in rows]} {r.stderr}")
finish("faults")
