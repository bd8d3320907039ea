#!/usr/bin/env bash
# Quick start, command 2: set up, build, and run the whole test suite (CTest).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cd "${RODEND_BUILD_DIR:-build}"
ctest --output-on-failure -j"$(nproc)" "$@"
