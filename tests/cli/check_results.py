#!/usr/bin/python3
"""Checks results folders (results/<study>/) for what must never be stored:

- a NaN or an infinity in any /signals dataset of any case file;
- a case whose status is not `ok` or one of the known failure statuses, or a failed case
  without a message, or whose message does not give the time reached;
- a summary row without its case file, or a case file the summary does not list;
- a non-monotonic time signal, or a history that goes past t_reached_s.

Prints, per folder, the number of cases ok and failed with the failure reasons counted, and
exits 1 if any check failed.

    /usr/bin/python3 tests/cli/check_results.py results/extremes-gravity-drop [more folders]
    /usr/bin/python3 tests/cli/check_results.py --markdown results/extremes-*   # a table
"""
import collections
import csv
import glob
import os
import sys

import h5py
import numpy as np

STATUSES = {"ok", "step_budget_exhausted", "rhs_budget_exhausted", "step_size_underflow",
            "non_finite_state", "penetration_limit", "energy_residual_limit",
            "actuator_saturation", "internal_error"}


def text(v):
    return v.decode() if isinstance(v, bytes) else str(v)


def check_folder(folder):
    problems = []
    cases = sorted(glob.glob(os.path.join(glob.escape(folder), "cases", "*.h5")))
    summary = os.path.join(folder, "summary.csv")
    listed = {}
    if os.path.exists(summary):
        with open(summary, newline="") as f:
            for row in csv.DictReader(f):
                listed[row["case_id"]] = row
    else:
        problems.append(f"{folder}: no summary.csv")
    ids = {os.path.basename(c)[:-3] for c in cases}
    for cid in sorted(set(listed) - ids):
        problems.append(f"{folder}: summary lists {cid} but there is no case file")
    for cid in sorted(ids - set(listed)):
        if listed:
            problems.append(f"{folder}: case file {cid} is not in the summary")
    statuses = collections.Counter()
    scenes = []                 # several when the scene is a grid axis
    for path in cases:
        with h5py.File(path, "r") as f:
            status = text(f.attrs["status"])
            message = text(f.attrs["message"])
            scene = text(f.attrs["scene"])
            if scene not in scenes:
                scenes.append(scene)
            t_reached = float(f.attrs["t_reached_s"])
            statuses[status] += 1
            if status not in STATUSES:
                problems.append(f"{path}: unknown status {status!r}")
            if status != "ok" and ("t = " not in message and "t=" not in message):
                problems.append(f"{path}: failed ({status}) without the time reached: {message!r}")
            for name, ds in f["signals"].items():
                v = ds[()]
                bad = ~np.isfinite(v)
                if bad.any():
                    first = int(np.argwhere(bad)[0][0])
                    problems.append(f"{path}: /signals/{name} has {int(bad.sum())} non-finite "
                                    f"values (first at sample {first})")
            t = f["signals/time"][()] if "time" in f["signals"] else None
            if t is not None and t.size:
                if np.any(np.diff(t) <= 0):
                    problems.append(f"{path}: time is not increasing")
                if t[-1] > t_reached * (1 + 1e-12) + 1e-300 and status != "ok":
                    problems.append(f"{path}: history ends at {t[-1]} s, after t_reached {t_reached} s")
            row = listed.get(os.path.basename(path)[:-3])
            if row is not None and row["status"] != status:
                problems.append(f"{path}: status {status} but the summary says {row['status']}")
            if row is not None and "scene" in row and row["scene"] != scene:
                problems.append(f"{path}: scene {scene} but the summary says {row['scene']}")
    return ", ".join(scenes), len(cases), statuses, problems


def main(argv):
    markdown = "--markdown" in argv
    folders = [a for a in argv if a != "--markdown"]
    if not folders:
        print(__doc__, file=sys.stderr)
        return 2
    all_problems = []
    table = []
    for folder in folders:
        scene, n, statuses, problems = check_folder(folder.rstrip("/"))
        all_problems += problems
        failed = {k: v for k, v in sorted(statuses.items()) if k != "ok"}
        reasons = ", ".join(f"{k} {v}" for k, v in failed.items()) or "-"
        table.append((os.path.basename(folder.rstrip("/")), scene, n, statuses.get("ok", 0),
                      sum(failed.values()), reasons))
    if markdown:
        print("| study | scene | cases | ok | failed | failure reasons (count) |")
        print("|---|---|---|---|---|---|")
        for row in table:
            print("| " + " | ".join(str(x) for x in row) + " |")
    else:
        for row in table:
            print(f"{row[0]} ({row[1]}): {row[2]} cases, {row[3]} ok, {row[4]} failed: {row[5]}")
    for p in all_problems:
        print("PROBLEM:", p, file=sys.stderr)
    print(f"{len(all_problems)} problem(s)" if all_problems else "no NaN/Inf, every status known",
          file=sys.stderr)
    return 1 if all_problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
