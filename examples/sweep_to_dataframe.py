"""Sweep -> DataFrame -> plot of a metric over a grid axis.

A clearance sweep of the gravity-drop scene (thesis fig. 3.24: a 0.2 kg ball falls from the
socket centre), run with rodend.run_study, read back with rodend.open_results as a pandas
DataFrame, and the first-impact peak force plotted over the clearance. The ball falls the
clearance c before it hits, so the impact speed is sqrt(2 g c) and the peak force grows with c.

    .venv/bin/python examples/sweep_to_dataframe.py [OUTPUT_DIR]   # default: results/examples
"""
import json
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import rodend

out = sys.argv[1] if len(sys.argv) > 1 else os.path.join("results", "examples")
os.makedirs(out, exist_ok=True)
study = {
    "name": "drop-clearance",
    "scene": "gravity-drop",
    "integrator": {"method": "dopri5", "abs_tol": 1e-8, "rel_tol": 1e-8},
    "time": {"end": 0.05, "sample_interval": 1e-4},
    "signals": ["eccentricity", "contact_force"],
    "grid": [{"key": "parameters.contact.clearance", "linspace": [1e-4, 5e-4, 5]}],
}
study_file = os.path.join(out, "drop-clearance.json")
with open(study_file, "w") as f:
    json.dump(study, f, indent=1)

rc, folder = rodend.run_study(study_file, threads=2, results_root=out)
assert rc == 0, f"a case failed: see {folder}/summary.csv"

results = rodend.open_results(folder)
df = results.summary                                   # one row per case, summary.csv's columns
units = df.attrs["units"]
key, metric = "parameters.contact.clearance", "first_impact_peak_force"
print(df[[key, "first_impact_speed", metric, "status"]].to_string(index=False))

# the impact speed is the free fall's, sqrt(2 g c)
g = 9.81
assert np.allclose(df["first_impact_speed"], np.sqrt(2 * g * df[key]), rtol=1e-6)
assert (np.diff(df[metric]) > 0).all(), "the peak force should grow with the clearance"

fig, ax = plt.subplots(figsize=(5, 3.5))
ax.plot(df[key] * 1e3, df[metric], "o-")
ax.set_xlabel("clearance [mm]")
ax.set_ylabel(f"first-impact peak force [{units[metric]}]")
ax.grid(alpha=0.3)
fig.tight_layout()
png = os.path.join(out, "peak_force_over_clearance.png")
fig.savefig(png, dpi=100)
print("figure:", png)
