#!/usr/bin/env bash
# Quick start, command 1: set up, build, run the default study into results/,
# and draw its figures.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
study="${1:-studies/default.json}"
./build/rodend run "$study" --threads "$(nproc)"
if [ -f plots/plot_study.py ]; then
  out=$(./build/rodend results-dir "$study")
  /usr/bin/python3 plots/plot_study.py "$out"
fi
