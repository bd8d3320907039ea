"""rodend.open_results and the Python calls' answers (issue 35 items 4, 5 and 6), on a 3 x 3
product study, a zip group with a sampled design, and a one-case run, all of gravity-drop:

- lazy (item 4): open_results and .histories read no case file (a damaged one is not seen
  until its values are accessed, and then raises CorruptFile naming it); a grid point's
  values, loaded alone, are its case file's; Results.case reads one case;
- coordinates (item 5): the summary as a Dataset over the two grid axes (a value at a grid
  point is that case's summary row); a zip group and a sampled design each one dimension with
  their keys as coordinates; a case's grid values are scalar coordinates of its signals;
  components labelled x, y, z (the chambers rear, front); Conventions CF-1.8; short
  long_names with the files' sentence in description;
- dimension names without dots: `clearance`, `restitution`, `design_sample` (`sample` is the
  Datasets' own), `rel_tol`, so `.sel(clearance=...)` works; the full key path in the attribute
  `key`; the dotted names still select (an indexed alias marked deprecated); two keys of the
  same last part are told apart by the part before it;
- honest answers (item 6): an unknown signal, metric, scene or case names the nearest valid
  names; run_study takes a dict (same case ids as the file, no file left behind); numpy
  scalars and arrays in parameters and set=; threads="2" and other wrong types are refused
  with TypeError naming the argument; threads beyond 1..4096, 2**31 included, with InputError
  naming threads.
"""
import glob
import os
import shutil
import sys
import tempfile
import traceback

import h5py
import numpy as np

from common import check, finish, write_study

import rodend  # noqa: E402  (PYTHONPATH=<repo>/python)

C = [2e-4, 3e-4, 4e-4]
R = [0.5, 0.7, 0.9]
BASE = {"scene": "gravity-drop", "time": {"end": 0.01, "sample_interval": 1e-3},
        "integrator": {"method": "dopri5", "abs_tol": 1e-8, "rel_tol": 1e-8},
        "signals": ["eccentricity", "ball_position"]}
GRID = [{"key": "parameters.contact.clearance", "values": C},
        {"key": "parameters.contact.restitution", "values": R}]


def raises(call, kinds, *words):
    """True when call() raises one of `kinds` whose message holds every word."""
    try:
        call()
    except kinds as e:
        ok = all(w in str(e) for w in words)
        check(ok, f"message {e!r} lacks {words}")
        return ok
    except Exception as e:  # noqa: BLE001
        check(False, f"expected {kinds} with {words}, got {type(e).__name__}: {e}")
        return False
    check(False, f"accepted: expected {kinds} with {words}")
    return False


def lazy(tmp, folder):
    res = rodend.open_results(folder)
    s = res.summary
    damaged = res.case_file(s.case_id[8])  # the last grid point
    with open(damaged, "r+b") as fh:  # one byte of its histories' area flipped
        fh.seek(-100, os.SEEK_END)
        b = fh.read(1)
        fh.seek(-100, os.SEEK_END)
        fh.write(bytes([b[0] ^ 0xFF]))
    res = rodend.open_results(folder)
    h = res.histories  # reads no case file: the damaged one is not seen yet
    check(h["eccentricity"].shape == (3, 3, 11), f"shape {h['eccentricity'].shape}")
    one = h["eccentricity"].sel(clearance=C[2], restitution=R[1]).values
    row = s[(s["parameters.contact.clearance"] == C[2]) &
            (s["parameters.contact.restitution"] == R[1])].iloc[0]
    with h5py.File(res.case_file(row.case_id), "r") as f:
        check(np.array_equal(one, f["signals/eccentricity"][()]), "lazy value != case file")
    check(np.array_equal(res.case(row.case_id)["eccentricity"].values, one), "case() value")
    raises(lambda: h["eccentricity"].isel(clearance=2).load(),
           rodend.CorruptFile, s.case_id[8])


def coordinates(folder):
    res = rodend.open_results(folder)
    ds = res.summary_dataset
    check(ds["max_penetration"].dims == ("clearance", "restitution"),
          f"summary dims {ds['max_penetration'].dims}")
    check(list(ds["restitution"].values) == R, "grid coordinate")
    s = res.summary
    for _, row in s.iterrows():
        at = {"clearance": row["parameters.contact.clearance"],
              "restitution": row["parameters.contact.restitution"]}
        check(ds["case_id"].sel(at).item() == row.case_id, "summary Dataset row")
        check(ds["max_penetration"].sel(**at).item() == row.max_penetration, "summary value")
    c = res.case(int(s.case_index[5]))
    check(c["eccentricity"].coords["clearance"].item() == C[1] and
          c["eccentricity"].coords["restitution"].item() == R[2],
          "a case's grid values as scalar coordinates")
    check(res.case({"clearance": C[1], "restitution": R[2]}).attrs["case_id"] ==
          c.attrs["case_id"], "case() by coordinate names")
    h = res.histories
    for d in (ds, h, c, rodend.run_case("gravity-drop", time={"end": 1e-3,
                                                             "sample_interval": 1e-3}).to_xarray()):
        check(d.attrs.get("Conventions") == "CF-1.8", f"Conventions {d.attrs}")
        check(list(d["ball_position"].coords["component3"].values) == ["x", "y", "z"]
              if "ball_position" in d else True, "components labelled")
    a = ds["clearance"].attrs
    check(a["long_name"] == "contact clearance" and a["units"] == "m" and
          len(a["description"]) > len(a["long_name"]), f"coordinate attrs {a}")
    with h5py.File(res.case_file(s.case_id[0]), "r") as f:
        sentence = f["signals/eccentricity"].attrs["long_name"]
    e = h["eccentricity"].attrs
    check(e["long_name"] == "eccentricity" and e["description"] == sentence, f"attrs {e}")
    from rodend import naming
    check(naming.components("chamber_pressures", 2) == ("chamber", ["rear", "front"]), "chamber")


def dimension_names(folder):
    """Dimensions named without dots, the key path an attribute, the dotted name an alias."""
    res = rodend.open_results(folder)
    check([d[0] for d in res.dimensions()] == ["clearance", "restitution"],
          f"dimensions {res.dimensions()}")
    for d in (res.summary_dataset, res.histories["eccentricity"]):
        check(d["clearance"].attrs["key"] == "parameters.contact.clearance", "attribute key")
        old = d.sel({"parameters.contact.clearance": C[2]})  # the alias still selects
        new = d.sel(clearance=C[2])
        check(old.sizes == new.sizes and float(old["clearance"]) == C[2], "alias selects")
        check("deprecated" in d["parameters.contact.clearance"].attrs and
              "clearance" in d["parameters.contact.clearance"].attrs["deprecated"],
              "the alias says it is deprecated")
    from rodend import naming
    names = naming.coordinate_names(["parameters.geometry.clearance",
                                     "parameters.contact.clearance", "time.end",
                                     "design.sample", "integrator.rel_tol"], taken={"sample"})
    check(names == {"parameters.geometry.clearance": "geometry_clearance",
                    "parameters.contact.clearance": "contact_clearance", "time.end": "end",
                    "design.sample": "design_sample", "integrator.rel_tol": "rel_tol"},
          f"coordinate_names {names}")


def stopped_early(tmp):
    """A case that stops early is NaN past its end, its samples those of its file."""
    doc = dict(BASE, name="budget", grid=[{"key": "integrator.max_steps", "values": [100000, 8]}])
    rc, folder = rodend.run_study(doc, results_root=os.path.join(tmp, "budget"))
    res = rodend.open_results(folder)
    s = res.summary
    check(rc == 1 and list(s.status) == ["ok", "step_budget_exhausted"], f"{rc} {list(s.status)}")
    h = res.histories
    with h5py.File(res.case_file(s.case_id[1]), "r") as f:
        part = f["signals/eccentricity"][()]
    e = h["eccentricity"].sel(max_steps=8).values
    check(0 < len(part) < 11 and np.array_equal(e[:len(part)], part) and
          np.isnan(e[len(part):]).all(), f"stopped case {e} vs {part}")
    check(np.array_equal(h["time"].values, np.arange(11) * 1e-3), "time coordinate")


def zip_and_design(tmp):
    doc = dict(BASE, name="zipdesign",
               grid=[{"zip": [{"key": "parameters.contact.clearance", "values": [2e-4, 4e-4]},
                              {"key": "parameters.contact.restitution", "values": [0.9, 0.5]}]}],
               design={"method": "monte-carlo", "size": 3, "seed": 7, "factors": [
                   {"key": "integrator.rel_tol", "distribution": "uniform",
                    "lower": 1e-9, "upper": 1e-8}]})
    rc, folder = rodend.run_study(doc, threads=2, results_root=os.path.join(tmp, "zd"))
    check(rc == 0, f"zip/design study exit {rc}")
    res = rodend.open_results(folder)
    ds = res.summary_dataset
    check(ds["status"].dims == ("clearance", "design_sample"),
          f"zip/design dims {ds['status'].dims}")
    check(list(ds["restitution"].values) == [0.9, 0.5], "zip coordinate")
    tol = ds["rel_tol"]
    s = res.summary
    check(tol.dims == ("design_sample",) and tol.attrs["key"] == "integrator.rel_tol" and
          np.array_equal(tol.values, s["integrator.rel_tol"].to_numpy()[:3]), "factor coordinate")
    h = res.histories
    check(h["eccentricity"].dims == ("clearance", "design_sample", "time"),
          f"histories dims {h['eccentricity'].dims}")


def honest(tmp, study, folder):
    raises(lambda: rodend.open_results(folder, signals=["eccentricty"]), ValueError,
           "eccentricty", "nearest: eccentricity")
    raises(lambda: rodend.open_results(folder, signals=["contact_force"]), ValueError,
           "contact_force", "recorded")
    case = rodend.run_case("gravity-drop", {"contact.clearance": np.float32(2e-4)},
                           time={"end": np.float64(2e-3), "sample_interval": 1e-3})
    check(case.parameters["contact.clearance"]["value"] == float(np.float32(2e-4)), "float32")
    raises(lambda: case.metrics["max_penetraton"], KeyError, "nearest: max_penetration")
    raises(lambda: case.signals["eccentricty"], KeyError, "nearest: eccentricity")
    # the Datasets too (xarray's own KeyError named only the key)
    res = rodend.open_results(folder)
    raises(lambda: res.histories["eccentricty"], KeyError, "nearest: eccentricity")
    raises(lambda: res.summary_dataset["max_penetraton"], KeyError, "nearest: max_penetration")
    raises(lambda: case.to_xarray()["eccentricty"], KeyError, "nearest: eccentricity")
    check(float(res.histories["eccentricity"].max()) > 0, "a known variable of the Dataset")
    raises(lambda: rodend.parameters("gravity-drp"), ValueError, "nearest: gravity-drop")
    raises(lambda: rodend.open_results(folder).case("0000"), KeyError, "case id")
    # run_study takes the study as a dict: the same cases as the file, nothing left behind
    root = os.path.join(tmp, "dict")
    doc = dict(BASE, name="product", grid=[dict(GRID[0], values=np.array(C)), GRID[1]])
    rc, got = rodend.run_study(doc, threads=np.int64(2), results_root=root)
    check(rc == 0 and os.listdir(root) == ["product"], f"dict study: {rc} {os.listdir(root)}")
    ids = lambda f: sorted(os.path.basename(p) for p in glob.glob(os.path.join(f, "cases", "*")))
    check(ids(got) == ids(folder) and len(ids(got)) == 9, "dict study cases differ")
    rc, again = rodend.run_study(study, results_root=os.path.join(tmp, "set"),
                                 set={"time.end": np.float32(0.005),
                                      "grid": [{"key": "parameters.contact.clearance",
                                                "values": np.array([2e-4, 3e-4])}]})
    check(rc == 0 and len(rodend.open_results(again).summary) == 2, "numpy in set=")
    for kw, word in (({"threads": "2"}, "threads"), ({"threads": 2.0}, "threads"),
                     ({"results_root": 3}, "results_root"), ({"rerun_failed": "no"},
                                                             "rerun_failed"),
                     ({"set": "time.end=1"}, "set")):
        raises(lambda: rodend.run_study(study, **kw), TypeError, word)
    # beyond a C int: named like 0 or 5000 are (main printed pybind's signature dump)
    for n in (2 ** 31, 2 ** 63, -2 ** 31 - 1, np.int64(2 ** 40)):
        raises(lambda: rodend.run_study(study, threads=n), rodend.InputError, "1 to 4096")
    raises(lambda: rodend.run_case("gravity-drop", time=[0.1, 1e-3]), TypeError, "time")


def item(name, call, *args):
    try:
        call(*args)
    except Exception:  # noqa: BLE001  (one item's failure does not hide the others')
        check(False, f"{name}: {traceback.format_exc()}")


def main():
    tmp = tempfile.mkdtemp(prefix="rodend-pyres-")
    try:
        study = write_study(os.path.join(tmp, "product.json"), dict(BASE, name="product",
                                                                    grid=GRID))
        rc, folder = rodend.run_study(study, threads=2, results_root=os.path.join(tmp, "res"))
        check(rc == 0, f"exit {rc}")
        copy = os.path.join(tmp, "damaged")
        shutil.copytree(folder, copy)
        item("coordinates (item 5)", coordinates, folder)
        item("dimension names without dots", dimension_names, folder)
        item("zip and design (item 5)", zip_and_design, tmp)
        item("honest answers (item 6)", honest, tmp, study, folder)
        item("lazy (item 4)", lazy, tmp, copy)
        item("lazy, a case that stopped early (item 4)", stopped_early, tmp)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    finish("python_results")


if __name__ == "__main__":
    sys.exit(main())
