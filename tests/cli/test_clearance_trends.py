"""Thesis §5.2 trends, checked on the summary of the shipped kinematic clearance study
(studies/clearance-kinematic.json): with a larger clearance the first-impact peak contact force grows, so does the peak-to-peak eccentricity
oscillation after the first contact, and the surface starts to move later."""
import os
import sys
import tempfile

from common import check, finish, read_summary, run

study = sys.argv[1]
with tempfile.TemporaryDirectory() as root:
    r = run(["run", study, "--results-root", root, "-q", "--threads", "2"])
    check(r.returncode == 0, f"clearance study failed: {r.stderr}")
    rows = read_summary(os.path.join(root, "clearance-kinematic"))
    rows.sort(key=lambda x: float(x["parameters.contact.clearance"]))
    check(len(rows) >= 5 and all(x["status"] == "ok" for x in rows), f"statuses {rows}")
    for metric in ("first_impact_peak_force", "eccentricity_ptp_after_first_contact",
                   "surface_motion_onset_time"):
        values = [float(x[metric]) for x in rows]
        check(all(b > a for a, b in zip(values, values[1:])),
              f"{metric} does not grow with clearance: {values}")
        print(metric, ["%.4g" % v for v in values])
finish("clearance trends")
