#!/usr/bin/env python3
"""Messages that name the key or file and what was expected, and leave nothing behind (issue 37
item 7 of "Why", Build 6): bytes that are not UTF-8 in a --set value (it used to print a JSON
library message and leave a results folder named by them), a study file that is a loop of
links (it used to say "no such file"), a clearance so small that the radii round alike (it used
to blame contact.stiffness_scale), a number beyond a double's range (it used to say "got a
string"), an integer beyond 9e18, and a tolerance file that is a FIFO (compare used to block on
it)."""
import os
import tempfile

from common import check, finish, run

REPO = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
STUDY = os.path.join(REPO, "studies", "default.json")

with tempfile.TemporaryDirectory() as tmp:
    root = os.path.join(tmp, "results")
    cases = {
        "name=\udcff\udcfe": ("name", "expected UTF-8 text"),
        "parameters.contact.clearance=1e-300": ("parameters.contact.clearance", "too small"),
        "time.end=1e309": ("time.end", "beyond a double's range"),
        "integrator.max_steps=9223372036854775807": ("integrator.max_steps", "at most 9e18"),
    }
    for setting, (key, text) in cases.items():
        for extra in (["--dry-run"], ["-q"]):
            arg = setting.encode("utf-8", "surrogateescape")
            r = run(["run", STUDY, "--results-root", root, "--set", os.fsdecode(arg)] + extra)
            msg = r.stderr
            check(r.returncode == 2, f"--set {setting!r} {extra}: exit {r.returncode}")
            check(f": {key}: " in msg and text in msg, f"--set {setting!r}: message {msg!r}")
            check(not os.path.exists(root), f"--set {setting!r}: something was written")
    a, b = os.path.join(tmp, "loop-a.json"), os.path.join(tmp, "loop-b.json")
    os.symlink(b, a)
    os.symlink(a, b)
    r = run(["run", a, "--dry-run"])
    check(r.returncode == 2 and "symbolic links" in r.stderr and "loop-a.json" in r.stderr,
          f"a loop of links: exit {r.returncode}, {r.stderr!r}")
    fifo = os.path.join(tmp, "tolerances.json")
    os.mkfifo(fifo)
    r = run(["compare", tmp, tmp, "--tolerances", fifo], timeout=20)
    check(r.returncode == 2 and "not a regular file" in r.stderr and fifo in r.stderr,
          f"a FIFO as the tolerance file: exit {r.returncode}, {r.stderr!r}")
finish("messages")
