#!/usr/bin/env bash
# Peak memory flat in the number of cases: peak RSS of a real run of 16 and
# of 4,096 gravity-drop cases of the same size (one thread), and time and peak RSS of
# --dry-run (validation of every case) for 1e4, 1e5 (and, with --large, 1e6) rod-end-kinematic
# cases. Figures from /usr/bin/time -v. Usage: bench/memory.sh [build-dir] [--large]
set -euo pipefail
build=${1:-build}
large=${2:-}
rodend=$(realpath "$build/rodend")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

peak() {  # peak RSS [kB] and wall time [s] of a command
  /usr/bin/time -v "$@" > /dev/null 2> "$work/time.txt" || { cat "$work/time.txt" >&2; exit 1; }
  local rss wall
  rss=$(awk -F': ' '/Maximum resident set size/ {print $2}' "$work/time.txt")
  wall=$(awk -F': ' '/Elapsed \(wall clock\)/ {print $2}' "$work/time.txt")
  echo "$rss $wall"
}

# gravity-drop: n cases = n restitutions x 1 clearance, 0.05 s each
run_grid() {
  local n=$1
  cat > "$work/gd-$n.json" <<JSON
{"name": "gd-$n", "scene": "gravity-drop", "output": "$work/out-$n",
 "time": {"end": 0.05, "sample_interval": 1e-3},
 "grid": [{"key": "parameters.contact.restitution", "linspace": [0.1, 0.9, $n]}]}
JSON
  peak "$rodend" run "$work/gd-$n.json" -j 1 -q
}
# (through a file, not a process substitution: a failed run stops the script)
run_grid 16 > "$work/peak.txt"
read -r rss16 wall16 < "$work/peak.txt"
run_grid 4096 > "$work/peak.txt"
read -r rss4096 wall4096 < "$work/peak.txt"
echo "run, gravity-drop, 16 cases:    peak RSS ${rss16} kB (wall ${wall16})"
echo "run, gravity-drop, 4096 cases:  peak RSS ${rss4096} kB (wall ${wall4096})"
awk -v a="$rss16" -v b="$rss4096" 'BEGIN {printf "4096 / 16 cases peak RSS: %.3f (target: < 1.20)\n", b / a}'

# rod-end-kinematic: 100 clearances x m hinge moments
dry() {
  local m=$1
  cat > "$work/rek-$m.json" <<JSON
{"name": "rek-$m", "scene": "rod-end-kinematic", "output": "$work/rek-$m",
 "parameters": {"hinge.kind": "constant"},
 "time": {"end": 2.4, "sample_interval": 1e-4},
 "grid": [{"key": "parameters.contact.clearance", "linspace": [1e-4, 5e-4, 100]},
          {"key": "parameters.hinge.constant_moment", "linspace": [-50, 50, $m]}]}
JSON
  peak "$rodend" run "$work/rek-$m.json" --dry-run > "$work/peak.txt"
  read -r rss wall < "$work/peak.txt"
  echo "dry-run, rod-end-kinematic, $((100 * m)) cases: wall ${wall}, peak RSS ${rss} kB"
}
dry 100
dry 1000
if [ "$large" = "--large" ]; then dry 10000; fi
