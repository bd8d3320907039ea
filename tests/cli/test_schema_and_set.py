"""`rodend schema` and `rodend run --set` (issue 22).

- the schema is a valid JSON Schema (draft 2020-12) and every shipped study (studies/*.json,
  the regression studies) validates against it; typical mistakes do not;
- `--set key.path=value` replaces a value wherever the study wrote it (nested or dotted), is
  recorded in the written study.json and in the provenance, and changes the case;
- a wrong key path or a value of the wrong type is refused (exit 2, nothing written), naming
  the study file, the key and the expected type.

    test_schema_and_set.py REPO
"""
import glob
import json
import os
import shutil
import sys
import tempfile

import h5py
import jsonschema

from common import check, finish, run, write_study


def main():
    repo = sys.argv[1]
    r = run(["schema"])
    check(r.returncode == 0, f"rodend schema: {r.stderr}")
    schema = json.loads(r.stdout)
    check(schema["$schema"] == "https://json-schema.org/draft/2020-12/schema", "not draft 2020-12")
    jsonschema.Draft202012Validator.check_schema(schema)
    v = jsonschema.Draft202012Validator(schema)

    shipped = sorted(glob.glob(os.path.join(repo, "studies", "*.json")) +
                     glob.glob(os.path.join(repo, "tests", "regression", "studies", "*.json")))
    check(len(shipped) >= 20, f"only {len(shipped)} shipped studies found")
    for path in shipped:
        with open(path, encoding="utf-8") as f:
            doc = json.load(f)
        errors = [f"{'/'.join(map(str, e.absolute_path))}: {e.message}" for e in v.iter_errors(doc)]
        check(not errors, f"{os.path.basename(path)} does not validate: {errors[:3]}")

    base = {"scene": "gravity-drop", "time": {"end": 0.02, "sample_interval": 1e-3}}
    bad = {
        "unknown top-level key": dict(base, tiem={"end": 1}),
        "unknown integrator setting": dict(base, integrator={"abs_toll": 1e-6}),
        "wrong type": dict(base, integrator={"abs_tol": "1e-6"}),
        "unknown scene": dict(base, scene="gravity-fall"),
        "unknown method": dict(base, integrator={"method": "euler"}),
        "time without end": dict(base, time={"sample_interval": 1e-3}),
        "parameter of the wrong type": dict(base, parameters={"contact.clearance": "big"}),
        "unknown signal": dict(base, signals=["eccentricty"]),
        "grid axis without values": dict(base, grid=[{"key": "parameters.contact.clearance"}]),
        "grid key outside the sections": dict(base, grid=[{"key": "contact.clearance",
                                                          "values": [1e-4]}]),
        # the schema knows every scene's parameters (issue 32 item 6)
        "misspelled parameter": dict(base, parameters={"contact.clearence": 1e-4}),
        "misspelled nested parameter": dict(base, parameters={"contact": {"clearence": 1e-4}}),
        "wrong type under the nested form": dict(base, parameters={"contact": {"clearance": "x"}}),
        "misspelled grid key": dict(base, grid=[{"key": "parameters.contact.clearence",
                                                 "values": [1e-4]}]),
        "misspelled key in a zip": dict(base, grid=[{"zip": [
            {"key": "parameters.contact.clearance", "values": [1e-4]},
            {"key": "integrator.abs_toll", "values": [1e-6]}]}]),
        "another scene's parameter": dict(base, parameters={"actuator.bulk_modulus": 1e9}),
        "negative end time": dict(base, time={"end": -1, "sample_interval": 1e-3}),
        "misspelled design factor": dict(base, design={
            "method": "sobol", "size": 8, "seed": 1, "factors": [
                {"key": "parameters.contact.clearence", "distribution": "uniform",
                 "lower": 1e-4, "upper": 2e-4}]}),
    }
    good = {"nested parameters": dict(base, parameters={"contact": {"clearance": 1e-4}}),
            "dotted parameters": dict(base, parameters={"contact.clearance": 1e-4})}
    for what, doc in good.items():
        check(v.is_valid(doc), f"the schema refuses a good study: {what}")
    for what, doc in bad.items():
        check(not v.is_valid(doc), f"the schema accepts a study with a mistake: {what}")
    check(v.is_valid(dict(base, grid=[{"zip": [
        {"key": "parameters.contact.clearance", "linspace": [1e-4, 5e-4, 3]},
        {"key": "integrator.rel_tol", "logspace": [1e-8, 1e-6, 3]}]}])), "a zip grid is refused")

    tmp = tempfile.mkdtemp(prefix="rodend-set-")
    try:
        study = write_study(os.path.join(tmp, "drop.json"), {
            "name": "drop", "scene": "gravity-drop",
            "parameters": {"contact": {"clearance": 1e-4, "restitution": 0.8}},
            "integrator": {"method": "dopri5", "abs_tol": 1e-8, "rel_tol": 1e-8},
            "time": {"end": 0.3, "sample_interval": 1e-3}})
        root = os.path.join(tmp, "results")
        sets = ["--set", "parameters.contact.clearance=3e-4", "--set", "time.end=0.02",
                "--set", "integrator.method=rk4", "--set", "integrator.step=1e-5"]
        r = run(["run", study, "--results-root", root, "-q"] + sets)
        check(r.returncode == 0, f"run with --set: {r.returncode} {r.stderr}")
        out = os.path.join(root, "drop")
        with open(os.path.join(out, "study.json"), encoding="utf-8") as f:
            written = json.load(f)
        check(written["parameters"] == {"contact": {"restitution": 0.8},
                                        "contact.clearance": 3e-4},
              f"study.json parameters: {written['parameters']}")
        check(written["time"]["end"] == 0.02 and written["integrator"]["method"] == "rk4",
              f"study.json: {written}")
        check(v.is_valid(written), "the written study.json does not validate")
        with h5py.File(os.path.join(out, "summary.h5"), "r") as f:
            prov = json.loads(f.attrs["provenance_json"])
        check(prov.get("overrides") == [s for s in sets if s != "--set"],
              f"provenance overrides: {prov.get('overrides')}")
        case = glob.glob(os.path.join(out, "cases", "*.h5"))
        check(len(case) == 1, f"case files: {case}")
        with h5py.File(case[0], "r") as f:
            check(float(f["parameters"].attrs["contact.clearance"]) == 3e-4, "clearance not set")
            check(abs(float(f.attrs["t_reached_s"]) - 0.02) < 1e-12, "end time not set")
            check(json.loads(f.attrs["case_json"])["integrator"]["method"] == "rk4", "method")

        refused = [
            (["parameters.contact.clearence=1e-4"], "parameters.contact.clearence",
             "nearest: parameters.contact.clearance, expected a number [m]"),
            (["parameters.contact.clearance=\"big\""], "parameters.contact.clearance",
             "expected a number, got a string"),
            (["integrator.abs_toll=1e-6"], "integrator.abs_toll",
             "nearest: integrator.abs_tol, expected a number"),
            (["integrator.max_steps=1.5"], "integrator.max_steps", "expected an integer"),
            (["time.end=[1]"], "time.end", "expected a number, got an array"),
            (["tiem.end=1"], "tiem.end", "unknown key; expected one of"),
            (["parameters.contact.law=\"newton\""], "parameters.contact.law", "expected one of"),
            (["no-equals-sign"], "--set", "expected key.path=value"),
        ]
        for args, key, expected in refused:
            fresh = os.path.join(tmp, "refused")
            r = run(["run", study, "--results-root", fresh, "-q", "--set", args[0]])
            msg = r.stderr
            check(r.returncode == 2, f"--set {args[0]}: exit {r.returncode}, expected 2")
            check(study in msg, f"--set {args[0]}: the message does not name the file: {msg}")
            check(f"{key}:" in msg, f"--set {args[0]}: the message does not name {key}: {msg}")
            check(expected in msg, f"--set {args[0]}: expected '{expected}' in: {msg}")
            check(not os.path.exists(fresh), f"--set {args[0]}: something was written")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    finish("schema_and_set")


if __name__ == "__main__":
    main()
