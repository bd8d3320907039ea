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

# good.h5 as committed (rewriting it with another h5py changes its bytes, and the case ids of
# the tests that read it)
if not os.path.exists(os.path.join(HERE, "good.h5")):
    with h5py.File(os.path.join(HERE, "good.h5"), "w", track_order=True) as f:
        f.create_dataset("time", data=np.array(TIME), track_times=False).attrs["units"] = "s"
        f.create_dataset("position", data=np.array(POSITION),
                         track_times=False).attrs["units"] = "m"
with h5py.File(os.path.join(HERE, "no_units.h5"), "w") as f:
    f.create_dataset("time", data=np.array(TIME), track_times=False).attrs["units"] = "s"
    f.create_dataset("position", data=np.array(POSITION), track_times=False)
with open(os.path.join(HERE, "corrupt.h5"), "wb") as f:  # the HDF5 signature, then nothing valid
    f.write(b"\x89HDF\r\n\x1a\n" + b"\x00" * 56)

# data kept in another file: an external link, a virtual dataset (both to good.h5's position);
# the case id hashes the profile file's own bytes, so these are refused
with h5py.File(os.path.join(HERE, "external_link.h5"), "w") as f:
    f.create_dataset("time", data=np.array(TIME), track_times=False).attrs["units"] = "s"
    f["position"] = h5py.ExternalLink("good.h5", "/position")
layout = h5py.VirtualLayout(shape=(len(TIME),), dtype="f8")
layout[:] = h5py.VirtualSource("good.h5", "position", shape=(len(TIME),))
with h5py.File(os.path.join(HERE, "virtual.h5"), "w") as f:
    f.create_dataset("time", data=np.array(TIME), track_times=False).attrs["units"] = "s"
    f.create_virtual_dataset("position", layout).attrs["units"] = "m"
# declared large, stored small: 2^40 values declared, chunked and compressed, nothing written
with h5py.File(os.path.join(HERE, "declared_huge.h5"), "w") as f:
    f.create_dataset("time", data=np.array(TIME), track_times=False).attrs["units"] = "s"
    f.create_dataset("position", shape=(2**40,), dtype="f8", chunks=(4096,),
                     compression="gzip", track_times=False).attrs["units"] = "m"
# five values in chunks declared to hold 2^25 + 8 values each (just over 256 MiB), none
# written (a written one would take 260 kB even compressed)
with h5py.File(os.path.join(HERE, "chunk_huge.h5"), "w") as f:
    f.create_dataset("time", data=np.array(TIME), track_times=False).attrs["units"] = "s"
    f.create_dataset("position", shape=(len(TIME),), dtype="f8", maxshape=(None,),
                     chunks=(2**25 + 8,), compression="gzip",
                     track_times=False).attrs["units"] = "m"
# bytes that are not text (no HDF5 signature: read as CSV), with terminal control sequences
with open(os.path.join(HERE, "binary.csv"), "wb") as f:
    f.write(b"\x1b[2J\x1b]0;owned\x07time [s],position [m]\x00\x9b31m\n" + bytes(range(256)))
