"""Crash safety under MPI: SIGKILL `mpirun -np 2` at several moments of a study, check that no
process of the job survives (Open MPI puts each rank in its own process group, so the whole
session of the job is checked and cleaned), rerun the same command and get results equal to an
uninterrupted run, case by case. The moments are states of the run, held by the rename hook
(tests/faults/pause_rename.c): 0, 1 and 2 case files renamed into place by each rank, its next
one held before its rename. Argument: the path of mpirun."""
import glob
import os
import signal
import subprocess
import sys
import tempfile
import time

import h5py

from common import Pause, assert_same_results, check, finish, rodend_path, write_study

MPIRUN = sys.argv[1]
ENV = {k: v for k, v in os.environ.items() if not k.startswith(("OMPI_", "PMIX_", "PMI_"))}
ENV.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")


def session_members(sid):
    """Live (non-zombie) processes of session `sid`."""
    out = []
    for d in os.listdir("/proc"):
        if not d.isdigit():
            continue
        try:
            with open(f"/proc/{d}/stat") as f:
                st = f.read()
        except OSError:
            continue
        fields = st[st.rindex(")") + 2:].split()
        if fields[0] != "Z" and int(fields[3]) == sid:
            out.append(int(d))
    return out


def command(root):
    return [MPIRUN, "--oversubscribe", "-np", "2", rodend_path(), "run", study,
            "--results-root", root, "--threads", "1"]


with tempfile.TemporaryDirectory() as tmp:
    study = write_study(os.path.join(tmp, "resume.json"), {
        "name": "resume",
        "scene": "rod-end-kinematic",
        "integrator": {"method": "dopri5", "abs_tol": 1e-7, "rel_tol": 1e-7, "max_step": 1e-3},
        "time": {"end": 1.2, "sample_interval": 1e-4},
        "grid": [{"key": "parameters.contact.clearance", "linspace": [1e-4, 6e-4, 8]}],
    })
    ref = os.path.join(tmp, "ref")
    r = subprocess.run(command(ref), capture_output=True, text=True, env=ENV, timeout=300)
    check(r.returncode == 0, f"reference run failed: {r.stderr}")
    # (both ranks run cases: each is held below at a rename of its own)

    for i, after in enumerate([0, 1, 2]):
        root = os.path.join(tmp, f"k{i}")
        hold = Pause(tmp, after)
        # its own session: mpirun and its ranks (each in a process group of its own)
        p = subprocess.Popen(command(root), env=hold.env(ENV), start_new_session=True,
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        check(hold.wait(2, alive=lambda: p.poll() is None), f"kill {i}: the ranks were not held")
        os.killpg(p.pid, signal.SIGKILL)  # mpirun's group: mpirun itself
        p.wait()
        t_kill = time.monotonic()
        # the ranks notice that mpirun is gone and exit by themselves (within 0.2 s)
        deadline = time.monotonic() + 60  # a failure bound: they watch it every 0.2 s
        while session_members(p.pid) and time.monotonic() < deadline:
            time.sleep(0.05)
        ranks_gone_after = time.monotonic() - t_kill
        orphans = session_members(p.pid)
        check(not orphans, f"kill {i}: ranks outlived mpirun by 60 s: {orphans}")
        for pid in orphans:  # never leave any behind
            try:
                os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
        done = glob.glob(os.path.join(root, "resume", "cases", "*.h5"))
        for path in done:  # every file under its final name opens and is complete
            with h5py.File(path, "r") as f:
                check(f.attrs["status"] == "ok", f"{path}: status {f.attrs['status']}")
        check(len(done) == 2 * after, f"kill {i}: {len(done)} case files, {2 * after} expected")
        r = subprocess.run(command(root), capture_output=True, text=True, env=ENV, timeout=300)
        check(r.returncode == 0, f"resume {i}: {r.stderr}")
        check(f"{len(done)} of 8 cases already complete" in r.stderr or len(done) == 0,
              f"resume {i} did not reuse the {len(done)} complete cases: {r.stderr}")
        assert_same_results(os.path.join(ref, "resume"), os.path.join(root, "resume"),
                            f"kill mpirun with {len(done)} cases done")
        leftovers = [f for f in os.listdir(os.path.join(root, "resume", "cases")) if not f.endswith(".h5")]
        check(all(f.startswith(".") for f in leftovers), f"unexpected files {leftovers}")
        print(f"kill with {after} case(s) per rank held: {len(done)} of 8 cases were complete; "
              f"the ranks were gone {ranks_gone_after:.2f} s after mpirun")
finish("mpi_resume")
