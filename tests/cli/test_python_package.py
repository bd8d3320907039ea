"""rodend installs into a fresh virtual environment with the documented command and the
examples run there (issue 35 item 1; docs/python.md "Installing"). Before, there was no
pyproject.toml: only /usr/bin/python3 could import rodend, through a .pth file setup.sh wrote
into the system's site-packages.

    test_python_package.py REPO BUILD_DIR

The venv is `python3 -m venv --system-site-packages` (numpy, h5py, pandas, xarray and
matplotlib from Debian), the install `pip install --no-build-isolation REPO` with --no-index
(nothing is downloaded: every dependency must already be there). RODEND_PIP_BUILD_DIR names this
build directory, configured for /usr/bin/python3, the venv's base interpreter: setup.py builds
the extension target there (up to date: no second compilation of the project) and installs it;
its build of a fresh CMake directory is the same code after a configure step. Then, with no
PYTHONPATH and no RODEND_BUILD_DIR, the venv's python imports rodend from its own
site-packages, its version is the project's, and every example (scripts and notebook) runs.
"""
import json
import os
import subprocess
import sys
import tempfile

from common import check, finish
from examples_runner import run_examples


def main():
    repo, build = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "RODEND_BUILD_DIR")}
    with tempfile.TemporaryDirectory(prefix="rodend-venv-") as tmp:
        venv = os.path.join(tmp, "venv")
        r = subprocess.run(["/usr/bin/python3", "-m", "venv", "--system-site-packages", venv],
                           capture_output=True, text=True, env=env, timeout=300)
        check(r.returncode == 0, f"python3 -m venv failed: {r.stderr}")
        python = os.path.join(venv, "bin", "python")
        r = subprocess.run([python, "-m", "pip", "install", "--no-index", "--no-cache-dir",
                            "--no-build-isolation", repo], capture_output=True, text=True,
                           env=dict(env, RODEND_PIP_BUILD_DIR=build), cwd=tmp, timeout=1800)
        check(r.returncode == 0, f"pip install failed ({r.returncode}):\n{r.stdout[-3000:]}\n"
              f"{r.stderr[-3000:]}")
        r = subprocess.run([python, "-c", "import importlib.metadata as m, json, rodend; "
                            "print(json.dumps([rodend.__file__, rodend._ext.__file__, "
                            "rodend.__version__, m.version('rodend')]))"],
                           capture_output=True, text=True, env=env, cwd=tmp, timeout=120)
        check(r.returncode == 0, f"the venv cannot import rodend: {r.stderr[-2000:]}")
        init, ext, version, dist = json.loads(r.stdout)
        site = os.path.join(venv, "lib")
        check(init.startswith(site) and ext.startswith(site),
              f"rodend is not imported from the venv's site-packages: {init}, {ext}")
        check(version == dist, f"the module says {version}, the installed package {dist}")
        print(f"installed: {init} ({dist}); extension {os.path.basename(ext)}")
        problems = run_examples(python, os.path.join(repo, "examples"), env)
        check(not problems, "in the venv:\n" + "\n".join(problems))
    finish("python_package")


if __name__ == "__main__":
    main()
