"""The noise model: independent Gaussian noise of a stated standard deviation on every sample
of a compared column (config `compare[i].noise_std`, in the signal's unit), and the synthetic
records the known-answer tests and the shipped example are made of: rodend's exact signal plus
that noise, seeded. When the scenes record sensor signals, `measured` reads the sensor's
signal instead of adding the noise here: the one call of `measured` in
studies/records/make-free-play-record.py and in tests/cli/test_calibrate_known_answers.py
becomes a read of the sensor's signal."""
import numpy as np


def feature_std(cfg, rec):
    """The noise's standard deviation at each feature (columns × times, flattened)."""
    n = len(rec["feature_times"])
    return np.concatenate([np.full(n, c["noise_std"]) for c in cfg["compare"]])


def measured(exact, std, seed):
    """What the instrument reports: the exact signal plus white Gaussian noise of std `std`,
    from numpy's PCG64 generator seeded with `seed` (the same seed, the same record)."""
    rng = np.random.default_rng(int(seed))
    return np.asarray(exact, dtype=float) + rng.normal(0.0, float(std), np.shape(exact))


def write_csv(path, time, columns, comments):
    """A record file as the profile readers read it: '#' comment lines (where the data come
    from), a header of 'name [unit]' cells, one row per sample. columns: [(name, unit,
    values)]."""
    lines = ["# " + c for c in comments]
    lines.append(",".join(["time [s]"] + [f"{n} [{u}]" for n, u, _ in columns]))
    for i, t in enumerate(time):
        lines.append(",".join([f"{t:.9g}"] + [f"{v[i]:.9g}" for _, _, v in columns]))
    with open(path, "w", encoding="utf-8") as fh:
        fh.write("\n".join(lines) + "\n")
