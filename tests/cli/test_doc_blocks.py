"""The code blocks of README.md and docs/*.md marked runnable (```sh runnable, ```python
runnable) run (examples that cannot rot). Each file's blocks run in order in one
temporary folder laid out like a clone (studies/, plots/, examples/, python/ linked from the
repository, build/rodend the binary under test), so results land there and not in the
repository; Python under /usr/bin/python3 with the rodend package importable.

    test_doc_blocks.py REPO BUILD_DIR
"""
import glob
import os
import re
import shutil
import subprocess
import sys
import tempfile

from common import check, finish, rodend_path

BLOCK = re.compile(r"^```(sh|bash|python) runnable[^\n]*\n(.*?)^```", re.S | re.M)


def main():
    repo, build = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    files = [os.path.join(repo, "README.md")] + sorted(glob.glob(os.path.join(repo, "docs", "*.md")))
    total = 0
    for doc in files:
        with open(doc, encoding="utf-8") as f:
            blocks = BLOCK.findall(f.read())
        if not blocks:
            continue
        work = tempfile.mkdtemp(prefix="rodend-doc-")
        try:
            for d in ("studies", "plots", "examples", "python", "tests"):
                os.symlink(os.path.join(repo, d), os.path.join(work, d))
            os.makedirs(os.path.join(work, "build"))
            os.symlink(rodend_path(), os.path.join(work, "build", "rodend"))
            env = dict(os.environ, PYTHONPATH=os.path.join(repo, "python"), RODEND_BUILD_DIR=build,
                       MPLBACKEND="Agg")
            for i, (lang, code) in enumerate(blocks):
                total += 1
                where = f"{os.path.relpath(doc, repo)} block {i + 1} ({lang})"
                cmd = ["/usr/bin/python3", "-c", code] if lang == "python" else \
                    ["bash", "-euo", "pipefail", "-c", code]
                # a shell block runs as a user types it: no PYTHONPATH (a command that needs the
                # package must find it itself, as rodend analyze and plots/ do); a Python block
                # stands for the clone's .venv/bin/python, which imports rodend
                shell_env = {k: v for k, v in env.items()
                             if k not in ("PYTHONPATH", "RODEND_BUILD_DIR")}
                r = subprocess.run(cmd, cwd=work, env=env if lang == "python" else shell_env,
                                   capture_output=True, text=True, timeout=600)
                check(r.returncode == 0, f"{where} failed ({r.returncode}):\n{code}\n--- stdout\n"
                                         f"{r.stdout[-2000:]}\n--- stderr\n{r.stderr[-3000:]}")
                print(f"{where}: exit {r.returncode}")
        finally:
            shutil.rmtree(work, ignore_errors=True)
    check(total >= 3, f"only {total} runnable blocks found")
    finish("doc_blocks")


if __name__ == "__main__":
    main()
