"""Results folders that cannot be trusted are reported, never overwritten:
- a read-only results directory: exit 2, a message naming it, before anything runs;
- a case file under its final name that is truncated, zeroed, or not an HDF5 file at all: reported
  as corrupt naming the file, moved aside to <id>.h5.corrupt byte for byte, and its case rerun;
- a directory, or another case's intact file, under a case file's name: exit 2, a message naming
  it, left as it was and no case run; once it is moved away the study resumes and reruns only
  that case.
A read-only directory does not stop root, so as root that part runs as user nobody (setpriv)."""
import glob
import os
import shutil
import stat
import subprocess
import tempfile

from common import check, finish, read_summary, rodend_path, run, write_study

STUDY = {
    "name": "folder",
    "scene": "gravity-drop",
    "time": {"end": 0.01, "sample_interval": 1e-3},
    "grid": [{"key": "parameters.contact.restitution", "values": [0.3, 0.6, 0.9]}],
}


def as_unprivileged(args):
    """Runs rodend as nobody when we are root (permissions bind only unprivileged users)."""
    cmd = [rodend_path()] + args
    if os.geteuid() == 0:
        setpriv = shutil.which("setpriv")
        if setpriv is None:
            return None
        cmd = [setpriv, "--reuid=65534", "--regid=65534", "--clear-groups"] + cmd
    return subprocess.run(cmd, capture_output=True, text=True)


with tempfile.TemporaryDirectory() as tmp:
    os.chmod(tmp, 0o755)  # readable by nobody
    study = write_study(os.path.join(tmp, "folder.json"), STUDY)
    os.chmod(study, 0o644)

    # 1. read-only results root (nothing can be created) and read-only existing results folder
    ro_root = os.path.join(tmp, "ro-root")
    os.mkdir(ro_root)
    done_root = os.path.join(tmp, "done")
    r = run(["run", study, "--results-root", done_root, "-q"])
    check(r.returncode == 0, f"first run failed: {r.stderr}")
    folder = os.path.join(done_root, "folder")
    for path in [done_root, folder, os.path.join(folder, "cases")]:
        os.chmod(path, 0o755)
    for p in [ro_root] + [folder, os.path.join(folder, "cases")]:
        if os.geteuid() == 0:
            os.chown(p, 65534, 65534)
    os.chmod(ro_root, 0o555)
    r = as_unprivileged(["run", study, "--results-root", ro_root, "-q"])
    if r is None:
        print("setpriv not found: read-only checks skipped")
    else:
        check(r.returncode == 2, f"read-only root: exit {r.returncode}, expected 2: {r.stderr}")
        check(ro_root in r.stderr and "Permission denied" in r.stderr,
              f"read-only root: message does not name the directory: {r.stderr}")
        check(os.listdir(ro_root) == [], f"read-only root: something was written")
        # an existing, complete results folder made read-only: reported before anything runs
        os.chmod(folder, 0o555)
        before = {p: os.stat(p).st_mtime_ns for p in glob.glob(os.path.join(folder, "**"), recursive=True)}
        r = as_unprivileged(["run", study, "--results-root", done_root, "--rerun-failed", "-q"])
        check(r.returncode == 2, f"read-only folder: exit {r.returncode}, expected 2: {r.stderr}")
        check("is not writable" in r.stderr and folder in r.stderr,
              f"read-only folder: message does not name it: {r.stderr}")
        after = {p: os.stat(p).st_mtime_ns for p in glob.glob(os.path.join(folder, "**"), recursive=True)}
        check(before == after, "read-only folder: something changed")
        os.chmod(folder, 0o755)

    # 2. a truncated case file, a corrupt one, a text file, a directory under a case file's name
    # and another case's file under this case's name
    root = os.path.join(tmp, "res")
    r = run(["run", study, "--results-root", root, "-q"])
    check(r.returncode == 0, f"run failed: {r.stderr}")
    cases = sorted(glob.glob(os.path.join(root, "folder", "cases", "*.h5")))
    check(len(cases) == 3, f"expected 3 case files, got {cases}")
    rows = read_summary(os.path.join(root, "folder"))
    strip = lambda rs: [{k: v for k, v in x.items() if k not in ("wall_time_s", "started_utc", "finished_utc")} for x in rs]
    for damage in ("truncated", "zeros", "text", "directory", "another case"):
        victim = cases[1]
        original = open(victim, "rb").read()
        if damage == "truncated":
            open(victim, "wb").write(original[: len(original) // 2])
        elif damage == "zeros":
            open(victim, "wb").write(b"\0" * len(original))
        elif damage == "text":
            open(victim, "w").write("not an HDF5 file\n")
        elif damage == "another case":
            shutil.copyfile(cases[0], victim)
        else:
            os.remove(victim)
            os.mkdir(victim)
        damaged = None if damage == "directory" else open(victim, "rb").read()
        others = {c: os.stat(c).st_mtime_ns for c in cases if c != victim}
        r = run(["run", study, "--results-root", root, "-q", "--rerun-failed"])
        check("Traceback" not in r.stderr and "terminate" not in r.stderr, f"{damage}: crash")
        check(others == {c: os.stat(c).st_mtime_ns for c in cases if c != victim},
              f"{damage}: other case files were rewritten")
        if damage in ("truncated", "zeros", "text"):
            # damaged bytes: reported as corrupt with the path, moved aside (kept byte for byte)
            # and the case rerun to the same results
            aside = sorted(glob.glob(victim + ".corrupt*"))
            check(r.returncode == 0, f"{damage}: exit {r.returncode}, expected 0: {r.stderr}")
            check(f"corrupt case file {victim}" in r.stderr and "moved to " + victim + ".corrupt"
                  in r.stderr, f"{damage}: the message does not name the file: {r.stderr}")
            check(len(aside) == 1 and open(aside[0], "rb").read() == damaged,
                  f"{damage}: the corrupt file was not kept aside: {aside}")
            check(os.path.isfile(victim), f"{damage}: case not rewritten")
            check(strip(read_summary(os.path.join(root, "folder"))) == strip(rows),
                  f"{damage}: the rerun changed the summary")
            for a in aside:
                os.remove(a)
            continue
        # not damage (a directory, another case's intact file): never touched, nothing runs
        check(r.returncode == 2, f"{damage}: exit {r.returncode}, expected 2: {r.stderr}")
        check(victim in r.stderr and "does not overwrite" in r.stderr,
              f"{damage}: the message does not name the file: {r.stderr}")
        if damaged is not None:
            check(open(victim, "rb").read() == damaged, f"{damage}: the file was overwritten")
        else:
            check(os.path.isdir(victim), f"{damage}: the directory was replaced")
        # moved away: the study resumes and reruns only that case, with the same results
        if damage == "directory":
            os.rmdir(victim)
        else:
            os.remove(victim)
        r = run(["run", study, "--results-root", root])
        check(r.returncode == 0, f"{damage}: resume failed: {r.stderr}")
        check("2 of 3 cases already complete" in r.stderr, f"{damage}: not a resume: {r.stderr}")
        check(strip(read_summary(os.path.join(root, "folder"))) == strip(rows),
              f"{damage}: the rerun changed the summary")
        check(os.path.isfile(victim), f"{damage}: case not rewritten")
finish("results folder")
