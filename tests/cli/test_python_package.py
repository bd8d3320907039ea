"""rodend installs into a fresh virtual environment with the documented command and the
examples run there (docs/python.md "Installing").

    test_python_package.py REPO BUILD_DIR

The venv is `python3 -m venv --system-site-packages` (numpy, h5py, pandas, xarray and
matplotlib from Debian), the install `pip install --no-build-isolation REPO` with --no-index
(nothing is downloaded: every dependency must already be there). With no RODEND_PIP_BUILD_DIR,
setup.py finds the clone's build (RODEND_BUILD_DIR names this test's), configured for
/usr/bin/python3, whose extensions the venv's python loads: it reuses it (builds the target
_rodend, up to date: no compilation) and says so; its build of a fresh CMake directory is the
same code after a configure step. Then, with no PYTHONPATH and no RODEND_BUILD_DIR, the venv's
python imports rodend from its own site-packages, its version is the project's, and every
example (scripts and notebook) runs.

A venv without Debian's packages (no wheel, numpy, ...) is refused before anything is built,
with what is missing and how to get it (it used to fail with setuptools' "invalid command
'bdist_wheel'").
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
        r = subprocess.run([python, "-m", "pip", "install", "-v", "--no-index", "--no-cache-dir",
                            "--no-build-isolation", repo], capture_output=True, text=True,
                           env=dict(env, RODEND_BUILD_DIR=build), cwd=tmp, timeout=1800)
        check(r.returncode == 0, f"pip install failed ({r.returncode}):\n{r.stdout[-3000:]}\n"
              f"{r.stderr[-3000:]}")
        check(f"rodend: reusing the CMake build {build}" in r.stdout + r.stderr,
              f"pip install did not reuse {build}:\n{(r.stdout + r.stderr)[-3000:]}")
        plain = os.path.join(tmp, "plain")
        subprocess.run(["/usr/bin/python3", "-m", "venv", plain], check=True, env=env, timeout=300)
        r = subprocess.run([os.path.join(plain, "bin", "python"), "-m", "pip", "install",
                            "--no-index", "--no-cache-dir", "--no-build-isolation", repo],
                           capture_output=True, text=True, env=env, cwd=tmp, timeout=600)
        out = r.stdout + r.stderr
        check(r.returncode != 0 and "missing build requirements: wheel" in out and
              "python3-wheel" in out and "pip install setuptools wheel pybind11 numpy" in out and
              "bdist_wheel" not in out, f"a venv without wheel: exit {r.returncode}:\n{out[-3000:]}")
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
