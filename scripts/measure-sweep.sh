#!/usr/bin/env bash
# Measures the sweep engine for the record: whole-process wall time of a 16-case study with 1 and
# 2 threads (median of 5 runs each, fresh results folder every run), and peak resident memory
# (GNU time) for 16 and 256 cases of the same per-case size.
set -euo pipefail
cd "$(dirname "$0")/.."
rodend=${RODEND:-./build/rodend}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
median() { sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
for threads in 1 2; do
  for i in 1 2 3 4 5; do
    rm -rf "$tmp/r"
    s=$(date +%s.%N)
    "$rodend" run studies/bench-16.json --results-root "$tmp/r" -q --threads "$threads" 2>/dev/null
    e=$(date +%s.%N)
    awk "BEGIN {print $e - $s}"
  done | median | sed "s/^/bench-16 wall time, $threads thread(s), median of 5 [s]: /"
done
for s in bench-16-short bench-256; do
  rm -rf "$tmp/m"
  /usr/bin/time -f "$s peak RSS [kB]: %M" "$rodend" run "studies/$s.json" --results-root "$tmp/m" -q --threads 2 2>&1 >/dev/null | grep "peak RSS"
done
echo "load average: $(cut -d' ' -f1-3 /proc/loadavg)"
