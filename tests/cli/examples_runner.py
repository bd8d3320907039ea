"""Runs the examples as a user would: every examples/*.py with an output folder as its
argument (it must exit 0, each asserting its own physics, and write a figure), and every
examples/*.ipynb executed cell by cell (nbclient, Debian's python3-nbclient and
python3-ipykernel) in a scratch folder, twice in a row ("Run All" again must work), each cell
asserting its own results. The notebook names its kernel, `rodend`; as scripts/setup.sh
registers the clone's .venv under that name, this registers the given Python under it (in a
temporary folder on JUPYTER_PATH, nothing in the user's home) and runs the notebook through
that kernelspec as Jupyter would: nothing of the kernel's command line is patched.

    /path/to/python examples_runner.py EXAMPLES_DIR     # what the tests run
"""
import glob
import json
import os
import shutil
import subprocess
import sys
import tempfile

NOTEBOOK = r"""
import sys, nbformat, nbclient
nb = nbformat.read(sys.argv[1], as_version=4)
# a first cell, added here: which Python the kernel runs
nb.cells.insert(0, nbformat.v4.new_code_cell("import sys; print(sys.executable)"))
for run in (1, 2):  # "Run All", then again
    nbclient.NotebookClient(nb, timeout=300, resources={"metadata": {"path": "."}}).execute()
    kernel = nb.cells[0].outputs[0]["text"].strip()
    if kernel != sys.executable:
        sys.exit(f"run {run}: the kernel ran {kernel}, not {sys.executable}")
nb.cells.pop(0)
images = sum(1 for c in nb.cells if c.cell_type == "code" for o in c.outputs
             if "image/png" in o.get("data", {}))
print(f"{len(nb.cells)} cells executed twice, {images} figure(s)")
sys.exit(0 if images else 3)
"""


def register_kernel(python, folder, env):
    """`python -m ipykernel install --prefix FOLDER --name rodend`, as setup.sh does with
    --user; returns the JUPYTER_PATH entry that finds it."""
    r = subprocess.run([python, "-m", "ipykernel", "install", "--prefix", folder, "--name",
                        "rodend", "--display-name", "Python (rodend)",
                        "--env", "PYDEVD_DISABLE_FILE_VALIDATION", "1"],
                       capture_output=True, text=True, env=env, timeout=300)
    if r.returncode != 0:
        raise RuntimeError(f"ipykernel install failed: {r.stderr[-2000:]}")
    spec = os.path.join(folder, "share", "jupyter", "kernels", "rodend", "kernel.json")
    with open(spec, encoding="utf-8") as fh:
        argv = json.load(fh)["argv"]
    if argv[0] != python:
        raise RuntimeError(f"the kernelspec runs {argv[0]}, not {python}")
    return os.path.join(folder, "share", "jupyter")


def run_examples(python, examples, env=None):
    """Runs every example under `python`; returns a list of failures (empty when all pass)."""
    env = dict(env if env is not None else os.environ, MPLBACKEND="Agg",
               PYDEVD_DISABLE_FILE_VALIDATION="1")
    failures, ran = [], 0
    for path in sorted(glob.glob(os.path.join(examples, "*.py")) +
                       glob.glob(os.path.join(examples, "*.ipynb"))):
        name, out = os.path.basename(path), tempfile.mkdtemp(prefix="rodend-example-")
        try:
            if path.endswith(".py"):
                cmd = [python, path, out]
            else:
                env.pop("MPLBACKEND", None)  # the notebook's inline figures
                env["JUPYTER_PATH"] = register_kernel(python, os.path.join(out, ".kernel"), env)
                cmd = [python, "-c", NOTEBOOK, path]
            r = subprocess.run(cmd, capture_output=True, text=True, timeout=900, cwd=out, env=env)
            ran += 1
            if r.returncode != 0:
                failures.append(f"{name} failed ({r.returncode}):\n{r.stdout}\n{r.stderr[-3000:]}")
            elif path.endswith(".py") and not glob.glob(os.path.join(out, "*.png")):
                failures.append(f"{name}: no figure")
            else:
                print(f"{name}: ok {r.stdout.strip()[-300:]}")
        finally:
            shutil.rmtree(out, ignore_errors=True)
    if ran < 4 or not glob.glob(os.path.join(examples, "*.ipynb")):
        failures.append(f"expected at least 3 scripts and a notebook in {examples}, ran {ran}")
    return failures


if __name__ == "__main__":
    problems = run_examples(sys.executable, sys.argv[1])
    print("\n".join(problems) or "all examples ran")
    sys.exit(1 if problems else 0)
