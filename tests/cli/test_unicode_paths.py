"""Paths with spaces and non-ASCII characters work: the study file's path, the results root and
the study name (hence the results folder); dry run, run, resume, results-dir and merge."""
import glob
import os
import tempfile

import h5py
import numpy as np

from common import check, finish, read_summary, run, write_study

with tempfile.TemporaryDirectory() as tmp:
    where = os.path.join(tmp, "études de cas", "rotule à jeu ü")
    os.makedirs(where)
    name = "chute libre – Δc µm 日本"
    study = write_study(os.path.join(where, "étude n° 1.json"), {
        "name": name,
        "scene": "gravity-drop",
        "time": {"end": 0.01, "sample_interval": 1e-3},
        "grid": [{"key": "parameters.contact.clearance", "values": [1e-4, 5e-4]}],
    })
    root = os.path.join(tmp, "résultats avec espaces")
    r = run(["run", study, "--results-root", root, "--dry-run"])
    check(r.returncode == 0 and "2 case(s)" in r.stdout, f"dry run: {r.returncode} {r.stderr}")
    r = run(["results-dir", study, "--results-root", root])
    expected = os.path.join(root, name)
    check(r.returncode == 0 and r.stdout.strip() == expected,
          f"results-dir: {r.stdout!r}, expected {expected!r}")
    r = run(["run", study, "--results-root", root, "-q"])
    check(r.returncode == 0, f"run: {r.returncode} {r.stderr}")
    rows = read_summary(expected)
    check([x["status"] for x in rows] == ["ok", "ok"], f"statuses: {rows}")
    files = sorted(glob.glob(os.path.join(glob.escape(expected), "cases", "*.h5")))
    check(len(files) == 2, f"case files: {files}")
    for path in files:
        with h5py.File(path, "r") as f:
            check(f.attrs["study_file"] == study, f"study_file attribute: {f.attrs['study_file']!r}")
            check(np.all(np.isfinite(f["signals/time"][()])), "time signal")
    with h5py.File(os.path.join(expected, "summary.h5"), "r") as f:
        check(f.attrs["study_file"] == study, "summary study_file attribute")
    # resume from the same paths, then merge from the results folder
    r = run(["run", study, "--results-root", root])
    check(r.returncode == 0 and "2 of 2 cases already complete" in r.stderr, f"resume: {r.stderr}")
    r = run(["merge", expected])
    check(r.returncode == 0, f"merge: {r.returncode} {r.stderr}")
    # a bad study under such a path: the message names the path as given
    bad = write_study(os.path.join(where, "mauvais ü.json"), {"scene": "gravity-drop", "time": {}})
    r = run(["run", bad, "--results-root", root])
    check(r.returncode == 2 and bad in r.stderr, f"bad study message: {r.stderr}")
finish("unicode paths")
