"""Shared helpers of the command-line tests (run by CTest under /usr/bin/python3)."""
import csv
import glob
import os
import subprocess
import sys

import h5py
import numpy as np

# columns that legitimately differ between two runs of the same case
VOLATILE = {"wall_time_s", "started_utc", "finished_utc"}


def rodend_path():
    return os.environ["RODEND"]


def run(args, **kw):
    return subprocess.run([rodend_path()] + args, capture_output=True, text=True, **kw)


def write_study(path, doc):
    import json
    with open(path, "w") as f:
        json.dump(doc, f, indent=1)
    return path


def read_summary(study_dir):
    with open(os.path.join(study_dir, "summary.csv"), newline="") as f:
        return list(csv.DictReader(f))


def stable(rows):
    return [{k: v for k, v in r.items() if k not in VOLATILE} for r in rows]


def case_signals(study_dir):
    """{case_id: {signal: array}} for every case file of a study."""
    out = {}
    for path in sorted(glob.glob(os.path.join(study_dir, "cases", "*.h5"))):
        with h5py.File(path, "r") as f:
            out[os.path.basename(path)[:-3]] = {k: f["signals"][k][()] for k in f["signals"]}
    return out


def assert_same_results(a, b, what):
    """Same summary (but timings) and bitwise-identical histories."""
    sa, sb = stable(read_summary(a)), stable(read_summary(b))
    check(sa == sb, f"{what}: summaries differ\n{sa}\n{sb}")
    ha, hb = case_signals(a), case_signals(b)
    check(sorted(ha) == sorted(hb), f"{what}: different case files {sorted(ha)} vs {sorted(hb)}")
    for cid in ha:
        check(sorted(ha[cid]) == sorted(hb[cid]), f"{what}: case {cid} has different signals")
        for sig in ha[cid]:
            x, y = ha[cid][sig], hb[cid][sig]
            check(x.shape == y.shape and np.array_equal(x, y, equal_nan=True),
                  f"{what}: case {cid} signal {sig} differs")


def reseal(path):
    """Rewrites the checksum header (docs/results.md, "Crash safety") of a case file or
    summary.h5 that a test changed on purpose through h5py, so that the readers take it as
    intact (they refuse a file whose checksum does not hold)."""
    import zlib
    with open(path, "rb") as f:
        data = f.read()
    assert data.startswith(b"RODEND-CHECKSUM 1\n"), f"{path}: no checksum header"
    header = b"RODEND-CHECKSUM 1\ncrc32 %08x\nbytes %d\n" % (zlib.crc32(data[512:]), len(data))
    with open(path, "r+b") as f:
        f.write(header.ljust(512, b"\0"))


failures = []


def check(cond, msg):
    if not cond:
        failures.append(msg)
        print("FAIL:", msg, file=sys.stderr)


def finish(name):
    if failures:
        print(f"{name}: {len(failures)} failure(s)", file=sys.stderr)
        sys.exit(1)
    print(f"{name}: all checks passed")


class Pause:
    """A run held at a state by the rename hook (tests/faults/pause_rename.c, whose path CTest
    gives in RODEND_PAUSE_LIB): the first `after` case files of each process are renamed into
    place, every later rename waits. `env()` is the environment that preloads the hook;
    `wait(processes)` waits until that many processes hold a rename (the state; `timeout` only
    bounds a failure); `release()` lets the held renames go on."""

    def __init__(self, directory, after):
        import tempfile
        self.dir = tempfile.mkdtemp(prefix="pause-", dir=directory)
        self.after = after

    def env(self, base=None):
        env = dict(os.environ if base is None else base)
        lib = os.environ["RODEND_PAUSE_LIB"]
        env["LD_PRELOAD"] = (env.get("LD_PRELOAD", "") + " " + lib).strip()
        env["RODEND_PAUSE_AFTER"] = str(self.after)
        env["RODEND_PAUSE_DIR"] = self.dir
        # a sanitizer build's runtime must otherwise come first among the preloaded libraries
        env["ASAN_OPTIONS"] = (env.get("ASAN_OPTIONS", "") + ":verify_asan_link_order=0").lstrip(":")
        return env

    def paused(self):
        return [p for p in os.listdir(self.dir) if p.startswith("paused.")]

    def wait(self, processes=1, alive=None, timeout=300.0):
        """True once `processes` processes hold a rename; False if `alive()` turns false first
        or after `timeout` seconds (a failure bound, not a measure)."""
        import time
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if len(self.paused()) >= processes:
                return True
            if alive is not None and not alive():
                return False
            time.sleep(0.01)
        return False

    def release(self):
        open(os.path.join(self.dir, "release"), "w").close()


def read_until(stream, text, lines=None, timeout=300.0):
    """Reads `stream` (a child's stderr, text mode) line by line until a line holds `text`;
    returns the lines read (appended to `lines` if given). Ends at end of file; `timeout`
    bounds a failure only (a child that neither writes nor ends)."""
    import threading
    out = [] if lines is None else lines
    found = threading.Event()

    def reader():
        for line in stream:
            out.append(line)
            if text in line:
                found.set()
                return
        found.set()

    t = threading.Thread(target=reader, daemon=True)
    t.start()
    found.wait(timeout)
    return out
