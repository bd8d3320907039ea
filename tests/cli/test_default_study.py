#!/usr/bin/env python3
"""The first command shows the whole system (issue 35 item 9): the default study
(studies/default.json, what `bash scripts/main.sh` runs) is on the full rod-end-crank-actuator
scene, every case ends ok, and its figures include the chamber pressures.

    test_default_study.py REPO"""
import json
import os
import subprocess
import sys
import tempfile

from common import check, finish, run

repo = sys.argv[1]
study = os.path.join(repo, "studies", "default.json")
with open(study, encoding="utf-8") as f:
    check(json.load(f)["scene"] == "rod-end-actuator", "the default study is not rod-end-actuator")
with tempfile.TemporaryDirectory() as root:
    r = run(["run", study, "-q", "-j", "2", "--results-root", root])
    check(r.returncode == 0, f"the default study: exit {r.returncode}: {r.stderr}")
    folder = os.path.join(root, "default")
    p = subprocess.run(["/usr/bin/python3", os.path.join(repo, "plots", "plot_study.py"), folder],
                       capture_output=True, text=True, env=dict(os.environ, MPLBACKEND="Agg"))
    check(p.returncode == 0, f"plot_study.py: {p.stderr[-400:]}")
    figures = os.listdir(os.path.join(folder, "plots"))
    check("hydraulics.png" in figures, f"no chamber-pressure figure among {sorted(figures)}")
finish("default study")
