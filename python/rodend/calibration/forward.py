"""The forward model the calibration inverts: the configuration's test run by rodend itself
(the `rodend` executable, `rodend run`), as a designed study over the unknowns' priors (the
surrogate's training and held-out cases) or as single runs (the final check at the posterior
mode, the synthetic records of the tests). Each run's compared signals are read at the
record's feature times."""
import copy
import json
import os
import shutil
import subprocess
import tempfile

import numpy as np

from ..casefiles import CaseFiles, _units


class ForwardError(RuntimeError):
    """rodend refused or failed a run; the message is rodend's."""


def rodend_executable():
    """The rodend executable: $RODEND, else the one in $RODEND_BUILD_DIR, else build/rodend."""
    if os.environ.get("RODEND"):
        return os.environ["RODEND"]
    here = os.path.dirname(os.path.abspath(__file__))
    repo = os.path.dirname(os.path.dirname(os.path.dirname(here)))
    build = os.environ.get("RODEND_BUILD_DIR") or os.path.join(repo, "build")
    return os.path.join(build, "rodend")


def version():
    """`rodend --version` of the executable that ran the test (provenance)."""
    r = subprocess.run([rodend_executable(), "--version"], capture_output=True, text=True)
    return r.stdout.strip()


def study_document(cfg, name, design=None, values=None):
    """The study of the test: cfg["study"] with the unknowns either as a designed study's
    factors (design: {method, size, seed}) or fixed (values: {key path: value})."""
    s = copy.deepcopy(cfg["study"])
    doc = {"name": name, "scene": s.pop("scene", None), **s}
    doc["signals"] = sorted({c["signal"] for c in cfg["compare"]} | set(s.get("signals", [])))
    for key, v in (values or {}).items():
        if key.startswith("parameters."):  # a dotted key, as the studies write them
            doc.setdefault("parameters", {})[key[len("parameters."):]] = v
            continue
        node, parts = doc, key.split(".")
        for p in parts[:-1]:
            node = node.setdefault(p, {})
        node[parts[-1]] = v
    if design:
        doc["design"] = {"method": design["method"], "size": int(design["size"]),
                         "seed": int(design["seed"]), "factors": cfg["unknowns"]}
    return doc


def run_study(doc, root, threads=2, dry_run=False):
    """Runs the study document in root/<name>; returns the results folder. Raises
    ForwardError with rodend's message when it refuses the study (exit 2) or a case fails."""
    os.makedirs(root, exist_ok=True)
    path = os.path.join(root, doc["name"] + ".json")
    with open(path, "w", encoding="utf-8") as fh:
        json.dump(doc, fh)
    cmd = [rodend_executable(), "run", path, "--results-root", root, "-q", "-j", str(threads)]
    r = subprocess.run(cmd + (["--dry-run"] if dry_run else []), capture_output=True,
                       text=True)
    if r.returncode != 0:
        raise ForwardError(r.returncode, r.stderr.strip() or r.stdout.strip())
    return os.path.join(root, doc["name"])


def case_rows(folder):
    """[(case id, {summary column: value})] of a results folder, in case order."""
    from ..results import Results
    s = Results(folder).summary
    return [(row["case_id"], row) for _, row in s.iterrows()]


def read_signals(folder, case_id, compare, times):
    """The compared signals of one case at `times` (linear interpolation of its histories,
    which are sampled at the study's sample interval): an array (len(compare), len(times))."""
    with CaseFiles(folder, [case_id]).open(0) as f:  # checked first: checksum, case id
        t = f["signals/time"][()]
        out = []
        for c in compare:
            v = np.asarray(f["signals/" + c["signal"]][()], dtype=float).reshape(len(t), -1)
            out.append(np.interp(times, t, v[:, 0]))
    return np.array(out)


def signal_units(folder, case_id, compare):
    with CaseFiles(folder, [case_id]).open(0) as f:
        return [_units(f["signals/" + c["signal"]]) for c in compare]


def designed_outputs(cfg, root, name, method, size, seed, times):
    """Runs a designed study of `size` points over the priors; returns (x (n, d) the unknowns'
    values, y (n, columns, times) the compared signals, failed case count)."""
    doc = study_document(cfg, name, design={"method": method, "size": size, "seed": seed})
    folder = run_allow_failures(doc, root, cfg)
    keys = [u["key"] for u in cfg["unknowns"]]
    xs, ys, failed = [], [], 0
    for cid, row in case_rows(folder):
        if row["status"] != "ok":
            failed += 1
            continue
        xs.append([float(row[k]) for k in keys])
        ys.append(read_signals(folder, cid, cfg["compare"], times))
    return np.array(xs), np.array(ys), failed


def run_allow_failures(doc, root, cfg):
    try:
        return run_study(doc, root, threads=int(cfg["surrogate"]["threads"]))
    except ForwardError as e:
        if e.args[0] == 1:  # some case failed: the rest are read, the count reported
            return os.path.join(root, doc["name"])
        raise


def single_run(cfg, root, name, values, times):
    """One run of the full model with the unknowns at `values` ({key path: value}): the
    compared signals at `times` (columns, times) and the case's status."""
    doc = study_document(cfg, name, values=values)
    folder = run_allow_failures(doc, root, cfg)
    (cid, row), = case_rows(folder)
    if row["status"] != "ok":
        raise ForwardError(1, f"the full model's run at {values} ended {row['status']}")
    return read_signals(folder, cid, cfg["compare"], times)


class Scratch:
    """A private temporary folder for the runs (in the system's temporary folder, $TMPDIR:
    nothing beside the results until they are complete), removed on exit."""

    def __enter__(self):
        self.path = tempfile.mkdtemp(prefix="rodend-calibrate-")
        return self.path

    def __exit__(self, *a):
        shutil.rmtree(self.path, ignore_errors=True)
