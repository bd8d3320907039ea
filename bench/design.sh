#!/usr/bin/env bash
# Resolving a large sampled design: `rodend run --dry-run` of a 1e5-point Sobol'
# design over four factors of rod-end-actuator (every case resolved, its scene built and
# checked, its id computed, and the table printed), wall time and peak RSS, REPEATS times.
#   bash bench/design.sh [BUILD_DIR]        (REPEATS=3, SIZE=100000 by default)
set -euo pipefail
build="${1:-build}"
repeats="${REPEATS:-3}"
size="${SIZE:-100000}"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cat > "$tmp/design-bench.json" <<JSON
{"name": "design-bench", "scene": "rod-end-actuator",
 "time": {"end": 2.4, "sample_interval": 1e-3},
 "design": {"method": "sobol", "size": $size, "seed": 1, "factors": [
   {"key": "parameters.contact.clearance", "distribution": "triangular", "lower": 1e-4, "mode": 2e-4, "upper": 5e-4},
   {"key": "parameters.socket.misalignment_z", "distribution": "truncated-normal", "mean": 0, "std": 3e-5, "lower": -9e-5, "upper": 9e-5},
   {"key": "parameters.hinge.constant_moment", "distribution": "normal", "mean": 0, "std": 100},
   {"key": "parameters.friction.dynamic_coefficient", "distribution": "uniform", "lower": 0.05, "upper": 0.12}]}}
JSON
echo "dry-run of a $size-point Sobol' design (4 factors, rod-end-actuator): wall s, user cpu s, peak RSS kB"
for _ in $(seq "$repeats"); do
  /usr/bin/time -f "%e %U %M" "$build/rodend" run "$tmp/design-bench.json" --dry-run \
    --results-root "$tmp" 2>&1 >/dev/null | tail -1
done
