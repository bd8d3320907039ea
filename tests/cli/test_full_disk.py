"""A real full disk (issue 19): a study run into a small tmpfs that holds only some of its case
files exits 2 with one rodend message (no HDF5 error stack, no crash), the case files written
before the disk filled are intact (their checksums hold), no temporary file is left; once the
file system has room again the run resumes to results equal to an uninterrupted run.
Needs to mount a tmpfs (root, or CAP_SYS_ADMIN); skipped with a message otherwise. Run by
scripts/faults-long.sh (the injected write failure of tests/test_runner.cpp "[faults]" is the
default suite's version)."""
import glob
import os
import subprocess
import sys
import tempfile
import zlib

from common import assert_same_results, check, finish, run, write_study

STUDY = {
    "name": "full",
    "scene": "gravity-drop",
    "time": {"end": 0.1, "sample_interval": 1e-5},  # about 4 MB per case file
    "grid": [{"key": "parameters.contact.restitution", "linspace": [0.2, 0.9, 8]}],
}


def checksum_holds(path):
    data = open(path, "rb").read()
    head = data[:512].split(b"\0")[0].decode().split("\n")
    fields = dict(line.split(" ", 1) for line in head[1:] if line)
    return (head[0] == "RODEND-CHECKSUM 1" and int(fields["bytes"]) == len(data) and
            int(fields["crc32"], 16) == zlib.crc32(data[512:]))


with tempfile.TemporaryDirectory() as tmp:
    study = write_study(os.path.join(tmp, "full.json"), STUDY)
    r = run(["run", study, "--results-root", os.path.join(tmp, "ref"), "-q", "-j", "2"])
    check(r.returncode == 0, f"reference run: {r.stderr}")
    case_size = os.path.getsize(glob.glob(os.path.join(tmp, "ref", "full", "cases", "*.h5"))[0])
    disk = os.path.join(tmp, "disk")
    os.mkdir(disk)
    size_kb = int(3.5 * case_size / 1024)  # room for three case files and a half
    m = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size_kb}k", "tmpfs", disk],
                       capture_output=True, text=True)
    if m.returncode != 0:
        print(f"full disk: cannot mount a tmpfs here ({m.stderr.strip()}): skipped")
        sys.exit(0)
    try:
        r = run(["run", study, "--results-root", disk, "-q", "-j", "2"])
        check(r.returncode == 2, f"full disk: exit {r.returncode}, expected 2: {r.stderr[-2000:]}")
        check("HDF5-DIAG" not in r.stderr and r.stderr.count("rodend: error:") == 1 and
              "No space left on device" in r.stderr and "Resume with" in r.stderr,
              f"full disk: message {r.stderr[-2000:]!r}")
        cases = glob.glob(os.path.join(disk, "full", "cases", "*.h5"))
        check(1 <= len(cases) < 8, f"full disk: {len(cases)} case files")
        check(all(checksum_holds(c) for c in cases), "full disk: an earlier case file is damaged")
        tmps = glob.glob(os.path.join(disk, "**", ".*.tmp.*"), recursive=True)
        check(tmps == [], f"full disk: temporary files left: {tmps}")
        # room again: resume completes to the uninterrupted run's results
        subprocess.run(["mount", "-o", "remount,size=200m", disk], check=True)
        r = run(["run", study, "--results-root", disk, "-j", "2"])
        check(r.returncode == 0 and f"{len(cases)} of 8 cases already complete" in r.stderr,
              f"resume after the full disk: {r.returncode} {r.stderr}")
        assert_same_results(os.path.join(tmp, "ref", "full"), os.path.join(disk, "full"),
                            "full disk")
    finally:
        subprocess.run(["umount", disk])
finish("full disk")
