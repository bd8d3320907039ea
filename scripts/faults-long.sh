#!/usr/bin/env bash
# The long fault scenarios (docs/testing.md, "Faults"), beyond what the default
# suite runs in seconds:
#   - a real full disk: a study run into a small tmpfs (needs root to mount it; skipped with a
#     message otherwise): exit 2, one message, earlier results intact, resume completes;
#   - damaged case files: 4 KiB zeroed at random offsets, SEEDS seeds per kind (uncompressed
#     history data, compressed chunks, anywhere in the file), detected by merge and resume;
#   - kill -9 at random moments of a sweep (tests/cli/test_resume.py), resume identical.
#
#   bash scripts/faults-long.sh                 # RODEND=./build/rodend, SEEDS=20
#   SEEDS=50 RODEND=/path/to/rodend bash scripts/faults-long.sh
set -euo pipefail
cd "$(dirname "$0")/.."
export RODEND="$(realpath "${RODEND:-./build/rodend}")"
seeds=${SEEDS:-20}
cd tests/cli
status=0
/usr/bin/python3 test_full_disk.py || status=1
/usr/bin/python3 test_corruption.py "$seeds" || status=1
/usr/bin/python3 test_resume.py random || status=1
[ "$status" = 0 ] && echo "faults-long: all passed" || echo "faults-long: FAILED" >&2
exit "$status"
