#!/usr/bin/env bash
# Quick start, command 2: set up, build everything (the tests, the benchmarks and what
# scripts/main.sh left out; what it built is up to date), and run the whole test suite (CTest).
# A build directory this configures afresh has warnings as errors (RODEND_WERROR=ON); one that
# scripts/main.sh configured keeps its setting (RODEND_WERROR=ON bash scripts/test.sh switches
# it, recompiling everything); the tests' own code is compiled with -Werror either way.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cd "${RODEND_BUILD_DIR:-build}"
ctest --output-on-failure -j"$(nproc)" "$@"
