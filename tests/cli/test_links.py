"""No write through a planted link (issue 37 item 1): rodend creates every file fresh, under an
unpredictable temporary name, and renames it into place; it never opens an existing name for
writing. Planted, each pointing at a file of the user's (precious.txt), which must not change:

- a symbolic link, and a hard link, at the lock file .rodend.lock: `rodend run` and `rodend
  merge` refuse (exit 2), naming the lock file; a symbolic link at a shard's lock file and at
  the marker .rodend: `rodend run` refuses (exit 2), naming it;
- symbolic links at every temporary name the previous naming scheme predicted
  (.<name>.tmp.<host>.<pid>.<n> for study.json, summary.h5, summary.csv and each case file, the
  pid known before the process starts): the run ends as an undisturbed run (exit 0, every file a
  regular file of its own), the links untouched;
- a symbolic link at report.html's temporary name (report.html.tmp): `rodend report` writes a
  regular report.html and leaves the link alone;
- Python: `rodend.run_case(..., write=...)` refuses a name with a NUL byte (no file created at
  the part before it), a FIFO (a special file), a symbolic link and an existing file that is not
  a case file rodend wrote, each unchanged; it replaces a case file it wrote.

    /usr/bin/python3 tests/cli/test_links.py"""
import glob
import os
import socket
import stat
import tempfile

from common import check, finish, rodend_path, run, write_study

PRECIOUS = "precious: must not change\n"


def precious(tmp):
    path = os.path.join(tmp, "precious.txt")
    with open(path, "w") as f:
        f.write(PRECIOUS)
    return path


def unchanged(path, what):
    with open(path, "rb") as f:
        text = f.read()
    check(text == PRECIOUS.encode(), f"{what}: {path} was written through a link: {text!r}")


def small_study(tmp, name):
    return write_study(os.path.join(tmp, name + ".json"), {
        "name": name, "scene": "gravity-drop", "time": {"end": 0.01, "sample_interval": 1e-3},
        "grid": [{"key": "parameters.contact.restitution", "values": [0.3, 0.9]}]})


def lock_links(tmp):
    s = small_study(tmp, "lock")
    root = os.path.join(tmp, "r-lock")
    r = run(["run", s, "--results-root", root, "-q"])
    check(r.returncode == 0, f"first run: {r.stderr}")
    lock = os.path.join(root, "lock", ".rodend.lock")
    for kind in ("symlink", "hardlink"):
        target = precious(tmp)
        if os.path.lexists(lock):
            os.remove(lock)
        (os.symlink if kind == "symlink" else os.link)(target, lock)
        for cmd in (["run", s, "--results-root", root, "-q"], ["merge", s, "--results-root", root]):
            r = run(cmd)
            check(r.returncode == 2, f"{kind} lock, {cmd[0]}: exit {r.returncode} ({r.stderr})")
            check(lock in r.stderr, f"{kind} lock, {cmd[0]}: message does not name {lock}: "
                  f"{r.stderr!r}")
            unchanged(target, f"{kind} at the lock file, {cmd[0]}")
        os.remove(lock)
    # a shard's lock file, and the marker .rodend
    target = precious(tmp)
    shard_lock = os.path.join(root, "lock", ".rodend.lock.shard-1-of-2")
    os.symlink(target, shard_lock)
    r = run(["run", s, "--results-root", root, "-q", "--shard", "1/2"])
    check(r.returncode == 2 and shard_lock in r.stderr,
          f"symlink at the shard's lock: exit {r.returncode} ({r.stderr})")
    unchanged(target, "symlink at the shard's lock file")
    os.remove(shard_lock)
    marker = os.path.join(root, "lock", ".rodend")
    os.remove(marker)
    os.symlink(target, marker)
    r = run(["run", s, "--results-root", root, "-q"])
    check(r.returncode == 2 and marker in r.stderr,
          f"symlink at the marker: exit {r.returncode} ({r.stderr})")
    unchanged(target, "symlink at the marker .rodend")


def start_paused(args):
    """Forks a child that runs rodend with `args` once the parent writes a byte to its pipe:
    the child's pid (the pid in rodend's temporary names) is known before rodend starts."""
    rfd, wfd = os.pipe()
    pid = os.fork()
    if pid == 0:
        os.close(wfd)
        os.read(rfd, 1)
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, 1)
        os.execv(rodend_path(), [rodend_path()] + args)
    os.close(rfd)
    return pid, wfd


def planted_temporaries(tmp):
    s = small_study(tmp, "temps")
    root = os.path.join(tmp, "r-temps")
    # the case ids and the results layout, from a dry run
    r = run(["run", s, "--results-root", root, "--dry-run"])
    check(r.returncode == 0, f"dry run: {r.stderr}")
    ids = sorted({w for line in r.stdout.splitlines() for w in line.split()
                  if len(w) == 16 and all(c in "0123456789abcdef" for c in w)})
    check(len(ids) == 2, f"case ids from the dry run: {ids} ({r.stdout!r})")
    d = os.path.join(root, "temps")
    os.makedirs(os.path.join(d, "cases"))
    with open(os.path.join(d, ".rodend"), "w") as f:
        f.write("rodend\n")
    target = precious(tmp)
    pid, go = start_paused(["run", s, "--results-root", root, "-q"])
    host = socket.gethostname()
    links = []
    for folder, name in [(d, "study.json"), (d, "summary.h5"), (d, "summary.csv")] + \
            [(os.path.join(d, "cases"), i + ".h5") for i in ids]:
        for n in range(8):
            link = os.path.join(folder, f".{name}.tmp.{host}.{pid}.{n}")
            os.symlink(target, link)
            links.append(link)
    os.write(go, b"x")
    os.close(go)
    _, status = os.waitpid(pid, 0)
    check(os.WIFEXITED(status) and os.WEXITSTATUS(status) == 0,
          f"run with links at the old temporary names: status {status}")
    unchanged(target, "links at the temporary names of the run")
    for name in ["study.json", "summary.h5", "summary.csv"] + \
            [os.path.join("cases", i + ".h5") for i in ids]:
        p = os.path.join(d, name)
        check(os.path.isfile(p) and not os.path.islink(p), f"{p}: not a regular file of its own")
    check(all(os.path.islink(p) for p in links), "a planted link was removed or replaced")

    # report.html's temporary name
    target = precious(tmp)
    link = os.path.join(d, "report.html.tmp")
    os.symlink(target, link)
    r = run(["report", d])
    check(r.returncode == 0, f"report: {r.stderr}")
    unchanged(target, "link at report.html.tmp")
    out = os.path.join(d, "report.html")
    check(os.path.isfile(out) and not os.path.islink(out) and os.path.getsize(out) > 0,
          "report.html not written")
    check(not glob.glob(os.path.join(d, ".report.html.tmp.*")), "report temporary left behind")


def python_write(tmp):
    try:
        import rodend
        rodend.scenes()  # loads the compiled module (on first use)
    except ImportError as e:  # the module is not built: the command-line checks only
        print(f"note: no Python module ({e}); run_case(write=...) not checked")
        return
    scene = "gravity-drop"
    time = {"end": 0.01, "sample_interval": 1e-3}
    target = precious(tmp)
    fifo = os.path.join(tmp, "fifo")
    os.mkfifo(fifo)
    link = os.path.join(tmp, "link.h5")
    os.symlink(target, link)
    nul = os.path.join(tmp, "a")
    for path, what in ((nul + "\0b", "a NUL byte"), (fifo, "a FIFO"), (link, "a symbolic link"),
                       (target, "a file rodend did not write")):
        try:
            rodend.run_case(scene, time=time, write=path)
            check(False, f"write= {what}: accepted")
        except (rodend.InputError, ValueError) as e:
            check("write" in str(e), f"write= {what}: message does not name write: {e}")
    check(not os.path.lexists(nul), "write= with a NUL byte created the file before it")
    check(stat.S_ISFIFO(os.lstat(fifo).st_mode), "write= a FIFO: replaced")
    check(os.path.islink(link), "write= a link: replaced")
    unchanged(target, "run_case(write=...)")
    ours = os.path.join(tmp, "ours.h5")
    rodend.run_case(scene, time=time, write=ours)
    rodend.run_case(scene, time=time, write=ours)  # its own file: replaced
    check(os.path.isfile(ours), "write= a case file of rodend's: not replaced")


with tempfile.TemporaryDirectory() as tmp:
    lock_links(tmp)
    planted_temporaries(tmp)
    python_write(tmp)
finish("links")
