"""`rodend calibrate` end to end on the shipped example (studies/records/free-play-calibration.json
and its synthetic record, made at contact.clearance = 0.23 mm): exit 0, the clearance's 90 %
interval holds 0.23 mm and is no wider than 0.02 mm, the results folder complete (its record
hash the file's SHA-256) and nothing else left behind. Then two calibrations that must not give
a confident answer, each exit 1 with a message naming what failed and a complete results
folder saying so:
- a prior that excludes every value the data allow (clearance uniform over 0.3-0.5 mm, the
  truth 0.23 mm): the posterior piles at the prior's lower bound and the full model at the mode
  misses the record by far more than the noise;
- chains too short to converge (60 draws each): the effective sample size check fails."""
import hashlib
import json
import os
import shutil
import sys
import tempfile

from common import check, finish, run

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
EXAMPLE = os.path.join(REPO, "studies", "records", "free-play-calibration.json")
RECORD = os.path.join(REPO, "studies", "records", "free-play-synthetic.csv")
FILES = {"calibration.json", "posterior.csv", "calibration-fit.png",
         "calibration-posterior.png"}
PROGNOSIS = {"prognosis.png"}


def calibrate(root, changes):
    cfg = json.load(open(EXAMPLE))
    cfg.update(changes, output=os.path.join(root, "out"))
    shutil.copy(RECORD, root)
    path = os.path.join(root, "config.json")
    json.dump(cfg, open(path, "w"))
    r = run(["calibrate", path], cwd=root)
    print(r.stdout.strip())
    left = set(os.listdir(root)) - {"out", "config.json", os.path.basename(RECORD)}
    check(not left, f"{changes}: left behind: {left}")
    out = os.path.join(root, "out")
    check(os.path.isdir(out) and FILES <= set(os.listdir(out)),
          f"{changes}: results folder incomplete: {os.listdir(root)} ({r.stderr[-2000:]})")
    if not os.path.isfile(os.path.join(out, "calibration.json")):
        finish("calibrate example")
    return r, json.load(open(os.path.join(out, "calibration.json")))


def example():
    with tempfile.TemporaryDirectory() as root:
        r, doc = calibrate(root, {})
        check(r.returncode == 0, f"example: exit {r.returncode}: {r.stderr}")
        c = doc["posterior"]["unknowns"][0]
        lo, hi = c["interval90"]
        check(lo <= 2.3e-4 <= hi, f"example: clearance interval [{lo}, {hi}] misses 0.23 mm")
        check(hi - lo <= 2e-5, f"example: clearance interval {hi - lo} m wider than 0.02 mm")
        sha = hashlib.sha256(open(RECORD, "rb").read()).hexdigest()
        check(doc["record"]["sha256"] == sha, "example: record hash is not the file's SHA-256")
        q = doc["prognosis"]["cycles_to_limit"]
        check(PROGNOSIS <= set(os.listdir(os.path.join(root, "out"))), "example: no prognosis.png")
        check(0 < q["q05"] <= q["q50"] <= q["q95"], f"example: prognosis quantiles {q}")
        print(f"example: prognosis {q}")
        print(f"example: clearance 90 % interval [{lo:.4e}, {hi:.4e}] m, width "
              f"{hi - lo:.3e} m; {doc['surrogate']['training_cases']} + "
              f"{doc['surrogate']['validation_cases']} cases")


def refused(changes, needles):
    with tempfile.TemporaryDirectory() as root:
        r, doc = calibrate(root, changes)
        msg = r.stderr
        check(r.returncode == 1, f"{changes}: exit {r.returncode}, expected 1: {msg}")
        for n in needles:
            check(n in msg, f"{changes}: message lacks '{n}': {msg}")
        check("config.json" in msg, f"{changes}: message does not name the file: {msg}")
        check(doc["status"].startswith("failed"), f"{changes}: status {doc['status']}")


def main():
    example()
    small = {"surrogate": {"cases": 24, "validation_cases": 8, "seed": 1}, "prognosis": None}
    refused({**small, "unknowns": [
        {"key": "parameters.contact.clearance", "distribution": "uniform", "lower": 3e-4,
         "upper": 5e-4},
        {"key": "parameters.friction.dynamic_coefficient", "distribution": "uniform",
         "lower": 0.04, "upper": 0.12}]},
        ["prior-data conflict", "parameters.contact.clearance", "unknowns[0]", "lower bound",
         "misses the record"])
    refused({**small, "mcmc": {"chains": 4, "samples": 60, "burn_in": 0, "seed": 1}},
            ["not converged", "effective sample size", "mcmc.samples"])
    finish("calibrate example")


if __name__ == "__main__":
    sys.exit(main())
