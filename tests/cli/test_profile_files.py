"""Profile files that are not what they seem (docs/inputs.md, "Profiles from data"), beyond the
bad-input corpus (tests/bad_inputs/profile_*.json):

- a profile that is a link to /proc/self/pagemap (a kernel file whose size is not its
  content's, and which fails partial reads): exit 2 naming the file, no C++ stream error;
- a binary profile (terminal escape sequences, NUL, every byte value): exit 2, and the message
  holds no control character or byte that is not UTF-8 (nothing reaches the terminal raw);
- a CSV that starts with a UTF-8 byte-order mark (spreadsheets write one): read as without it;
- `rodend merge` after a profile was edited: its cases have new ids, and the message names
  the changed profile file (its content then and now) and the command that computes them.

    RODEND=build/rodend /usr/bin/python3 tests/cli/test_profile_files.py"""
import json
import os
import shutil
import subprocess
import tempfile

from common import check, finish, rodend_path, write_study

HERE = os.path.dirname(os.path.abspath(__file__))
PROFILES = os.path.join(HERE, "..", "bad_inputs", "profiles")


def profile_study(path, profile, end=1.0):
    return write_study(path, {
        "name": os.path.basename(path)[:-5], "scene": "rod-end-kinematic",
        "time": {"end": end, "sample_interval": 0.01},
        "parameters": {"motion.shape": "profile", "motion.profile.file": profile}})


def run_bytes(args):
    return subprocess.run([rodend_path()] + args, capture_output=True, timeout=120)


with tempfile.TemporaryDirectory() as tmp:
    root = os.path.join(tmp, "results")

    # --- a link to /proc/self/pagemap
    os.symlink("/proc/self/pagemap", os.path.join(tmp, "pagemap.csv"))
    s = profile_study(os.path.join(tmp, "pagemap.json"), "pagemap.csv")
    r = run_bytes(["run", s, "--dry-run", "--results-root", root])
    err = r.stderr.decode("utf-8", "replace")
    check(r.returncode == 2 and "pagemap.csv" in err and "parameters.motion.profile.file" in err
          and "kernel" in err and "basic_filebuf" not in err,
          f"pagemap: exit {r.returncode}, {err!r}")

    # --- a binary profile: exit 2, no control byte echoed
    shutil.copy(os.path.join(PROFILES, "binary.csv"), os.path.join(tmp, "binary.csv"))
    s = profile_study(os.path.join(tmp, "binary.json"), "binary.csv")
    r = run_bytes(["run", s, "--dry-run", "--results-root", root])
    raw = r.stderr
    controls = sorted({b for b in raw if (b < 0x20 and b != 0x0a) or b == 0x7f})
    check(r.returncode == 2 and b"binary.csv" in raw, f"binary: exit {r.returncode}, {raw!r}")
    check(controls == [], f"binary: control bytes {controls} reach the terminal: {raw!r}")
    try:
        text = raw.decode("utf-8")
        c1 = [c for c in text if 0x80 <= ord(c) < 0xa0]
        check(c1 == [], f"binary: C1 control characters in the message: {raw!r}")
    except UnicodeDecodeError as e:
        check(False, f"binary: the message is not UTF-8 ({e}): {raw!r}")
    check(b"\\x1b" in raw, f"binary: the escape byte is not shown as \\x1b: {raw!r}")

    # --- a CSV with a UTF-8 byte-order mark: the same profile, the same case id
    good = open(os.path.join(PROFILES, "good.csv"), "rb").read()
    with open(os.path.join(tmp, "bom.csv"), "wb") as f:
        f.write(b"\xef\xbb\xbf" + good)
    with open(os.path.join(tmp, "plain.csv"), "wb") as f:
        f.write(good)
    ids = {}
    for name in ("bom", "plain"):
        s = profile_study(os.path.join(tmp, name + ".json"), name + ".csv")
        r = run_bytes(["run", s, "--dry-run", "--results-root", root])
        check(r.returncode == 0, f"{name}: exit {r.returncode}, {r.stderr!r}")
        rows = r.stdout.decode().splitlines()
        ids[name] = rows[-1].split("\t")[1] if rows else None
    # the case id hashes the file's bytes (the mark included): both ids exist, and differ
    check(ids["bom"] and ids["plain"] and ids["bom"] != ids["plain"], f"bom: case ids {ids}")

    # --- merge after a profile edit names the changed file
    with open(os.path.join(tmp, "edited.csv"), "wb") as f:
        f.write(good)
    s = profile_study(os.path.join(tmp, "edited.json"), "edited.csv", end=0.05)
    r = run_bytes(["run", s, "-q", "--results-root", root])
    check(r.returncode == 0, f"edited: first run {r.stderr!r}")
    with open(os.path.join(tmp, "edited.csv"), "wb") as f:
        f.write(good.replace(b"0.005", b"0.006"))
    r = run_bytes(["merge", s, "--results-root", root])
    err = r.stderr.decode()
    recorded = json.load(open(os.path.join(root, "edited", "profiles.json")))[0]["content_fnv1a64"]
    check(r.returncode == 1 and "edited.csv" in err and "changed since the run" in err
          and recorded in err and "rodend run" in err and "no complete file" in err,
          f"merge after an edit: exit {r.returncode}, {err!r}")
finish("profile files")
