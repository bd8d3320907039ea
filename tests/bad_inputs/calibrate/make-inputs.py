"""Writes the bad calibration inputs of this folder: one configuration per way a calibration's
input can be wrong, each with the record it reads, and expected.json: for each configuration
the file the message must name (the configuration or its record), the key path or column it
must name, and a piece of its text. tests/cli/test_calibrate_bad_input.py runs
`rodend calibrate` on each: exit 2, the names, nothing written.

    /usr/bin/python3 tests/bad_inputs/calibrate/make-inputs.py

The records are 21 samples (0 to 20 ms) of a made-up surface angle: every check they fail is
made before any run."""
import copy
import json
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
BASE = {
    "name": "bad",
    "record": {"file": "good.csv"},
    "study": {"scene": "rod-end-actuator",
              "parameters": {"motion.shape": "step", "motion.extension": 0.0,
                             "motion.retraction": 0.0},
              "time": {"end": 0.02, "sample_interval": 0.001}},
    "window": {"start": 0.0, "end": 0.02},
    "compare": [{"column": "surface_angle", "signal": "surface_angle", "noise_std": 1e-4}],
    "unknowns": [{"key": "parameters.contact.clearance", "distribution": "uniform",
                  "lower": 5e-5, "upper": 5e-4}],
    "surrogate": {"cases": 4, "validation_cases": 2},
    "output": "calibration-result",
}
TIMES = [i * 1e-3 for i in range(21)]


def record(name, header="time [s],surface_angle [rad]", times=TIMES, value=None):
    rows = [f"{t:.9g},{(value(i) if value else 1e-3 * math.sin(50 * t)):.9g}"
            for i, t in enumerate(times)]
    with open(os.path.join(HERE, name), "w") as fh:
        fh.write("# made-up record of tests/bad_inputs/calibrate (make-inputs.py)\n")
        fh.write(header + "\n" + "\n".join(rows) + "\n")


def hdf5(name, units="rad", nan_at=None):
    import h5py
    import numpy as np
    with h5py.File(os.path.join(HERE, name), "w") as f:
        f["time"] = np.array(TIMES)
        f["time"].attrs["units"] = "s"
        v = 1e-3 * np.sin(50 * np.array(TIMES))
        if nan_at is not None:
            v[nan_at] = np.nan
        f["surface_angle"] = v
        if units:
            f["surface_angle"].attrs["units"] = units


def config(name, expected, record_file="good.csv", **changes):
    doc = copy.deepcopy(BASE)
    doc["record"]["file"] = record_file
    for path, v in changes.items():
        node, parts = doc, path.split("__")
        for p in parts[:-1]:
            node = node[p]
        if v is None:
            del node[parts[-1]]
        else:
            node[parts[-1]] = v
    with open(os.path.join(HERE, name), "w") as fh:
        json.dump(doc, fh, indent=1)
    EXPECTED[name] = expected


EXPECTED = {}


def records():
    record("good.csv")
    record("column_missing.csv", header="time [s],lvdt_position [m]")
    record("column_misnamed.csv", header="time [s],surface_angel [rad]")
    record("unit_wrong.csv", header="time [s],surface_angle [deg]")
    record("unit_missing.csv", header="time [s],surface_angle")
    record("time_unit_wrong.csv", header="time [ms],surface_angle [rad]")
    record("time_decreasing.csv", times=TIMES[:10] + [TIMES[8]] + TIMES[11:])
    record("time_repeated.csv", times=TIMES[:10] + [TIMES[9]] + TIMES[11:])
    record("time_irregular.csv", times=TIMES[:10] + [TIMES[10] + 4e-4] + TIMES[11:])
    record("value_nan.csv", value=lambda i: float("nan") if i == 7 else 0.0)
    record("too_short.csv", times=TIMES[:15])
    hdf5("hdf5_unit_missing.h5", units=None)
    hdf5("hdf5_nan.h5", nan_at=4)


def configs():
    config("record_column_missing.json", ["column_missing.csv", "surface_angle",
                                          "has no column 'surface_angle'"],
           "column_missing.csv")
    config("record_column_misnamed.json", ["column_misnamed.csv", "surface_angle",
                                           "its header names 'time', 'surface_angel'"],
           "column_misnamed.csv")
    config("record_unit_wrong.json", ["unit_wrong.csv", "surface_angle",
                                      "is in 'deg'; expected 'rad'"], "unit_wrong.csv")
    config("record_unit_missing.json", ["unit_missing.csv", "surface_angle",
                                        "states no unit; expected 'rad'"], "unit_missing.csv")
    config("record_time_unit_wrong.json", ["time_unit_wrong.csv", "time",
                                           "is in 'ms'; expected 's'"], "time_unit_wrong.csv")
    config("record_time_decreasing.json", ["time_decreasing.csv", "time",
                                           "expected a strictly increasing time column"],
           "time_decreasing.csv")
    config("record_time_repeated.json", ["time_repeated.csv", "time",
                                         "expected a strictly increasing time column"],
           "time_repeated.csv")
    config("record_time_irregular.json", ["time_irregular.csv", "line 13",
                                          "expected a regular time base"],
           "time_irregular.csv")
    config("record_nan.json", ["value_nan.csv", "surface_angle", "expected finite numbers"],
           "value_nan.csv")
    config("record_too_short.json", ["too_short.csv", "time", "too short for the test"],
           "too_short.csv")
    config("record_hdf5_unit_missing.json", ["hdf5_unit_missing.h5", "dataset 'surface_angle'",
                                             "states no unit; expected 'rad'"],
           "hdf5_unit_missing.h5")
    config("record_hdf5_nan.json", ["hdf5_nan.h5", "element 4", "expected finite numbers"],
           "hdf5_nan.h5")
    config("record_file_missing.json", ["no_such_record.csv", "", "cannot open the record"],
           "no_such_record.csv")
    config("config_unknown_key.json", ["config_unknown_key.json", "mcmc.chain",
                                       "unknown key"], mcmc={"chain": 4})
    config("config_noise_missing.json", ["config_noise_missing.json", "compare[0].noise_std",
                                         "missing"],
           compare=[{"column": "surface_angle", "signal": "surface_angle"}])
    config("config_noise_negative.json", ["config_noise_negative.json",
                                          "compare[0].noise_std", "expected a value > 0"],
           compare=[{"column": "surface_angle", "signal": "surface_angle",
                     "noise_std": -1e-4}])
    config("config_signal_unknown.json", ["config_signal_unknown.json", "compare[0].signal",
                                          "unknown signal 'surface_angel'"],
           compare=[{"column": "surface_angle", "signal": "surface_angel",
                     "noise_std": 1e-4}])
    config("config_signal_vector.json", ["config_signal_vector.json", "compare[0].signal",
                                         "has 3 components; expected a scalar signal"],
           compare=[{"column": "surface_angle", "signal": "contact_force_vector",
                     "noise_std": 1e-4}])
    config("config_prior_inverted.json", ["config_prior_inverted.json", "unknowns[0].upper",
                                          "expected upper > lower"],
           unknowns=[{"key": "parameters.contact.clearance", "distribution": "uniform",
                      "lower": 5e-4, "upper": 5e-5}])
    config("config_prior_unknown_parameter.json", ["config_prior_unknown_parameter.json",
                                                   "unknowns[0].key", "contact.clearence"],
           unknowns=[{"key": "parameters.contact.clearence", "distribution": "uniform",
                      "lower": 5e-5, "upper": 5e-4}])
    config("config_window_beyond_run.json", ["config_window_beyond_run.json", "window.end",
                                             "within the test's run"], window={"end": 0.05})
    config("config_record_missing.json", ["config_record_missing.json", "record",
                                          "missing"], record=None)


if __name__ == "__main__":
    records()
    configs()
    with open(os.path.join(HERE, "expected.json"), "w") as fh:
        json.dump(EXPECTED, fh, indent=1)
        fh.write("\n")
