#!/usr/bin/env python3
"""Allocation failures and truncated files (issue 37 item 8, the fault-injection suite, in the
spirit of SQLite's malloc tests).

Allocations: tests/faults/failalloc.c, preloaded into `rodend run` of a short study, makes the
K-th allocation of rodend's own code fail, for a sample of K over the run's allocations (those of
HDF5 and libgomp, which do not survive a failure, are not failed: the shim says why). Whatever K,
the run must end in one of two ways:
  - exit 0 with the results of an undisturbed run (the failure was met and recovered from);
  - exit 2 with a message ("rodend: error: ..." or "rodend: out of memory ..."), after which a
    run without the failure completes to the undisturbed results;
never a crash (a signal), never exit 1 (an allocation failure is no case result), never a hang
(300 s, a failure bound), and nothing left behind that a resume does not accept.

Truncations: a case file and summary.h5 cut at a sample of lengths are fed to `rodend merge`,
`rodend compare` and `rodend report`: each reports the damage naming the file (exit 1 or 2),
none passes or crashes.

    test_alloc_failures.py LIBFAILALLOC [SAMPLES [--persistent]]   (default 40 values of K)

An allocation made inside nlohmann::json's destructor is never failed (the next one is instead):
the library allocates its work stack there, in a noexcept destructor, so a failure ends any
program in std::terminate (a limit of the library, like HDF5's and libgomp's; the shim's
RODEND_FAIL_ALLOC_SPARE).

--persistent also fails every allocation after the K-th, and reports (does not assert) how those
runs end: memory that never comes back is beyond what rodend can promise, since destroying a
JSON object or array (nlohmann::json 3.11) allocates a work stack, and a destructor that cannot
allocate during the unwinding ends the process (std::terminate).
"""
import os
import random
import shutil
import subprocess
import sys
import tempfile

from common import assert_same_results, check, finish, rodend_path, run, write_study

LIB = sys.argv[1]
SAMPLES = int(sys.argv[2]) if len(sys.argv) > 2 else 40
PERSISTENT = "--persistent" in sys.argv[3:]
STUDY = {"name": "alloc", "scene": "gravity-drop",
         "time": {"end": 0.02, "sample_interval": 1e-3},
         "grid": [{"key": "parameters.contact.clearance", "values": [1e-4, 3e-4, 5e-4]}]}


def spared_functions():
    """RODEND_FAIL_ALLOC_SPARE for the shim: the ranges of nlohmann::json's destructor
    (json_value::destroy) in the executable, whose work-stack allocation ends any program in
    std::terminate when it fails (a noexcept destructor). Empty when the symbols are stripped."""
    try:
        out = subprocess.run(["nm", "-S", "-C", "--defined-only", rodend_path()],
                             capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return ""
    ranges = []
    for line in out.splitlines():
        parts = line.split(None, 3)
        if len(parts) == 4 and "json_value::destroy" in parts[3]:
            lo, size = int(parts[0], 16), int(parts[1], 16)
            ranges.append(f"{lo:x}-{lo + size:x}")
    return ",".join(ranges)


SPARE = spared_functions()
check(SPARE != "", "no symbol json_value::destroy in the executable (stripped?): the shim cannot spare it")


def run_injected(path, root, k, persist):
    env = dict(os.environ, LD_PRELOAD=LIB, RODEND_FAIL_ALLOC=str(k),
               RODEND_FAIL_ALLOC_PERSIST="1" if persist else "0", RODEND_FAIL_ALLOC_SPARE=SPARE)
    try:
        return subprocess.run([rodend_path(), "run", path, "-q", "-j", "2", "--results-root",
                               root], capture_output=True, text=True, env=env, timeout=300)
    except subprocess.TimeoutExpired:
        return None


def count_allocations(path, root):
    env = dict(os.environ, LD_PRELOAD=LIB, RODEND_FAIL_ALLOC_COUNT="1")
    r = subprocess.run([rodend_path(), "run", path, "-q", "-j", "2", "--results-root", root],
                       capture_output=True, text=True, env=env, timeout=300)
    check(r.returncode == 0, f"counting run: exit {r.returncode}: {r.stderr}")
    return int(r.stderr.strip().splitlines()[-1].split()[1])


def check_outcome(r, k, persist, path, root, reference):
    what = f"allocation {k} failing{' and every one after' if persist else ''}"
    if r is None:
        check(False, f"{what}: the run hung (60 s)")
        return
    check(r.returncode in (0, 2), f"{what}: exit {r.returncode} (expected 0 or 2; a negative "
          f"code is a signal): {r.stderr[-400:]!r}")
    if r.returncode == 2:
        check("rodend" in r.stderr, f"{what}: exit 2 without a message: {r.stderr!r}")
        again = run(["run", path, "-q", "--results-root", root])
        check(again.returncode == 0, f"{what}: the resume afterwards exits {again.returncode}: "
              f"{again.stderr[-400:]!r}")
    if r.returncode in (0, 2):
        assert_same_results(reference, os.path.join(root, "alloc"), what)


def allocation_failures(tmp):
    path = write_study(os.path.join(tmp, "alloc.json"), STUDY)
    ref_root = os.path.join(tmp, "ref")
    r = run(["run", path, "-q", "--results-root", ref_root])
    check(r.returncode == 0, f"reference run: {r.stderr}")
    reference = os.path.join(ref_root, "alloc")
    total = count_allocations(path, os.path.join(tmp, "count"))
    print(f"the run makes {total} allocations")
    rng = random.Random(1)
    # the first allocations (start-up, loading), then a spread over the whole run
    ks = sorted(set(list(range(1, 11)) + [rng.randint(11, total) for _ in range(SAMPLES - 10)]))
    outcomes = {0: 0, 2: 0}
    for k in ks:
        root = os.path.join(tmp, f"k{k}")
        r = run_injected(path, root, k, False)
        if r is not None and r.returncode in outcomes:
            outcomes[r.returncode] += 1
        check_outcome(r, k, False, path, root, reference)
        shutil.rmtree(root, ignore_errors=True)
    print(f"{len(ks)} injected runs: {outcomes[0]} recovered (exit 0), {outcomes[2]} "
          "stopped with a message (exit 2)")
    if PERSISTENT:
        ends = {}
        for k in ks:
            r = run_injected(path, os.path.join(tmp, f"p{k}"), k, True)
            end = "hang" if r is None else f"exit {r.returncode}"
            ends[end] = ends.get(end, 0) + 1
        print(f"persistent (every allocation from K on failing), not asserted: {ends}")


def truncations(tmp):
    path = write_study(os.path.join(tmp, "trunc.json"), dict(STUDY, name="trunc"))
    a_root, b_root = os.path.join(tmp, "ta"), os.path.join(tmp, "tb")
    for root in (a_root, b_root):
        check(run(["run", path, "-q", "--results-root", root]).returncode == 0, "trunc run")
    a, b = os.path.join(a_root, "trunc"), os.path.join(b_root, "trunc")
    case = sorted(os.listdir(os.path.join(b, "cases")))[0]
    rng = random.Random(2)
    for name in (os.path.join("cases", case), "summary.h5"):
        target = os.path.join(b, name)
        original = open(target, "rb").read()
        for cut in sorted({0, 1, 511, 512, 513} | {rng.randrange(len(original)) for _ in range(6)}):
            with open(target, "wb") as f:
                f.write(original[:cut])
            # report reads the summary only; merge writes summary.h5 anew from the case files
            cmds = [["compare", a, b]] + ([["report", b]] if name == "summary.h5" else
                                          [["merge", b]])
            for cmd in cmds:
                r = run(cmd)
                check(r.returncode in (1, 2) and os.path.basename(target) in r.stderr + r.stdout,
                      f"{' '.join(cmd[:1])} of {name} cut at {cut} bytes: exit {r.returncode}, "
                      f"{(r.stderr + r.stdout)[-300:]!r}")
        with open(target, "wb") as f:
            f.write(original)


with tempfile.TemporaryDirectory() as tmp:
    allocation_failures(tmp)
    truncations(tmp)
finish("allocation failures and truncations")
