#!/usr/bin/env bash
# The fault and signal tests under load (docs/testing.md, "Under load"): runs every test with the
# CTest label `faults` (and the unit tests tagged [faults]) PASSES times in a row, each pass
# beside BUSY busy loops (`yes > /dev/null`, one per core by default), and fails if any run of
# any test fails. A user's CI is often a loaded machine: these tests wait for states of the run
# (a case file renamed, a message written, a handler installed), never for a time.
#
#   bash scripts/stress-tests.sh                    # build/, 3 passes, nproc busy loops
#   PASSES=5 BUSY=6 bash scripts/stress-tests.sh -R 'faults|mpi'   # extra ctest arguments
#
# Not part of the default suite: three passes take several minutes (most of it
# cli.alloc_failures).
set -euo pipefail
cd "$(dirname "$0")/.."
build=$(realpath "${RODEND_BUILD_DIR:-build}")
passes=${PASSES:-3}
busy=${BUSY:-$(nproc)}
[ -x "$build/rodend" ] || { echo "stress-tests: no $build/rodend (build first)" >&2; exit 2; }

pids=()
stop_busy() {
  for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
  for pid in "${pids[@]}"; do wait "$pid" 2>/dev/null || true; done
}
trap stop_busy EXIT
for _ in $(seq "$busy"); do
  yes > /dev/null &
  pids+=($!)
done
echo "stress-tests: $busy busy loop(s) started (pids ${pids[*]}); $passes pass(es)"

failed=0
for pass in $(seq "$passes"); do
  echo "=== pass $pass of $passes: load $(cut -d' ' -f1-3 /proc/loadavg)"
  if ! (cd "$build" && ctest -L faults --output-on-failure "$@"); then
    echo "stress-tests: pass $pass: a ctest test failed" >&2
    failed=1
  fi
  if ! "$build/tests/rodend_tests" "[faults]"; then
    echo "stress-tests: pass $pass: a unit test tagged [faults] failed" >&2
    failed=1
  fi
done
if [ "$failed" = 0 ]; then
  echo "stress-tests: $passes pass(es) beside $busy busy loop(s): every test passed"
else
  echo "stress-tests: FAILED" >&2
fi
exit "$failed"
