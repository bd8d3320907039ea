#!/usr/bin/python3
"""Writes the profile files of the bad-input studies (tests/bad_inputs/profile_*.json) and of
tests/test_profiles.cpp, each a small made-up position command in metres (or a hinge moment in
N m) that breaks one rule of docs/inputs.md "Profiles from data":

    /usr/bin/python3 tests/bad_inputs/profiles/make-profiles.py

good.csv and good.h5 hold the same samples (a 1 s ramp from 0 to 10 mm and back); each bad
file differs from good.csv in the one way its name says."""
import os

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
TIME = [0.0, 0.25, 0.5, 0.75, 1.0]
POSITION = [0.0, 0.005, 0.01, 0.005, 0.0]


def csv(name, header="time [s],position [m]", rows=None, comment=True):
    rows = rows if rows is not None else [f"{t!r},{x!r}" for t, x in zip(TIME, POSITION)]
    with open(os.path.join(HERE, name), "w", encoding="utf-8") as f:
        if comment:
            f.write("# made up by make-profiles.py for the bad-input tests\n")
        f.write(header + "\n")
        for r in rows:
            f.write(r + "\n")


def good_rows():
    return [f"{t!r},{x!r}" for t, x in zip(TIME, POSITION)]


csv("good.csv")
rows = good_rows(); rows[2] = "0.25,0.01"
csv("time_repeated.csv", rows=rows)
rows = good_rows(); rows[3] = "0.4,0.005"
csv("time_decreasing.csv", rows=rows)
rows = good_rows(); rows[2] = "0.5,nan"
csv("value_nan.csv", rows=rows)
rows = good_rows(); rows[3] = "0.75,inf"
csv("value_infinite.csv", rows=rows)
rows = good_rows(); rows[1] = "0.25,five"
csv("value_not_a_number.csv", rows=rows)
csv("unit_missing.csv", header="time [s],position")
csv("unit_wrong.csv", header="time [s],position [mm]")
csv("time_unit_wrong.csv", header="time [ms],position [m]")
csv("column_missing.csv", header="time [s],command [m]")
csv("moment_wrong_unit.csv", header="time [s],moment [kN*m]")

with h5py.File(os.path.join(HERE, "good.h5"), "w", track_order=True) as f:
    f.create_dataset("time", data=np.array(TIME), track_times=False).attrs["units"] = "s"
    f.create_dataset("position", data=np.array(POSITION), track_times=False).attrs["units"] = "m"
with h5py.File(os.path.join(HERE, "no_units.h5"), "w") as f:
    f.create_dataset("time", data=np.array(TIME), track_times=False).attrs["units"] = "s"
    f.create_dataset("position", data=np.array(POSITION), track_times=False)
with open(os.path.join(HERE, "corrupt.h5"), "wb") as f:  # the HDF5 signature, then nothing valid
    f.write(b"\x89HDF\r\n\x1a\n" + b"\x00" * 56)
