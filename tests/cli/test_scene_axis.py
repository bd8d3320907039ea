"""The scene as a grid axis from the command line: kinematic and full-system cases side by side
in one study; the summary's scene column; shards + merge and a resume give the same summary
(rodend compare); check_results.py names both scenes."""
import os
import subprocess
import sys
import tempfile

from common import check, finish, read_summary, run, write_study

HERE = os.path.dirname(os.path.abspath(__file__))
doc = {
    "name": "sa",
    "parameters": {"hinge.kind": "constant", "hinge.constant_moment": -20.0},
    "integrator": {"method": "dopri5", "abs_tol": 1e-6, "rel_tol": 1e-6, "max_step": 1e-3},
    "time": {"end": 0.15, "sample_interval": 1e-3},
    "grid": [{"key": "scene", "values": ["rod-end-kinematic", "rod-end-actuator"]},
             {"key": "parameters.contact.clearance", "values": [2e-4, 5e-4]}],
}
with tempfile.TemporaryDirectory() as tmp:
    study = write_study(os.path.join(tmp, "sa.json"), doc)
    full, shards = os.path.join(tmp, "full"), os.path.join(tmp, "shards")
    r = run(["run", study, "--results-root", full, "-q", "--threads", "2"])
    check(r.returncode == 0, f"run: {r.returncode} {r.stderr}")
    rows = read_summary(os.path.join(full, "sa"))
    check([x["scene"] for x in rows] == ["rod-end-kinematic"] * 2 + ["rod-end-actuator"] * 2,
          f"scene column {[x.get('scene') for x in rows]}")
    check(list(rows[0])[:4] == ["case_id", "case_index", "scene", "parameters.contact.clearance"],
          f"columns {list(rows[0])[:5]}")
    check(all(x["status"] == "ok" for x in rows), f"statuses {[x['status'] for x in rows]}")
    # only the full-system cases have an actuator: their chamber pressure is a number
    check([x["max_chamber_pressure"] == "nan" for x in rows] == [True, True, False, False],
          f"max_chamber_pressure {[x['max_chamber_pressure'] for x in rows]}")

    for k in (1, 2):
        r = run(["run", study, "--results-root", shards, "-q", "--shard", f"{k}/2"])
        check(r.returncode == 0, f"shard {k}: {r.stderr}")
    r = run(["merge", study, "--results-root", shards])
    check(r.returncode == 0, f"merge: {r.stderr}")
    r = run(["compare", os.path.join(full, "sa"), os.path.join(shards, "sa"), "--summary-only"])
    check(r.returncode == 0, f"compare full vs merged shards:\n{r.stdout}{r.stderr}")
    check(read_summary(os.path.join(shards, "sa"))[3]["scene"] == "rod-end-actuator",
          "merged summary: scene column")

    # resume: a lost case file is rerun, the others kept
    cases = sorted(os.listdir(os.path.join(full, "sa", "cases")))
    os.remove(os.path.join(full, "sa", "cases", cases[0]))
    r = run(["run", study, "--results-root", full, "-q"])
    check(r.returncode == 0, f"resume: {r.stderr}")
    check(sorted(os.listdir(os.path.join(full, "sa", "cases"))) == cases, "resume: case files")
    r = run(["compare", os.path.join(shards, "sa"), os.path.join(full, "sa"), "--summary-only"])
    check(r.returncode == 0, f"compare after resume:\n{r.stdout}{r.stderr}")

    c = subprocess.run([sys.executable, os.path.join(HERE, "check_results.py"),
                        os.path.join(full, "sa")], capture_output=True, text=True)
    # both scenes named (in the order of the case files, which follows the case ids)
    check(c.returncode == 0 and "rod-end-kinematic" in c.stdout and "rod-end-actuator" in c.stdout,
          f"check_results: {c.returncode} {c.stdout} {c.stderr}")
finish("scene axis")
