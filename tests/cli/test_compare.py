"""rodend compare: identical inputs -> 0; a 2 % change in one metric with a 1 % tolerance -> 1,
naming the metric and the case; a missing case -> 1; a changed history -> 1; an unreadable file
-> 2; a tolerance file with an unknown metric -> 2 (no traceback, the file named)."""
import json
import os
import shutil
import tempfile

import h5py

from common import check, finish, reseal, run, write_study

with tempfile.TemporaryDirectory() as tmp:
    study = write_study(os.path.join(tmp, "c.json"), {
        "name": "c", "scene": "gravity-drop",
        "integrator": {"method": "dopri5", "abs_tol": 1e-8, "rel_tol": 1e-8},
        "time": {"end": 0.05, "sample_interval": 1e-4},
        "grid": [{"key": "parameters.contact.clearance", "values": [2e-4, 5e-4]}]})
    r = run(["run", study, "--results-root", tmp, "-q"])
    check(r.returncode == 0, f"run: {r.stderr}")
    a = os.path.join(tmp, "c")

    def copy(name):
        dst = os.path.join(tmp, name)
        shutil.copytree(a, dst)
        return dst

    r = run(["compare", a, copy("same")])
    check(r.returncode == 0 and "equal within tolerance" in r.stdout, f"identical: {r.returncode} {r.stdout}")

    # a 2 % change of one metric of one case, with a 1 % tolerance on that metric
    b = copy("metric")
    with h5py.File(os.path.join(b, "summary.h5"), "r+") as f:
        col = f["summary/max_contact_force"]
        v = col[()]
        v[1] *= 1.02
        col[...] = v
        case = f["summary/case_id"][1].decode()
    reseal(os.path.join(b, "summary.h5"))  # a changed result, not a damaged file
    tol = os.path.join(tmp, "tol.json")
    json.dump({"metrics": {"max_contact_force": {"rel": 0.01, "abs": 0.0}}}, open(tol, "w"))
    r = run(["compare", a, b, "--tolerances", tol])
    check(r.returncode == 1, f"2% change: exit {r.returncode}\n{r.stdout}")
    check("max_contact_force" in r.stdout and case in r.stdout, f"report does not name metric and case:\n{r.stdout}")
    check(r.stdout.count("DIFF") == 1, f"exactly one difference expected:\n{r.stdout}")
    json.dump({"metrics": {"max_contact_force": {"rel": 0.03, "abs": 0.0}}}, open(tol, "w"))
    r = run(["compare", a, b, "--tolerances", tol])
    check(r.returncode == 0, f"2% change with 3% tolerance: exit {r.returncode}\n{r.stdout}")

    # a missing case: compare against a study with one case only
    one = write_study(os.path.join(tmp, "one.json"), {
        "name": "one", "scene": "gravity-drop",
        "integrator": {"method": "dopri5", "abs_tol": 1e-8, "rel_tol": 1e-8},
        "time": {"end": 0.05, "sample_interval": 1e-4},
        "grid": [{"key": "parameters.contact.clearance", "values": [2e-4]}]})
    run(["run", one, "--results-root", tmp, "-q"])
    r = run(["compare", a, os.path.join(tmp, "one")])
    check(r.returncode == 1 and "missing" in r.stdout, f"missing case: {r.returncode}\n{r.stdout}")

    # a changed history before the first impact (pointwise)
    h = copy("history")
    cases = sorted(os.listdir(os.path.join(h, "cases")))
    with h5py.File(os.path.join(h, "cases", cases[0]), "r+") as f:
        d = f["signals/ball_position"]
        v = d[()]
        v[5, 1] += 1e-6
        d[...] = v
    reseal(os.path.join(h, "cases", cases[0]))
    r = run(["compare", a, h])
    check(r.returncode == 1 and "ball_position[1]" in r.stdout, f"history change: {r.returncode}\n{r.stdout}")
    r = run(["compare", a, h, "--summary-only"])
    check(r.returncode == 0, f"summary-only ignores histories: {r.returncode}\n{r.stdout}")

    # errors: an unreadable summary, a folder that is not a study, an unknown metric name
    bad = copy("bad")
    open(os.path.join(bad, "summary.h5"), "wb").write(b"not hdf5 at all")
    r = run(["compare", a, bad])
    check(r.returncode == 2 and "summary.h5" in r.stderr, f"unreadable: {r.returncode} {r.stderr}")
    r = run(["compare", a, tmp])
    check(r.returncode == 2 and "not a rodend study" in r.stderr, f"not a study: {r.returncode} {r.stderr}")
    json.dump({"metrics": {"max_contact_farce": {"rel": 0.01}}}, open(tol, "w"))
    r = run(["compare", a, a, "--tolerances", tol])
    check(r.returncode == 2 and "metrics.max_contact_farce" in r.stderr and "tol.json" in r.stderr,
          f"unknown metric: {r.returncode} {r.stderr}")
finish("compare")
