"""Sweep engine: 1 and 2 threads give identical summaries and histories; a divergent case is
recorded as failed while the others succeed; dry-run prints the case count."""
import os
import tempfile

from common import assert_same_results, check, finish, read_summary, run, write_study

with tempfile.TemporaryDirectory() as tmp:
    study = write_study(os.path.join(tmp, "grid.json"), {
        "name": "grid",
        "scene": "gravity-drop",
        "integrator": {"method": "dopri5", "abs_tol": 1e-8, "rel_tol": 1e-8},
        "time": {"end": 0.04, "sample_interval": 1e-4},
        "grid": [
            {"key": "parameters.contact.clearance", "values": [2e-4, 5e-4]},
            {"zip": [{"key": "parameters.contact.restitution", "values": [0.5, 0.9, 1.0]},
                     {"key": "parameters.contact.law", "values": ["lankarani-nikravesh", "hunt-crossley", "hertz"]}]},
        ],
    })
    r = run(["run", study, "--dry-run", "--results-root", tmp])
    check(r.returncode == 0 and "6 case(s)" in r.stdout, f"dry run: {r.returncode} {r.stdout}")
    check(not os.path.exists(os.path.join(tmp, "grid")), "dry run wrote results")

    one, two = os.path.join(tmp, "one"), os.path.join(tmp, "two")
    r1 = run(["run", study, "--threads", "1", "--results-root", one, "-q"])
    r2 = run(["run", study, "--threads", "2", "--results-root", two, "-q"])
    check(r1.returncode == 0 and r2.returncode == 0, f"runs failed: {r1.stderr} {r2.stderr}")
    rows = read_summary(os.path.join(one, "grid"))
    check(len(rows) == 6 and all(r["status"] == "ok" for r in rows), f"statuses: {rows}")
    check([int(r["case_index"]) for r in rows] == list(range(6)), "summary not in grid order")
    assert_same_results(os.path.join(one, "grid"), os.path.join(two, "grid"), "1 vs 2 threads")

    # a deliberately divergent case: rk4 at a step far beyond the stability limit of a contact
    # made 1e4 times stiffer; the other cases are fine
    bad = write_study(os.path.join(tmp, "diverge.json"), {
        "name": "diverge",
        "scene": "gravity-drop",
        "integrator": {"method": "rk4", "step": 2e-5},
        "time": {"end": 0.03, "sample_interval": 1e-3},
        "grid": [{"key": "parameters.contact.stiffness_scale", "values": [1.0, 1e4, 0.5]}],
    })
    r = run(["run", bad, "--results-root", tmp, "-q"])
    rows = read_summary(os.path.join(tmp, "diverge"))
    check(r.returncode == 1, f"divergent study exit code {r.returncode}, expected 1")
    check([x["status"] for x in rows][0::2] == ["ok", "ok"], f"statuses {rows}")
    check(rows[1]["status"] in ("non_finite_state", "penetration_limit"),
          f"divergent case status {rows[1]['status']}")
    check("t = " in rows[1]["message"] and float(rows[1]["t_reached_s"]) < 0.03,
          f"divergent case message/time: {rows[1]['message']} {rows[1]['t_reached_s']}")
    # the same command again keeps the failure; --rerun-failed reruns it (and fails again)
    r = run(["run", bad, "--results-root", tmp])
    check(r.returncode == 1 and "2 of 3 cases already complete" not in r.stderr
          and "3 of 3 cases already complete" in r.stderr, f"resume of failed: {r.stderr}")
    r = run(["run", bad, "--results-root", tmp, "--rerun-failed"])
    check(r.returncode == 1 and "2 of 3 cases already complete" in r.stderr, f"rerun-failed: {r.stderr}")
finish("sweep")
