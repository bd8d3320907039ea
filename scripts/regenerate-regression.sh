#!/usr/bin/env bash
# Regenerates the regression references in tests/regression/reference/ from the studies in
# tests/regression/studies/. Run it only when a change is meant to move results.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for s in tests/regression/studies/*.json; do
  name=$(basename "$s" .json)
  ./build/rodend run "$s" --results-root "$tmp" -q --threads "$(nproc)"
  mkdir -p "tests/regression/reference/$name"
  cp "$tmp/$name/summary.h5" "$tmp/$name/summary.csv" "tests/regression/reference/$name/"
  echo "regenerated tests/regression/reference/$name"
done
