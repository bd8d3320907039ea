#!/usr/bin/env python3
"""Messages that name the key or file and what was expected, and leave nothing behind (issue 37
item 7 of "Why", Build 6): bytes that are not UTF-8 in a --set value (it used to print a JSON
library message and leave a results folder named by them), a study file that is a loop of
links (it used to say "no such file"), a clearance so small that the radii round alike (it used
to blame contact.stiffness_scale), a number beyond a double's range (it used to say "got a
string"), an integer beyond 9e18, and a tolerance file that is a FIFO (compare used to block on
it).

Also: `rodend analyze --help` lists rodend.analyze's options (CLI11 answered it with only -h)
and `rodend analyze` on a folder that is not there says so (it said "no design.json"); on a
terminal, the "stopped by SIGINT" line after Ctrl-C starts on a line of its own (it was glued to
the updating progress line)."""
import os
import pty
import select
import signal
import subprocess
import tempfile

from common import check, finish, rodend_path, run, write_study

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

    r = run(["analyze", "--help"])
    check(r.returncode == 0 and "--threshold" in r.stdout and "--metric" in r.stdout,
          f"analyze --help: exit {r.returncode}, {r.stdout!r} {r.stderr!r}")
    nope = os.path.join(tmp, "nope")
    r = run(["analyze", nope])
    check(r.returncode == 2 and f"{nope}: no such folder" in r.stderr,
          f"analyze of a missing folder: exit {r.returncode}, {r.stderr!r}")


def stop_on_a_terminal(tmp):
    """rodend run under a pseudo-terminal, SIGINT once the progress line shows the first case
    done: the stop message starts a line (what precedes it ends with a newline)."""
    study = write_study(os.path.join(tmp, "many.json"), {
        "name": "many", "scene": "gravity-drop", "time": {"end": 3.0, "sample_interval": 1e-3},
        "grid": [{"key": "parameters.contact.clearance",
                  "values": [1e-4 + 1e-5 * k for k in range(20)]}]})
    master, slave = pty.openpty()
    p = subprocess.Popen([rodend_path(), "run", study, "-j", "1", "--results-root",
                          os.path.join(tmp, "pty")], stdin=slave, stdout=slave, stderr=slave)
    os.close(slave)
    out, sent = b"", False
    while True:
        ready, _, _ = select.select([master], [], [], 60)
        try:
            chunk = os.read(master, 4096) if ready else b""
        except OSError:  # the child closed the terminal
            chunk = b""
        if not chunk:
            break
        out += chunk
        if not sent and b"[1/20]" in out:
            p.send_signal(signal.SIGINT)
            sent = True
    rc = p.wait(timeout=120)
    os.close(master)
    text = out.decode(errors="replace")
    check(sent and rc == 130, f"on a terminal: SIGINT sent {sent}, exit {rc}: {text!r}")
    before = text.split("rodend: stopped by SIGINT")[0]
    check("rodend: stopped by SIGINT" in text and before.endswith("\n"),
          f"the stop message is glued to the progress line: {text!r}")


with tempfile.TemporaryDirectory() as tmp:
    stop_on_a_terminal(tmp)
finish("messages")
