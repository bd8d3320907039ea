"""The Python module rodend (issue 22), under /usr/bin/python3 with PYTHONPATH=<repo>/python.

- run_case returns the histories as numpy arrays and the metrics as a dict and writes nothing
  (the working directory stays empty); with write= it writes the same case file rodend run
  writes (same id, bitwise-equal histories);
- the free fall before the first contact matches the analytic one (sqrt(2 c / g));
- bad input raises rodend.InputError with the command line's message, never a crash;
- run_study + open_results: the summary DataFrame equals summary.csv, the histories are an
  xarray.Dataset over the grid axes (a zip group is one dimension) and time, with units.
"""
import glob
import json
import math
import os
import shutil
import sys
import tempfile

import h5py
import numpy as np
import pandas as pd

from common import check, finish, run, write_study

import rodend  # noqa: E402  (PYTHONPATH=<repo>/python)


def main():
    tmp = tempfile.mkdtemp(prefix="rodend-python-")
    cwd = os.getcwd()
    try:
        os.chdir(tmp)
        c = 4e-4
        case = rodend.run_case("gravity-drop", {"contact.clearance": c},
                               integrator={"method": "dopri5", "abs_tol": 1e-9, "rel_tol": 1e-9},
                               time={"end": 0.03, "sample_interval": 1e-3})
        check(os.listdir(tmp) == [], f"run_case wrote {os.listdir(tmp)}")
        check(case.status == "ok", case.status)
        t = case.signals["time"]
        check(isinstance(t, np.ndarray) and t.shape == (31,), f"time {type(t)} {t.shape}")
        check(case.signals["ball_position"].shape == (31, 3), "ball_position shape")
        check(case.units["ball_position"] == "m", "units")
        check(isinstance(case.metrics, dict) and "first_contact_time" in case.metrics, "metrics")
        tc = case.metrics["first_contact_time"]
        check(abs(tc / math.sqrt(2 * c / 9.81) - 1) < 1e-6, f"first contact {tc}")
        # before the contact the ball falls freely: y = -g t^2 / 2
        free = t < tc
        y = case.signals["ball_position"][free, 1]
        check(np.allclose(y, -0.5 * 9.81 * t[free] ** 2, rtol=1e-7, atol=1e-15), "free fall")
        ds = case.to_xarray()
        check("time" in ds.dims and ds["ball_position"].attrs["units"] == "m", "to_xarray")

        # write= writes the case file rodend run writes
        path = os.path.join(tmp, "one.h5")
        written = rodend.run_case("gravity-drop", {"contact.clearance": c},
                                  integrator={"method": "dopri5", "abs_tol": 1e-9,
                                              "rel_tol": 1e-9},
                                  time={"end": 0.03, "sample_interval": 1e-3}, write=path)
        check(written.case_id == case.case_id, "same case, different id")
        with h5py.File(path, "r") as f:
            check(f.attrs["case_id"] == case.case_id, "case file id")
            for n, v in case.signals.items():
                check(np.array_equal(f["signals"][n][()], v), f"case file signal {n}")
        study = write_study(os.path.join(tmp, "same.json"), {
            "scene": "gravity-drop", "parameters": {"contact.clearance": c},
            "integrator": {"method": "dopri5", "abs_tol": 1e-9, "rel_tol": 1e-9},
            "time": {"end": 0.03, "sample_interval": 1e-3}})
        r = run(["run", study, "--results-root", os.path.join(tmp, "cli"), "-q"])
        check(r.returncode == 0, r.stderr)
        check(os.path.isfile(os.path.join(tmp, "cli", "same", "cases", case.case_id + ".h5")),
              "rodend run gives the case another id than run_case")

        # bad input: InputError with the command line's message
        bad = write_study(os.path.join(tmp, "bad.json"), {
            "scene": "gravity-drop", "parameters": {"contact.clearance": "big"},
            "time": {"end": 0.03, "sample_interval": 1e-3}})
        r = run(["run", bad, "--results-root", os.path.join(tmp, "bad"), "-q"])
        cli_message = r.stderr.strip().removeprefix("rodend: error: ")
        try:
            rodend.run_study(bad, results_root=os.path.join(tmp, "bad"))
            check(False, "run_study accepted a bad study")
        except rodend.InputError as e:
            check(str(e) == cli_message, f"message differs from the CLI's:\n{e}\n{cli_message}")
            check(isinstance(e, ValueError), "InputError is not a ValueError")
        for call, expected in [
            (lambda: rodend.run_case("gravity-fall"), "unknown scene"),
            (lambda: rodend.run_case("gravity-drop", {"contact.clearence": 1e-4}),
             "parameters.contact.clearence: unknown parameter"),
            (lambda: rodend.run_case("gravity-drop", time={"end": -1, "sample_interval": 1e-3}),
             "time.end"),
            (lambda: rodend.run_case("gravity-drop", {"contact.clearance": float("nan")}),
             "Out of range float values are not JSON compliant"),
            (lambda: rodend.run_study(study, threads=0), "threads"),
        ]:
            try:
                call()
                check(False, f"accepted: expected an error with {expected!r}")
            except (rodend.InputError, ValueError) as e:
                check(expected in str(e), f"expected {expected!r} in {e}")
        # a study file that is not there: FileNotFoundError naming it, as open() would raise
        for call in (rodend.run_study, rodend.load_study):
            missing = os.path.join(tmp, "missing.json")
            try:
                call(missing)
                check(False, f"{call.__name__} accepted a missing study file")
            except FileNotFoundError as e:
                check(e.filename == missing, f"{call.__name__}: {e} does not name {missing}")

        # a study over a zip group and a plain axis
        grid = write_study(os.path.join(tmp, "grid.json"), {
            "name": "grid", "scene": "gravity-drop",
            "integrator": {"method": "dopri5", "abs_tol": 1e-8, "rel_tol": 1e-8},
            "time": {"end": 0.02, "sample_interval": 1e-3},
            "signals": ["eccentricity", "ball_position"],
            "grid": [{"zip": [{"key": "parameters.contact.clearance", "values": [2e-4, 4e-4]},
                              {"key": "parameters.contact.restitution", "values": [0.9, 0.5]}]},
                     {"key": "integrator.rel_tol", "values": [1e-8, 1e-9, 1e-10]}]})
        rc, folder = rodend.run_study(grid, threads=2, results_root=os.path.join(tmp, "py"))
        check(rc == 0, f"run_study exit {rc}")
        res = rodend.open_results(folder)
        csv = pd.read_csv(os.path.join(folder, "summary.csv"), float_precision="round_trip")
        check(list(res.summary.columns) == list(csv.columns), "summary columns")
        check(len(res.summary) == 6, "summary rows")
        for col in ("first_contact_time", "parameters.contact.clearance", "rhs_calls"):
            check(np.array_equal(res.summary[col].to_numpy(), csv[col].to_numpy()), col)
        check(res.summary.attrs["units"]["first_contact_time"] == "s", "summary units")
        h = res.histories
        check(h["eccentricity"].dims == ("clearance", "rel_tol", "time"),
              f"dims {h['eccentricity'].dims}")
        check(h["ball_position"].dims[-1] == "component3", "component dim")
        check(h["eccentricity"].attrs["units"] == "m", "history units")
        check(list(h["restitution"].values) == [0.9, 0.5], "zip coordinate")
        check(h["clearance"].attrs["units"] == "m", "coordinate units")
        # each history is its case file's
        for _, row in res.summary.iterrows():
            with h5py.File(res.case_file(row.case_id), "r") as f:
                got = h["eccentricity"].sel(clearance=row["parameters.contact.clearance"],
                                            rel_tol=row["integrator.rel_tol"])
                check(np.array_equal(got.values, f["signals/eccentricity"][()]),
                      f"case {row.case_id} history")
        # the same study through the CLI gives the same files (the module is the CLI's code)
        r = run(["run", grid, "--results-root", os.path.join(tmp, "cli"), "-q"])
        check(r.returncode == 0, r.stderr)
        a = sorted(os.path.basename(p) for p in glob.glob(os.path.join(folder, "cases", "*.h5")))
        b = sorted(os.path.basename(p) for p in glob.glob(os.path.join(tmp, "cli", "grid", "cases",
                                                                        "*.h5")))
        check(a == b and len(a) == 6, f"case ids differ: {a} vs {b}")
        check(rodend.schema()["title"] == "rodend study", "schema")
        check("gravity-drop" in rodend.scenes(), "scenes")
    finally:
        os.chdir(cwd)
        shutil.rmtree(tmp, ignore_errors=True)
    finish("python")


if __name__ == "__main__":
    main()
