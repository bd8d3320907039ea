"""Every reader checks what it reads (issue 37 items 2 and 3).

Damage fed to every reader of a results folder, each of which must report it naming the file:
no crash (a signal, an exit code other than 0-2, an exception of another kind), no silent pass
(exit 0, a table or histories handed out):

- random single-bit flips anywhere in a case file (its checksum header included): `rodend
  merge` (exit 1, "corrupt case file"), `rodend compare` (exit 2), `rodend.open_results(...)
  .histories` (rodend.CorruptFile), the plots' reader (the case listed as unreadable);
- random single-bit flips anywhere in summary.h5: `rodend compare` (exit 2), `rodend report`
  (exit 2, no report.html), `rodend.open_results` (rodend.CorruptFile), the plots' reader
  (rodend.study.Study, as plots/ uses it: NotAStudy); `rodend merge` and `rodend run` (a resume with every
  case complete), every other flip each, write the summary again from the case files instead,
  the reference's summary.csv byte for byte;
- an intact case file copied over another case's file: `rodend merge` refuses it (exit 1, no
  summary written), `rodend compare` (exit 2) and `open_results(...).histories` too;
- a deleted case file: `open_results(...).histories` raises FileNotFoundError naming it (not
  NaN histories for a case whose status is ok).

The Python readers run in a worker process, restarted after a crash, so that a crash is counted
rather than ending the test; the readers of one damaged folder run side by side.

    /usr/bin/python3 tests/cli/test_readers.py [CASE_FLIPS [SUMMARY_FLIPS [SEED]]]
    (defaults 200, 100, 1)"""
import json
import os
import random
import shutil
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor

from common import check, finish, run, write_study

CASE_FLIPS = int(sys.argv[1]) if len(sys.argv) > 1 else 200
SUMMARY_FLIPS = int(sys.argv[2]) if len(sys.argv) > 2 else 100
SEED = int(sys.argv[3]) if len(sys.argv) > 3 else 1
POOL = ThreadPoolExecutor(2)

WORKER = r"""
import json, sys
import rodend
from rodend.study import NotAStudy, Study
for line in sys.stdin:
    req = json.loads(line)
    out = {}
    try:
        res = rodend.open_results(req["folder"])
        if req["histories"]:
            res.histories.load()  # lazy: the case files are read here
        out["result"] = "pass"
    except (rodend.CorruptFile, FileNotFoundError) as e:
        out["result"], out["message"] = type(e).__name__, str(e)
    except Exception as e:
        out["result"], out["message"] = "other " + type(e).__name__, str(e)
    if req["plots"] == "cases":
        try:
            study = Study(req["folder"])
            study.cases()
            out["plots"], out["plots_message"] = "listed", " ".join(study.missing)
        except Exception as e:
            out["plots"], out["plots_message"] = "other " + type(e).__name__, str(e)
    elif req["plots"]:
        try:
            Study(req["folder"])  # reads summary.h5
            out["plots"] = "pass"
        except NotAStudy as e:
            out["plots"], out["plots_message"] = "NotAStudy", str(e)
        except Exception as e:
            out["plots"], out["plots_message"] = "other " + type(e).__name__, str(e)
    print(json.dumps(out), flush=True)
"""


class Worker:
    """open_results (and the plots' reader) in a process of its own; a crash is reported."""

    def __init__(self):
        self.proc = None

    def ask(self, folder, histories, plots=False):
        if self.proc is None:
            self.proc = subprocess.Popen([sys.executable, "-c", WORKER], text=True,
                                         stdin=subprocess.PIPE, stdout=subprocess.PIPE)
        self.proc.stdin.write(json.dumps({"folder": folder, "histories": histories,
                                          "plots": plots}) + "\n")
        self.proc.stdin.flush()
        line = self.proc.stdout.readline()
        if not line:
            rc = self.proc.wait()
            self.proc = None
            return {"result": f"crash (exit {rc})"}
        return json.loads(line)

    def close(self):
        if self.proc is not None:
            self.proc.stdin.close()
            self.proc.wait()


class Tally:
    def __init__(self):
        self.counts = {"crash": 0, "silent": 0, "unnamed": 0, "ok": 0}

    def cli(self, what, r, expected_rc, name):
        if r.returncode < 0 or r.returncode > 2:
            return self.bad("crash", f"{what}: exit {r.returncode}: {r.stderr[-300:]!r}")
        if r.returncode != expected_rc:
            return self.bad("silent", f"{what}: exit {r.returncode}, expected {expected_rc}: "
                            f"{(r.stdout + r.stderr)[-300:]!r}")
        if name not in r.stderr:
            return self.bad("unnamed", f"{what}: message does not name {name}: {r.stderr!r}")
        self.counts["ok"] += 1

    def py(self, what, got, expected, name, key="result"):
        res = got.get(key, "")
        if res.startswith("crash") or res.startswith("other"):
            return self.bad("crash", f"{what}: {res}: {got}")
        if res != expected:
            return self.bad("silent", f"{what}: {res}, expected {expected}")
        if name not in got.get("message" if key == "result" else "plots_message", ""):
            return self.bad("unnamed", f"{what}: message does not name {name}: {got}")
        self.counts["ok"] += 1

    def bad(self, kind, msg):
        self.counts[kind] += 1
        check(False, msg)


def flip(path, rng):
    """Flips one random bit of the file; returns (offset, bit)."""
    with open(path, "r+b") as f:
        size = os.fstat(f.fileno()).st_size
        off, bit = rng.randrange(size), rng.randrange(8)
        f.seek(off)
        b = f.read(1)[0] ^ (1 << bit)
        f.seek(off)
        f.write(bytes([b]))
    return off, bit


def wrong_case_and_missing(s, ref, work_root, work, worker, tally):
    ids = sorted(n[:-3] for n in os.listdir(os.path.join(work, "cases")))
    a, b = (os.path.join(work, "cases", i + ".h5") for i in ids[:2])
    summary = open(os.path.join(work, "summary.h5"), "rb").read()
    shutil.copyfile(a, b)
    r = run(["merge", s, "--results-root", work_root])
    tally.cli("merge, another case's file", r, 1, ids[1] + ".h5")
    check("holds case" in r.stderr, f"merge, another case's file: {r.stderr!r}")
    check(open(os.path.join(work, "summary.h5"), "rb").read() == summary,
          "merge, another case's file: the summary was rewritten")
    tally.cli("compare, another case's file", run(["compare", ref, work]), 2, ids[1] + ".h5")
    tally.py("open_results, another case's file", worker.ask(work, True), "CorruptFile",
             ids[1] + ".h5")
    os.remove(b)
    tally.py("open_results, a missing case file", worker.ask(work, True), "FileNotFoundError",
             ids[1] + ".h5")
    shutil.copyfile(os.path.join(ref, "cases", ids[1] + ".h5"), b)


def case_flips(s, ref, work_root, work, worker, tally, rng):
    ids = sorted(n[:-3] for n in os.listdir(os.path.join(work, "cases")))
    for k in range(CASE_FLIPS):
        name = rng.choice(ids) + ".h5"
        path = os.path.join(work, "cases", name)
        off, bit = flip(path, rng)
        where = f"case file {name} bit {bit} of byte {off}"
        # the readers side by side (none of them writes when it finds the damage)
        merged = POOL.submit(run, ["merge", s, "--results-root", work_root])
        compared = POOL.submit(run, ["compare", ref, work])
        got = worker.ask(work, True, plots="cases")
        r = merged.result()
        tally.cli(f"merge, {where}", r, 1, name)
        check("corrupt case file" in r.stderr, f"merge, {where}: {r.stderr!r}")
        tally.cli(f"compare, {where}", compared.result(), 2, name)
        tally.py(f"open_results, {where}", got, "CorruptFile", name)
        tally.py(f"plots' reader, {where}", got, "listed", name, key="plots")
        shutil.copyfile(os.path.join(ref, "cases", name), path)


def summary_flips(s, ref, work_root, work, worker, tally, rng):
    path = os.path.join(work, "summary.h5")
    ref_csv = open(os.path.join(ref, "summary.csv"), "rb").read()
    for k in range(SUMMARY_FLIPS):
        shutil.copyfile(os.path.join(ref, "summary.h5"), path)
        off, bit = flip(path, rng)
        where = f"summary.h5 bit {bit} of byte {off}"
        compared = POOL.submit(run, ["compare", ref, work])
        reported = POOL.submit(run, ["report", work])
        got = worker.ask(work, False, plots=True)
        tally.cli(f"compare, {where}", compared.result(), 2, "summary.h5")
        tally.cli(f"report, {where}", reported.result(), 2, "summary.h5")
        report = os.path.join(work, "report.html")
        check(not os.path.exists(report), f"report, {where}: written")
        if os.path.exists(report):
            os.remove(report)
        tally.py(f"open_results, {where}", got, "CorruptFile", "summary.h5")
        tally.py(f"plots' Study, {where}", got, "NotAStudy", "summary.h5", key="plots")
        # merge, or a resume (every case complete), writes the summary again from the cases
        cmd = ["merge", s, "--results-root", work_root] if k % 2 == 0 else \
            ["run", s, "--results-root", work_root, "-q"]
        r = run(cmd)
        check(r.returncode == 0, f"{cmd[0]}, {where}: exit {r.returncode}: {r.stderr!r}")
        check(open(os.path.join(work, "summary.csv"), "rb").read() == ref_csv,
              f"{cmd[0]}, {where}: summary.csv differs from the reference's")


def main():
    rng = random.Random(SEED)
    worker, tally = Worker(), Tally()
    with tempfile.TemporaryDirectory() as tmp:
        s = write_study(os.path.join(tmp, "readers.json"), {
            "name": "readers", "scene": "gravity-drop",
            "time": {"end": 0.02, "sample_interval": 1e-4},
            "grid": [{"key": "parameters.contact.restitution", "values": [0.3, 0.6, 0.9]}]})
        r = run(["run", s, "--results-root", os.path.join(tmp, "ref"), "-q"])
        check(r.returncode == 0, f"reference run: {r.stderr}")
        ref = os.path.join(tmp, "ref", "readers")
        work_root = os.path.join(tmp, "w")
        work = os.path.join(work_root, "readers")
        shutil.copytree(ref, work)
        r = run(["compare", ref, work])
        check(r.returncode == 0, f"compare of intact copies: {r.stdout}{r.stderr}")
        check(worker.ask(work, True).get("result") == "pass", "open_results of an intact copy")
        wrong_case_and_missing(s, ref, work_root, work, worker, tally)
        case_flips(s, ref, work_root, work, worker, tally, rng)
        summary_flips(s, ref, work_root, work, worker, tally, rng)
    worker.close()
    POOL.shutdown()
    c = tally.counts
    print(f"{CASE_FLIPS} case-file flips, {SUMMARY_FLIPS} summary.h5 flips: {c['ok']} reports "
          f"naming the file, {c['crash']} crashes, {c['silent']} silent passes, {c['unnamed']} "
          "reports not naming the file")
    finish("readers")


main()
