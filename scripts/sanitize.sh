#!/usr/bin/env bash
# The test suite under AddressSanitizer + UndefinedBehaviorSanitizer (docs/testing.md).
# Builds build-asan/ (RelWithDebInfo, -DRODEND_SANITIZE=ON; without the Python module, which a
# plain python3 cannot load when it is ASan-instrumented) and runs CTest there; any sanitizer
# report aborts the test that triggered it. Extra arguments go to ctest:
#
#   bash scripts/sanitize.sh               # the whole suite (command-line tests included)
#   RODEND_BUILD_TARGETS=rodend_tests bash scripts/sanitize.sh -E '^cli\.'
#                                          # the unit tests only, nothing else built (.ci/run)
set -euo pipefail
cd "$(dirname "$0")/.."
RODEND_BUILD_DIR=build-asan RODEND_BUILD_TYPE=RelWithDebInfo \
  RODEND_CMAKE_ARGS="-DRODEND_SANITIZE=ON -DRODEND_BUILD_BENCHMARKS=OFF -DRODEND_PYTHON=OFF ${RODEND_CMAKE_ARGS:-}" \
  bash scripts/setup.sh
cd build-asan
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
ctest --output-on-failure -j"$(nproc)" "$@"
