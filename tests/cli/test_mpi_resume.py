"""Crash safety under MPI: SIGKILL `mpirun -np 2` at several moments of a study, check that no
process of the job survives (Open MPI puts each rank in its own process group, so the whole
session of the job is checked and cleaned), rerun the same command and get results equal to an
uninterrupted run, case by case. Argument: the path of mpirun."""
import glob
import os
import signal
import subprocess
import sys
import tempfile
import time

import h5py

from common import assert_same_results, check, finish, rodend_path, write_study

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
    t0 = time.monotonic()
    r = subprocess.run(command(ref), capture_output=True, text=True, env=ENV, timeout=120)
    full = time.monotonic() - t0
    check(r.returncode == 0, f"reference run failed: {r.stderr}")
    per_rank = [ln for ln in r.stderr.splitlines() if "cases run by rank" in ln]
    check(len(per_rank) == 1 and all(int(n) > 0 for n in per_rank[0].split(":")[-1].split()),
          f"both ranks should have run cases: {per_rank}")

    for i, frac in enumerate([0.3, 0.5, 0.7]):
        root = os.path.join(tmp, f"k{i}")
        # its own session: mpirun and its ranks (each in a process group of its own)
        p = subprocess.Popen(command(root), env=ENV, start_new_session=True,
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        time.sleep(frac * full)
        os.killpg(p.pid, signal.SIGKILL)  # mpirun's group: mpirun itself
        p.wait()
        t_kill = time.monotonic()
        # the ranks notice that mpirun is gone and exit by themselves (within 0.2 s)
        deadline = time.monotonic() + 10
        while session_members(p.pid) and time.monotonic() < deadline:
            time.sleep(0.2)
        ranks_gone_after = time.monotonic() - t_kill
        orphans = session_members(p.pid)
        check(not orphans, f"kill {i}: ranks outlived mpirun by 10 s: {orphans}")
        for pid in orphans:  # never leave any behind
            try:
                os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
        done = glob.glob(os.path.join(root, "resume", "cases", "*.h5"))
        for path in done:  # every file under its final name opens and is complete
            with h5py.File(path, "r") as f:
                check(f.attrs["status"] == "ok", f"{path}: status {f.attrs['status']}")
        r = subprocess.run(command(root), capture_output=True, text=True, env=ENV, timeout=120)
        check(r.returncode == 0, f"resume {i}: {r.stderr}")
        check(f"{len(done)} of 8 cases already complete" in r.stderr or len(done) == 0,
              f"resume {i} did not reuse the {len(done)} complete cases: {r.stderr}")
        assert_same_results(os.path.join(ref, "resume"), os.path.join(root, "resume"),
                            f"kill mpirun at {frac:.2f} ({len(done)} cases done)")
        leftovers = [f for f in os.listdir(os.path.join(root, "resume", "cases")) if not f.endswith(".h5")]
        check(all(f.startswith(".") for f in leftovers), f"unexpected files {leftovers}")
        print(f"kill at {frac:.2f} of {full:.1f} s: {len(done)} of 8 cases were complete; "
              f"the ranks were gone {ranks_gone_after:.2f} s after mpirun")
finish("mpi_resume")
