"""Every configuration of tests/bad_inputs/calibrate/ is refused by `rodend calibrate` with
exit code 2, a message that names the file (the configuration or its record), the key path or
column and says what was expected, and nothing written (no results folder, no temporary one,
neither in the working directory nor beside the configuration). Then the results folder's
writer itself: an error while it writes leaves the earlier result as it was and no temporary
folder; a complete write replaces the earlier result whole."""
import json
import os
import shutil
import sys
import tempfile

from common import check, finish, run

corpus = sys.argv[1]
expected = json.load(open(os.path.join(corpus, "expected.json")))
files = sorted(f for f in os.listdir(corpus) if f.endswith(".json") and f != "expected.json")
check(sorted(expected) == files, f"expected.json does not list exactly the corpus: {files}")

for name in files:
    where, key, text = expected[name]
    with tempfile.TemporaryDirectory() as root:
        for f in os.listdir(corpus):  # a private copy: nothing may appear beside it either
            shutil.copy(os.path.join(corpus, f), root)
        before = sorted(os.listdir(root))
        r = run(["calibrate", os.path.join(root, name)], cwd=root)
        msg = r.stderr.strip()
        check(r.returncode == 2, f"{name}: exit code {r.returncode}, expected 2 ({msg})")
        check(where in msg, f"{name}: message does not name {where}: {msg}")
        check(key == "" or key in msg, f"{name}: message does not name '{key}': {msg}")
        check(text in msg, f"{name}: message lacks '{text}': {msg}")
        check("Traceback" not in msg, f"{name}: crash: {msg}")
        check(sorted(os.listdir(root)) == before,
              f"{name}: something was written: {set(os.listdir(root)) - set(before)}")


def results_folder():
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                    "python"))
    from rodend.calibration.output import ResultsFolder
    with tempfile.TemporaryDirectory() as root:
        target = os.path.join(root, "out")
        with ResultsFolder(target) as out:
            out.write_text("a.txt", "first")
        try:
            with ResultsFolder(target) as out:
                out.write_text("a.txt", "second")
                raise RuntimeError("a failure while writing")
        except RuntimeError:
            pass
        check(os.listdir(root) == ["out"], f"left behind: {os.listdir(root)}")
        check(open(os.path.join(target, "a.txt")).read() == "first",
              "a failed write changed the earlier result")
        with ResultsFolder(target) as out:
            out.write_text("b.txt", "third")
        check(os.listdir(root) == ["out"] and os.listdir(target) == ["b.txt"],
              f"a complete write did not replace the earlier result whole: {os.listdir(target)}")


results_folder()
finish("calibrate bad input")
