#!/usr/bin/env bash
# Measures the sweep engine for the record, on a quiet machine (nothing else running):
#   - bench-32 (studies/bench-32.json, 32 cases) with 1 thread, 2 threads and, when mpirun is
#     present and the build has MPI, `mpirun -np 2` (one thread per rank): whole-process wall
#     time, REPEATS interleaved rounds (each round runs every configuration once, in turn, so a
#     drift of the machine's speed hits them alike), fresh results folder every run; the median
#     per configuration, as cases per hour and as the ratio to one thread;
#   - how long the HDF5 lock (the serial section of writing case files) is held, with 1 and 2
#     threads (RODEND_LOCK_STATS=1: wall time and the holder's CPU time, summed);
#   - peak resident memory (GNU time) for 16 and 256 cases of the same per-case size.
#
#   bash scripts/measure-sweep.sh              # REPEATS=5 by default
#   REPEATS=9 RODEND=./build/rodend bash scripts/measure-sweep.sh
set -euo pipefail
cd "$(dirname "$0")/.."
rodend=${RODEND:-./build/rodend}
repeats=${REPEATS:-5}
study=studies/bench-32.json
cases=32
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

configs=("1 thread" "2 threads")
mpirun_bin=$(command -v mpirun || true)
[ -n "$mpirun_bin" ] && configs+=("mpirun -np 2")

run_config() {  # $1 = configuration; prints the wall time [s]
  rm -rf "$tmp/r"
  # Case files are not fsync'd (their checksum guards them), so the kernel writes the previous
  # run's files back while the next one computes; flush them first, outside the timed interval,
  # so that every run starts from the same clean page cache.
  sync
  local s e
  s=$(date +%s.%N)
  case "$1" in
    "1 thread") "$rodend" run "$study" --results-root "$tmp/r" -q --threads 1 >/dev/null 2>&1 ;;
    "2 threads") "$rodend" run "$study" --results-root "$tmp/r" -q --threads 2 >/dev/null 2>&1 ;;
    "mpirun -np 2")
      "$mpirun_bin" --allow-run-as-root --oversubscribe -np 2 "$rodend" run "$study" \
        --results-root "$tmp/r" -q --threads 1 >/dev/null 2>&1 ;;
  esac
  e=$(date +%s.%N)
  awk "BEGIN {printf \"%.4f\n\", $e - $s}"
}

declare -A times
for ((round = 1; round <= repeats; ++round)); do
  for c in "${configs[@]}"; do times[$c]+="$(run_config "$c") "; done
done

median() { tr ' ' '\n' | grep -v '^$' | sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2] + a[NR/2+1]) / 2}'; }
base=$(echo "${times["1 thread"]}" | median)
printf "%-14s %10s %14s %10s   %s\n" "bench-32" "median [s]" "cases / hour" "ratio" "runs [s]"
for c in "${configs[@]}"; do
  m=$(echo "${times[$c]}" | median)
  awk -v c="$c" -v m="$m" -v b="$base" -v n="$cases" -v runs="${times[$c]}" \
    'BEGIN {printf "%-14s %10.3f %14.0f %9.2fx   %s\n", c, m, n * 3600 / m, b / m, runs}'
done
# the serial section: how long the process-wide HDF5 lock was held (sweep/results/lock.cpp)
for j in 1 2; do
  rm -rf "$tmp/l"
  RODEND_LOCK_STATS=1 "$rodend" run "$study" --results-root "$tmp/l" -q --threads "$j" 2>&1 >/dev/null |
    sed -n "s/^rodend: HDF5 lock/bench-32, $j thread(s): HDF5 lock/p"
done
for s in bench-16-short bench-256; do
  rm -rf "$tmp/m"
  /usr/bin/time -f "$s peak RSS [kB]: %M" "$rodend" run "studies/$s.json" --results-root "$tmp/m" -q --threads 2 2>&1 >/dev/null | grep "peak RSS"
done
echo "repeats: $repeats interleaved rounds; load average: $(cut -d' ' -f1-3 /proc/loadavg)"
