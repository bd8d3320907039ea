"""Failed cases are stored cleanly: each new failure status is produced through the command line
(energy_residual_limit, actuator_saturation, penetration_limit, a budget), exit code 1, the
status and the time reached in the summary and the case file, and check_results.py finds no NaN
or infinity in any stored signal and every status known."""
import csv
import os
import subprocess
import sys
import tempfile

from common import check, finish, run, write_study

HERE = os.path.dirname(os.path.abspath(__file__))

with tempfile.TemporaryDirectory() as tmp:
    studies = {
        "failing-drop": ({
            "scene": "gravity-drop",
            "integrator": {"method": "rk4", "step": 2e-5},
            "time": {"end": 0.05, "sample_interval": 1e-4},
            "grid": [{"zip": [
                {"key": "health.max_energy_residual", "values": [0.01, 1e-6, 0.01]},
                {"key": "parameters.ball.initial_velocity", "values": [[0, 0, 0], [0, 0, 0], [0, -10, 0]]},
                # a contact a million times too soft: the ball sinks past the Hertz law's validity
                # (health.max_penetration_strain, 0.05 of the ball radius)
                {"key": "parameters.contact.stiffness_scale", "values": [1, 1, 1e-6]},
            ]}],
        }, ["ok", "energy_residual_limit", "penetration_limit"]),
        "failing-servo": ({
            "scene": "servo-actuator",
            "integrator": {"method": "dopri5", "abs_tol": 1e-6, "rel_tol": 1e-6, "max_steps": 300},
            "time": {"end": 0.5, "sample_interval": 1e-3},
            "grid": [{"zip": [
                {"key": "parameters.load.external_force", "values": [0.0, -15000.0, 0.0]},
                {"key": "integrator.max_steps", "values": [100000, 100000, 300]},
            ]}],
        }, ["ok", "actuator_saturation", "step_budget_exhausted"]),
    }
    for name, (doc, expected) in studies.items():
        doc["name"] = name
        path = write_study(os.path.join(tmp, name + ".json"), doc)
        r = run(["run", path, "--results-root", tmp, "-q"])
        check(r.returncode == 1, f"{name}: exit {r.returncode}, expected 1: {r.stderr}")
        with open(os.path.join(tmp, name, "summary.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        check([x["status"] for x in rows] == expected,
              f"{name}: statuses {[x['status'] for x in rows]}, expected {expected}: "
              f"{[x['message'] for x in rows]}")
        for x in rows:
            if x["status"] != "ok":
                check("at t = " in x["message"], f"{name}: message without the time: {x['message']}")
                check(float(x["t_reached_s"]) < doc["time"]["end"], f"{name}: t_reached {x['t_reached_s']}")
        c = subprocess.run([sys.executable, os.path.join(HERE, "check_results.py"),
                            os.path.join(tmp, name)], capture_output=True, text=True)
        check(c.returncode == 0, f"{name}: check_results.py: {c.stdout}{c.stderr}")
finish("failed cases")
