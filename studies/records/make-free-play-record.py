"""Writes free-play-synthetic.csv, the SYNTHETIC record of the calibration example
(free-play-calibration.json, docs/health-monitoring.md#calibration): rodend's own free-play
ground test at a hidden clearance and friction, its exact surface angle plus white Gaussian
noise (rodend/calibration/noise.py), sampled every 1 ms over the test's 2 s.

    /usr/bin/python3 studies/records/make-free-play-record.py [build/rodend]

The values that made it (keep them in the file's comments and in the docs):"""
import json
import os
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "python"))

from rodend.calibration import config, forward, noise  # noqa: E402

TRUTH = {"parameters.contact.clearance": 2.3e-4,
         "parameters.friction.dynamic_coefficient": 0.08}
NOISE_STD = 1e-4  # rad, as the configuration's compare[0].noise_std
SEED = 2026


def main():
    if len(sys.argv) > 1:
        os.environ["RODEND"] = os.path.abspath(sys.argv[1])
    cfg = config.load(os.path.join(HERE, "free-play-calibration.json"))
    end, dt = cfg["study"]["time"]["end"], cfg["study"]["time"]["sample_interval"]
    n = int(round(end / dt)) + 1
    times = [i * dt for i in range(n)]
    with tempfile.TemporaryDirectory() as tmp:
        exact = forward.single_run(cfg, tmp, "truth", TRUTH, times)[0]
    values = noise.measured(exact, NOISE_STD, SEED)
    comments = [
        "SYNTHETIC record, not a measurement: written by studies/records/make-free-play-record.py",
        "rodend's free-play ground test (studies/records/free-play-calibration.json: "
        "rod-end-actuator holding its zero, hinge moment a triangle +-400 N m at 1 Hz, 2 periods)",
        f"hidden truth: {json.dumps(TRUTH)}",
        f"surface_angle = the exact signal + white Gaussian noise, std {NOISE_STD} rad, "
        f"numpy PCG64 seed {SEED}"]
    noise.write_csv(os.path.join(HERE, "free-play-synthetic.csv"), times,
                    [("surface_angle", "rad", values)], comments)


if __name__ == "__main__":
    main()
