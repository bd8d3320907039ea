"""A symbolic link at a case file's name (docs/testing.md, "Faults") is never read or written
through:

- `rodend merge` refuses it (exit 1, no summary written), naming the link and the one command
  that fixes it (`rodend run` on the study);
- `rodend run` (a resume) moves the link itself aside to <id>.h5.corrupt, reruns the case and
  ends as an undisturbed run; the link's target is unchanged, whether it is another copy of the
  same case's file (which reading through would have taken as complete) or a file of the user's.

    RODEND=build/rodend /usr/bin/python3 tests/cli/test_case_links.py"""
import glob
import os
import shutil
import tempfile

from common import assert_same_results, check, finish, run, write_study

with tempfile.TemporaryDirectory() as tmp:
    s = write_study(os.path.join(tmp, "links.json"), {
        "name": "links", "scene": "gravity-drop", "time": {"end": 0.01, "sample_interval": 1e-3},
        "grid": [{"key": "parameters.contact.restitution", "values": [0.3, 0.9]}]})
    ref = os.path.join(tmp, "ref")
    r = run(["run", s, "--results-root", ref, "-q"])
    check(r.returncode == 0, f"reference: {r.stderr}")
    root = os.path.join(tmp, "root")
    r = run(["run", s, "--results-root", root, "-q"])
    check(r.returncode == 0, f"first run: {r.stderr}")
    case = sorted(glob.glob(os.path.join(root, "links", "cases", "*.h5")))[0]

    for kind in ("copy of the case", "user's file"):
        summary = open(os.path.join(root, "links", "summary.h5"), "rb").read()
        target = os.path.join(tmp, "target.h5")
        if kind == "copy of the case":
            shutil.copy(case if os.path.exists(case) else glob.glob(case + ".corrupt*")[0], target)
        else:
            with open(target, "w") as f:
                f.write("precious: must not change\n")
        before = open(target, "rb").read()
        if os.path.lexists(case):
            os.remove(case)
        os.symlink(target, case)

        r = run(["merge", s, "--results-root", root])
        check(r.returncode == 1 and case in r.stderr and "symbolic link" in r.stderr and
              f"rodend run {s} --results-root {root}" in r.stderr,
              f"{kind}, merge: exit {r.returncode}, {r.stderr!r}")
        check(open(os.path.join(root, "links", "summary.h5"), "rb").read() == summary,
              f"{kind}: merge wrote a summary")

        r = run(["run", s, "--results-root", root])
        check(r.returncode == 0 and "symbolic link" in r.stderr and "moved to" in r.stderr,
              f"{kind}, run: exit {r.returncode}, {r.stderr!r}")
        check(os.path.isfile(case) and not os.path.islink(case),
              f"{kind}: the case file is not a regular file after the run")
        asides = glob.glob(case + ".corrupt*")
        check(any(os.path.islink(a) and os.readlink(a) == target for a in asides),
              f"{kind}: the link was not moved aside: {asides}")
        check(open(target, "rb").read() == before, f"{kind}: the link's target changed")
        assert_same_results(os.path.join(ref, "links"), os.path.join(root, "links"), kind)
        for a in asides:
            os.remove(a)
        os.remove(target)
finish("case links")
