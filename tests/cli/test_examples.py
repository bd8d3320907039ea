"""examples/*.py run (issue 22): each one under /usr/bin/python3, output into a temporary
folder, must exit 0 (each asserts its own physics) and write its figure.

    test_examples.py EXAMPLES_DIR
"""
import glob
import os
import shutil
import subprocess
import sys
import tempfile

from common import check, finish


def main():
    scripts = sorted(glob.glob(os.path.join(sys.argv[1], "*.py")))
    check(len(scripts) >= 3, f"expected at least 3 examples, found {scripts}")
    for script in scripts:
        out = tempfile.mkdtemp(prefix="rodend-example-")
        try:
            r = subprocess.run(["/usr/bin/python3", script, out], capture_output=True, text=True,
                               timeout=300)
            check(r.returncode == 0,
                  f"{os.path.basename(script)} failed ({r.returncode}):\n{r.stdout}\n{r.stderr}")
            check(glob.glob(os.path.join(out, "*.png")), f"{os.path.basename(script)}: no figure")
            print(f"{os.path.basename(script)}: ok\n{r.stdout}")
        finally:
            shutil.rmtree(out, ignore_errors=True)
    finish("examples")


if __name__ == "__main__":
    main()
