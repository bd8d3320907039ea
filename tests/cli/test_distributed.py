"""Distributed runs: the same study run by 1 thread, 2 threads, shards 1/2 + 2/2 + `rodend merge`
and (given the path of mpirun as the first argument) `mpirun -np 2`, with 1 and 2 threads per
rank, and `mpirun -np 3`, gives identical summaries (but timings) and bitwise-identical histories. Also: merge
reports missing cases; under mpirun, resume, --rerun-failed, bad input and a case file that
cannot be written (MPI_Abort) behave as documented. Plain runs get an environment with no MPI
variables at all: as root, without OMPI_ALLOW_RUN_AS_ROOT, `rodend run` must not touch MPI."""
import os
import sys
import tempfile

from common import (Pause, assert_same_results, check, finish, read_summary, rodend_path, run, stable,
                    write_study)
import subprocess

MPIRUN = sys.argv[1] if len(sys.argv) > 1 and sys.argv[1] else None

# plain runs: no launcher variables, no permission to run MPI as root
PLAIN_ENV = {k: v for k, v in os.environ.items()
             if not k.startswith(("OMPI_", "PMIX_", "PMI_", "OPAL_", "PRTE_"))}
MPI_ENV = dict(PLAIN_ENV, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")


def plain(args):
    return run(args, env=PLAIN_ENV, timeout=120)


def mpirun(n, args):
    return subprocess.run([MPIRUN, "--oversubscribe", "-np", str(n), rodend_path()] + args,
                          capture_output=True, text=True, env=MPI_ENV, timeout=120)


with tempfile.TemporaryDirectory() as tmp:
    study = write_study(os.path.join(tmp, "grid.json"), {
        "name": "grid",
        "scene": "gravity-drop",
        "integrator": {"method": "dopri5", "abs_tol": 1e-8, "rel_tol": 1e-8},
        "time": {"end": 0.04, "sample_interval": 1e-4},
        "grid": [
            {"key": "parameters.contact.clearance", "values": [2e-4, 5e-4]},
            {"zip": [{"key": "parameters.contact.restitution", "values": [0.5, 0.9, 1.0]},
                     {"key": "parameters.contact.law",
                      "values": ["lankarani-nikravesh", "hunt-crossley", "hertz"]}]},
        ],
    })
    res = lambda name: os.path.join(tmp, name, "grid")  # noqa: E731

    # reference: one thread, no MPI, as root without any MPI variable
    r = plain(["run", study, "--threads", "1", "--results-root", os.path.join(tmp, "one"), "-q"])
    check(r.returncode == 0, f"1 thread: {r.returncode} {r.stderr}")
    rows = read_summary(res("one"))
    check(len(rows) == 6 and all(x["status"] == "ok" for x in rows), f"statuses: {rows}")
    r = plain(["run", study, "--threads", "2", "--results-root", os.path.join(tmp, "two"), "-q"])
    check(r.returncode == 0, f"2 threads: {r.returncode} {r.stderr}")
    assert_same_results(res("one"), res("two"), "1 thread vs 2 threads")

    # shards: merge before the last shard reports the missing cases and writes no summary
    shards = os.path.join(tmp, "shards")
    r = plain(["run", study, "--shard", "1/2", "--results-root", shards, "-q"])
    check(r.returncode == 0, f"shard 1/2: {r.returncode} {r.stderr}")
    check(len(read_summary(os.path.join(res("shards"), "shard-1-of-2"))) == 3, "shard 1/2 summary rows")
    r = plain(["merge", study, "--results-root", shards])
    check(r.returncode == 1, f"merge with a shard missing: exit {r.returncode}, expected 1")
    check("3 of 6 cases have no complete file" in r.stderr, f"merge report: {r.stderr}")
    missing = [ln.split() for ln in r.stderr.splitlines() if ln.startswith("  ")]
    check(sorted(int(m[0]) for m in missing) == [1, 3, 5] and all(m[2] == "2/2" for m in missing),
          f"missing cases listed: {missing}")
    check(not os.path.exists(os.path.join(res("shards"), "summary.csv")), "merge wrote a partial summary")
    r = plain(["run", study, "--shard", "2/2", "--results-root", shards, "-q"])
    check(r.returncode == 0, f"shard 2/2: {r.returncode} {r.stderr}")
    r = plain(["merge", study, "--results-root", shards])
    check(r.returncode == 0 and "merged 6 cases (0 failed)" in r.stderr, f"merge: {r.returncode} {r.stderr}")
    assert_same_results(res("one"), res("shards"), "1 thread vs shards + merge")
    # merge named by the results directory (its study.json) gives the same summary
    os.remove(os.path.join(res("shards"), "summary.csv"))
    r = plain(["merge", res("shards") + "/"])
    check(r.returncode == 0, f"merge RESULTS_DIR: {r.returncode} {r.stderr}")
    assert_same_results(res("one"), res("shards"), "1 thread vs merge of the results directory")
    r = plain(["merge", os.path.join(tmp, "nowhere.json")])
    check(r.returncode == 2 and "rodend: error" in r.stderr, f"merge of a missing study: {r.returncode} {r.stderr}")

    if MPIRUN:
        for threads in ("1", "2"):
            root = os.path.join(tmp, f"mpi{threads}")
            r = mpirun(2, ["run", study, "--threads", threads, "--results-root", root])
            check(r.returncode == 0, f"mpirun -np 2 --threads {threads}: {r.returncode} {r.stderr}")
            check("2 MPI ranks" in r.stderr, f"mpirun -np 2: not distributed: {r.stderr}")
            assert_same_results(res("one"), os.path.join(root, "grid"), f"1 thread vs mpirun -np 2 --threads {threads}")
        # three ranks on two cores (oversubscribed): two remote workers asking one request
        # ahead, the manager serving both; the same results
        r = mpirun(3, ["run", study, "--threads", "1", "--results-root", os.path.join(tmp, "np3"), "-q"])
        check(r.returncode == 0, f"mpirun -np 3: {r.returncode} {r.stderr}")
        assert_same_results(res("one"), res("np3"), "1 thread vs mpirun -np 3")
        # rank 0 decides what to run from the case files present: nothing, then one case
        r = mpirun(2, ["run", study, "--results-root", os.path.join(tmp, "mpi1")])
        check(r.returncode == 0 and "6 of 6 cases already complete, 0 to run" in r.stderr,
              f"mpirun resume of a complete study: {r.stderr}")
        os.remove(os.path.join(res("mpi1"), "cases", rows[4]["case_id"] + ".h5"))
        r = mpirun(2, ["run", study, "--results-root", os.path.join(tmp, "mpi1")])
        check(r.returncode == 0 and "5 of 6 cases already complete, 1 to run" in r.stderr,
              f"mpirun resume of one case: {r.stderr}")
        assert_same_results(res("one"), res("mpi1"), "1 thread vs mpirun resume")
        # one rank: exactly the plain behaviour
        r = mpirun(1, ["run", study, "--results-root", os.path.join(tmp, "np1"), "-q"])
        check(r.returncode == 0 and "MPI ranks" not in r.stderr, f"mpirun -np 1: {r.returncode} {r.stderr}")
        assert_same_results(res("one"), res("np1"), "1 thread vs mpirun -np 1")

        # a failing case is a failed record; the ranks go on; --rerun-failed works across ranks
        bad = write_study(os.path.join(tmp, "diverge.json"), {
            "name": "diverge",
            "scene": "gravity-drop",
            "integrator": {"method": "rk4", "step": 2e-5},
            "time": {"end": 0.03, "sample_interval": 1e-3},
            "grid": [{"key": "parameters.contact.stiffness_scale", "values": [1.0, 1e4, 0.5]}],
        })
        r = mpirun(2, ["run", bad, "--results-root", tmp])
        drows = read_summary(os.path.join(tmp, "diverge"))
        check(r.returncode == 1, f"mpirun divergent study: exit {r.returncode}, expected 1: {r.stderr}")
        check(drows[1]["status"] in ("non_finite_state", "penetration_limit"), f"statuses {drows}")
        n_ok = sum(x["status"] == "ok" for x in drows)
        r = mpirun(2, ["run", bad, "--results-root", tmp])
        check(r.returncode == 1 and "3 of 3 cases already complete" in r.stderr, f"mpirun keeps the failure: {r.stderr}")
        r = mpirun(2, ["run", bad, "--results-root", tmp, "--rerun-failed"])
        check(r.returncode == 1 and f"{n_ok} of 3 cases already complete, {3 - n_ok} to run" in r.stderr,
              f"mpirun --rerun-failed: {r.stderr}")
        check(stable(read_summary(os.path.join(tmp, "diverge"))) == stable(drows), "--rerun-failed changed the results")

        # bad input: exit 2 on every rank, one message
        r = mpirun(2, ["run", os.path.join(tmp, "nowhere.json"), "--results-root", tmp])
        check(r.returncode == 2 and r.stderr.count("rodend: error") == 1,
              f"mpirun bad input: exit {r.returncode}, stderr {r.stderr}")
        # a case file that cannot be written mid-run (the cases folder is replaced by a plain
        # file once the first case is done): the job ends with MPI_Abort and a message naming
        # the case; putting the folder back and rerunning the command completes the study
        slow = write_study(os.path.join(tmp, "slow.json"), {
            "name": "slow",
            "scene": "rod-end-kinematic",
            "integrator": {"method": "dopri5", "abs_tol": 1e-7, "rel_tol": 1e-7, "max_step": 1e-3},
            "time": {"end": 1.2, "sample_interval": 1e-4},
            "grid": [{"key": "parameters.contact.clearance", "linspace": [1e-4, 6e-4, 8]}],
        })
        ab = os.path.join(tmp, "abort")
        cases = os.path.join(ab, "slow", "cases")
        # each rank held (tests/faults/pause_rename.c) after its first case file, with cases
        # left to start, while the folder is replaced
        hold = Pause(tmp, 1)
        p = subprocess.Popen([MPIRUN, "--oversubscribe", "-np", "2", rodend_path(), "run", slow,
                              "--results-root", ab, "-q"], env=hold.env(MPI_ENV), text=True,
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, start_new_session=True)
        check(hold.wait(2, alive=lambda: p.poll() is None), "abort: the ranks were not held")
        os.rename(cases, cases + ".moved")
        open(cases, "w").close()
        hold.release()
        out, err = p.communicate(timeout=300)
        check(p.returncode != 0 and "cannot write" in err and "aborting the MPI job" in err
              and err.count("rodend: error: rank") >= 1,
              f"unwritable case file: exit {p.returncode}, {err}")
        os.remove(cases)
        os.rename(cases + ".moved", cases)
        r = mpirun(2, ["run", slow, "--results-root", ab])
        srows = read_summary(os.path.join(ab, "slow"))
        check(r.returncode == 0 and len(srows) == 8 and all(x["status"] == "ok" for x in srows)
              and "cases already complete" in r.stderr, f"resume after the abort: {r.returncode} {r.stderr}")
    else:
        print("distributed: no mpirun given: MPI checks skipped")
finish("distributed")
