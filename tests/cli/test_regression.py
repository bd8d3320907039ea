"""Regression check of study outputs: every study in tests/regression/studies is rerun and
compared with its committed reference summary (rodend compare --summary-only)."""
import glob
import os
import sys
import tempfile

from common import check, finish, run

root = sys.argv[1]  # tests/regression
with tempfile.TemporaryDirectory() as tmp:
    for study in sorted(glob.glob(os.path.join(root, "studies", "*.json"))):
        name = os.path.basename(study)[:-5]
        r = run(["run", study, "--results-root", tmp, "-q", "--threads", "2"])
        check(r.returncode == 0, f"{name}: run failed: {r.stderr}")
        ref = os.path.join(root, "reference", name)
        check(os.path.exists(os.path.join(ref, "summary.h5")), f"{name}: no reference (regenerate)")
        c = run(["compare", ref, os.path.join(tmp, name), "--summary-only",
                 "--tolerances", os.path.join(root, "tolerances.json")])
        print(c.stdout.strip())
        check(c.returncode == 0, f"{name}: differs from its reference "
              f"(if intended: bash scripts/regenerate-regression.sh):\n{c.stdout}{c.stderr}")
finish("regression")
