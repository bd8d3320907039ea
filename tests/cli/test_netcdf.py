"""Self-describing results (issue 22): the case and summary files open in netCDF tools as they
are. xarray (h5netcdf engine, no phony_dims) finds the `time` dimension of every history and
`units` on every variable; the summary is one xarray call from a pandas DataFrame equal to
summary.csv; the wear maps have latitude x longitude dimensions. Files of schema 1 (attribute
`unit`, no dimension scales) are still read: resume keeps them and `rodend compare` reads them.
"""
import glob
import math
import os
import shutil
import sys
import tempfile

import h5py
import numpy as np
import pandas as pd
import xarray as xr

from common import check, finish, read_summary, run, write_study


def open_signals(path):
    return xr.open_dataset(path, engine="h5netcdf", group="signals")


def main():
    tmp = tempfile.mkdtemp(prefix="rodend-netcdf-")
    try:
        study = write_study(os.path.join(tmp, "drop.json"), {
            "name": "drop", "scene": "gravity-drop",
            "integrator": {"method": "dopri5", "abs_tol": 1e-8, "rel_tol": 1e-8},
            "time": {"end": 0.05, "sample_interval": 1e-3},
            "grid": [{"key": "parameters.contact.clearance", "values": [2e-4, 5e-4]}]})
        root = os.path.join(tmp, "results")
        r = run(["run", study, "--results-root", root, "-q"])
        check(r.returncode == 0, f"run failed: {r.stderr}")
        out = os.path.join(root, "drop")
        cases = sorted(glob.glob(os.path.join(out, "cases", "*.h5")))
        check(len(cases) == 2, f"expected 2 case files, got {cases}")

        # --- a case file: time dimension, units and long_name on every variable
        ds = open_signals(cases[0])
        check("time" in ds.dims, f"no time dimension: {dict(ds.dims)}")
        check(ds.dims["time"] == 51, f"time has {ds.dims.get('time')} samples, expected 51")
        check("time" in ds.coords, "time is not a coordinate of the histories")
        with h5py.File(cases[0], "r") as f:
            check(int(f.attrs["schema_version"]) == 2, "schema_version is not 2")
            names = sorted(f["signals"].keys())
            check(sorted(list(ds.variables)) == names,
                  f"xarray sees {sorted(ds.variables)}, the file has {names}")
            for name in names:
                v = ds[name]
                check("units" in v.attrs and v.attrs["units"] != "", f"{name}: no units")
                check("long_name" in v.attrs, f"{name}: no long_name")
                check(v.dims[0] == "time", f"{name}: first dimension {v.dims}, expected time")
                if v.ndim == 2:
                    check(v.dims[1] == f"component{v.shape[1]}", f"{name}: dims {v.dims}")
                check(np.array_equal(v.values, f["signals"][name][()]), f"{name}: values differ")
        check(ds["ball_position"].attrs["units"] == "m", "ball_position is not in m")
        check(ds["time"].attrs["units"] == "s", "time is not in s")
        ds.close()

        # --- the summary: one call, a DataFrame equal to summary.csv
        df = xr.open_dataset(os.path.join(out, "summary.h5"), engine="h5netcdf",
                             group="summary").to_dataframe()
        csv = pd.read_csv(os.path.join(out, "summary.csv"), float_precision="round_trip")
        check(list(df.index) == list(csv["case_index"]), f"index {list(df.index)}")
        check(set(df.columns) == set(csv.columns) - {"case_index"},
              f"columns differ: {set(df.columns) ^ (set(csv.columns) - {'case_index'})}")
        for col in df.columns:
            a, b = df[col].to_numpy(), csv[col].to_numpy()
            if a.dtype.kind == "f":
                check(np.array_equal(a, b.astype(float), equal_nan=True), f"summary column {col}")
            elif a.dtype.kind in "iu":
                check(np.array_equal(a, b), f"summary column {col}")
            else:
                b = ["" if isinstance(x, float) and math.isnan(x) else str(x) for x in b]
                check([str(x) for x in a] == b, f"summary column {col}: {list(a)} vs {b}")
        check(list(csv["parameters.contact.clearance"].astype(str)) == ["0.0002", "0.0005"],
              "summary.csv does not write the clearances as 0.0002 and 0.0005")
        with h5py.File(os.path.join(out, "summary.h5"), "r") as f:
            g = f["summary"]
            check(g["max_penetration"].attrs["units"] == "m", "max_penetration units")
            check(g["parameters.contact.clearance"].attrs["units"] == "m", "clearance units")

        # --- wear maps: latitude x longitude, units everywhere
        wear = write_study(os.path.join(tmp, "wear.json"), {
            "name": "wear", "scene": "rod-end-kinematic",
            "parameters": {"wear.model": "archard"},
            "integrator": {"preset": "fast"},
            "time": {"end": 0.2, "sample_interval": 1e-2}})
        r = run(["run", wear, "--results-root", root, "-q"])
        check(r.returncode == 0, f"wear run failed: {r.stderr}")
        wear_case = glob.glob(os.path.join(root, "wear", "cases", "*.h5"))[0]
        w = xr.open_dataset(wear_case, engine="h5netcdf", group="wear")
        check(w["ball_depth"].dims == ("latitude", "longitude"), f"dims {w['ball_depth'].dims}")
        check("latitude" in w.coords and "longitude" in w.coords, "no latitude/longitude coords")
        for name in w.variables:
            check("units" in w[name].attrs, f"wear/{name}: no units")
        w.close()
        s = open_signals(wear_case)
        check("time" in s.dims and all("units" in s[n].attrs for n in s.variables),
              "wear case signals: no time dimension or units")
        s.close()

        # --- schema 1 files (unit, no scales) still read: resume keeps them, compare reads them
        old = os.path.join(tmp, "old", "drop")
        shutil.copytree(out, old)
        for path in glob.glob(os.path.join(old, "cases", "*.h5")) + [os.path.join(old, "summary.h5")]:
            # files of that time had no checksum header (the 512-byte user block): without it
            # the HDF5 part is the file as it was, which resume reads unchecked
            with open(path, "rb") as f:
                data = f.read()
            if data.startswith(b"RODEND-CHECKSUM"):
                with open(path, "wb") as f:
                    f.write(data[512:])
            with h5py.File(path, "r+") as f:
                f.attrs["schema_version"] = np.int32(1)
                for g in [f[k] for k in ("signals", "summary") if k in f]:
                    for name in g:
                        a = g[name].attrs
                        if "units" in a:
                            a["unit"] = a["units"]
                            del a["units"]
        r = run(["compare", out, old])
        check(r.returncode == 0, f"compare new vs schema-1 copy: {r.returncode} {r.stdout} {r.stderr}")
        before = {p: os.path.getmtime(p) for p in glob.glob(os.path.join(old, "cases", "*.h5"))}
        r = run(["run", study, "--results-root", os.path.join(tmp, "old"), "-q"])
        check(r.returncode == 0, f"resume over schema-1 files: {r.stderr}")
        after = {p: os.path.getmtime(p) for p in before}
        check(before == after, "resume reran cases whose schema-1 files were complete")
        # the figures' reader (the package's, which needs no compiled module)
        sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "python"))
        from rodend.study import open_study
        study = open_study(old)
        check(study.units["max_penetration"] == "m",
              f"plots read schema-1 summary units as {study.units['max_penetration']!r}")
        units = {study.cases()[0].unit(n) for n in ("eccentricity", "contact_force")}
        check(units == {"m", "N"}, f"plots read schema-1 signal units as {units}")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    finish("netcdf")


if __name__ == "__main__":
    main()
