#!/usr/bin/env python3
"""An overridden parameter's provenance says where its value came from (issue 35 item 6): the
study file's "parameters" (source "study"), a grid axis ("grid"), `--set` ("set"), with the
scene's default kept under "default" (value, source, note). Before, an override kept the
default's provenance: a clearance set to 0.3 mm said "source: thesis" for the thesis's 0.5 mm.

Checked in the case files' parameters_json (as `rodend run` writes them) and in
rodend.run_case(...).parameters (Python)."""
import json
import os
import subprocess
import tempfile

import h5py

import rodend
from common import check, finish, rodend_path, write_study


def case_parameters(folder):
    out = []
    for name in sorted(os.listdir(os.path.join(folder, "cases"))):
        with h5py.File(os.path.join(folder, "cases", name), "r") as f:
            a = f.attrs["parameters_json"]
            out.append(json.loads(a.decode() if isinstance(a, bytes) else a))
    return out


def check_leaf(leaf, source, note_has, default_value, default_source, what):
    check(leaf["source"] == source and all(n in leaf["note"] for n in note_has),
          f"{what}: source {leaf.get('source')!r}, note {leaf.get('note')!r}; expected "
          f"{source!r} with {note_has}")
    d = leaf.get("default", {})
    check(d.get("value") == default_value and d.get("source") == default_source,
          f"{what}: the default kept is {d}; expected {default_value} ({default_source})")


def main():
    defaults = rodend.parameters("gravity-drop")
    with tempfile.TemporaryDirectory() as root:
        study = write_study(os.path.join(root, "prov.json"), {
            "name": "prov", "scene": "gravity-drop",
            "parameters": {"contact": {"restitution": 0.7}},
            "time": {"end": 0.01, "sample_interval": 1e-3},
            "grid": [{"key": "parameters.contact.clearance", "values": [2e-4, 3e-4]}]})
        setting = "parameters.friction.dynamic_coefficient=0.2"
        r = subprocess.run([rodend_path(), "run", study, "--results-root", root, "-q",
                            "--set", setting], capture_output=True, text=True, timeout=300)
        check(r.returncode == 0, f"rodend run failed: {r.stderr}")
        cases = case_parameters(os.path.join(root, "prov"))
        check(len(cases) == 2, f"expected 2 case files, found {len(cases)}")
        for p in cases:
            check(p["contact.clearance"]["value"] in (2e-4, 3e-4), "the grid value")
            check_leaf(p["contact.clearance"], "grid", ["grid[0]", study],
                       defaults["contact.clearance"]["value"], "thesis", "grid key")
            check_leaf(p["contact.restitution"], "study", ["parameters.contact.restitution",
                                                           study],
                       defaults["contact.restitution"]["value"],
                       defaults["contact.restitution"]["source"], "study parameter")
            check_leaf(p["friction.dynamic_coefficient"], "set", ["--set " + setting],
                       defaults["friction.dynamic_coefficient"]["value"],
                       defaults["friction.dynamic_coefficient"]["source"], "--set")
            check(p["ball.mass"] == defaults["ball.mass"],
                  f"a parameter nobody set changed: {p['ball.mass']}")
        case = rodend.run_case("gravity-drop", {"contact.clearance": 3e-4},
                               time={"end": 0.005, "sample_interval": 1e-3})
        leaf = case.parameters["contact.clearance"]
        check(leaf["value"] == 3e-4, f"run_case's clearance: {leaf}")
        check_leaf(leaf, "study", ["parameters.contact.clearance", "run_case()"],
                   defaults["contact.clearance"]["value"], "thesis", "run_case parameter")
        print("grid, study, --set and run_case provenance:", json.dumps(cases[0]["contact.clearance"]))
    finish("provenance")


if __name__ == "__main__":
    main()
