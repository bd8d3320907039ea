"""Reading one history: a case file opened as it is by xarray, and the same case through
rodend.open_results (the study's histories over its grid axes and time).

Runs the gravity-drop study with a small clearance sweep (as examples/sweep_to_dataframe.py),
then plots the eccentricity of the 0.3 mm case over time: the ball falls, bounces and settles.

    .venv/bin/python examples/read_history.py [OUTPUT_DIR]   # default: results/examples
"""
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import xarray as xr

import rodend

out = sys.argv[1] if len(sys.argv) > 1 else os.path.join("results", "examples")
study = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "studies", "gravity-drop.json")
rc, folder = rodend.run_study(study, threads=2, results_root=out,
                              set={"time.end": 0.1,
                                   "grid": [{"key": "parameters.contact.clearance",
                                             "values": [2e-4, 3e-4, 5e-4]}]})
assert rc == 0

# 1. one case file, as any netCDF tool reads it: time is a dimension, every signal has units
res = rodend.open_results(folder)
row = res.summary[res.summary["parameters.contact.clearance"] == 3e-4].iloc[0]
with xr.open_dataset(res.case_file(row.case_id), engine="h5netcdf", group="signals") as case:
    e = case["eccentricity"].load()
    print(f"case {row.case_id}: {e.sizes['time']} samples, eccentricity in {e.attrs['units']}, "
          f"max {float(e.max()) * 1e3:.4f} mm")

# 2. the whole study at once: dimensions = the grid axis and time
h = res.histories
print(h["eccentricity"].dims, dict(h.sizes))
e3 = h["eccentricity"].sel(clearance=3e-4)   # dimensions named by the key's last part
assert np.allclose(e3.values, e.values)

fig, ax = plt.subplots(figsize=(5, 3.5))
for c in h["clearance"].values:
    trace = h["eccentricity"].sel(clearance=c)
    ax.plot(h["time"] * 1e3, trace * 1e3, label=f"c = {c * 1e3:g} mm")
ax.set_xlabel("time [ms]")
ax.set_ylabel("eccentricity [mm]")
ax.legend(fontsize=8)
ax.grid(alpha=0.3)
fig.tight_layout()
png = os.path.join(out, "eccentricity.png")
fig.savefig(png, dpi=100)
print("figure:", png)
