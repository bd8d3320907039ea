#!/usr/bin/env bash
# Quick start, command 1: set up (the Debian packages, configure, build only what this needs:
# the rodend executable and the Python module, and the package in .venv), run the default
# study into results/, and draw its figures. Each step prints what it took. Warnings are not
# errors in this build (a newer compiler's new warning must not stop a user); the tests' build
# and CI keep -Werror. `bash scripts/test.sh` builds the rest (tests, benchmarks) in the same
# build directory, recompiling nothing this built.
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
RODEND_BUILD_TARGETS="${RODEND_BUILD_TARGETS:-rodend _rodend}" RODEND_WERROR_DEFAULT=OFF \
  bash scripts/setup.sh
study="${1:-studies/default.json}"
t0=$(date +%s)
./build/rodend run "$study" --threads "$(nproc)"
echo "main: running $study took $(($(date +%s) - t0)) s" >&2
if [ -f plots/plot_study.py ]; then
  t0=$(date +%s)
  out=$(./build/rodend results-dir "$study")
  /usr/bin/python3 plots/plot_study.py "$out"
  echo "main: the figures took $(($(date +%s) - t0)) s" >&2
fi
echo "main: done in $(($(date +%s) - start)) s" >&2
