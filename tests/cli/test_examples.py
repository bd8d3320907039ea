"""examples/ run: each script under /usr/bin/python3,
output into a temporary folder, must exit 0 (each asserts its own physics) and write its
figure; each notebook (examples/*.ipynb: a study run, its summary as a grid-shaped Dataset, a
history plotted with .plot(), an interrupted and resumed run) is executed cell by cell and must
draw its figures (tests/cli/examples_runner.py).

    test_examples.py EXAMPLES_DIR
"""
import sys

from common import check, finish
from examples_runner import run_examples


def main():
    problems = run_examples("/usr/bin/python3", sys.argv[1])
    check(not problems, "\n".join(problems))
    finish("examples")


if __name__ == "__main__":
    main()
