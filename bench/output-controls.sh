#!/usr/bin/env bash
# File size and write cost of the output controls (output.compression_level,
# output.history_precision) on studies/bench-32.json:
#   - size: the whole study's case files (32 cases), run natively once per setting;
#   - write cost: instructions (callgrind, deterministic) of write_case_file, inclusive, for the
#     study's first case (a one-case copy of bench-32 at its first grid point), per setting.
# Prints one table row per setting. Takes ~15 min on the 2-core VM (callgrind).
#
#   bash bench/output-controls.sh [levels...]     # default: 0 1 2 3 4 6 9 12
set -euo pipefail
cd "$(dirname "$0")/.."
rodend=${RODEND:-./build/rodend}
levels=("$@")
[ ${#levels[@]} -eq 0 ] && levels=(0 1 2 3 4 6 9 12)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
study() {  # $1 level, $2 precision, $3 "all" | "first" -> study file
  /usr/bin/python3 - "$1" "$2" "$3" "$tmp/s-$1-$2-$3.json" <<'PY'
import json, sys
level, precision, which, out = int(sys.argv[1]), sys.argv[2], sys.argv[3], sys.argv[4]
s = json.load(open("studies/bench-32.json"))
s["name"] = f"oc-{level}-{precision}-{which}"
s["output"] = {"compression_level": level, "history_precision": precision}
if which == "first":
    s["parameters"] = {"contact": {"clearance": s["grid"][0]["linspace"][0]},
                       "socket": {"misalignment_z": s["grid"][1]["values"][0]}}
    del s["grid"]
json.dump(s, open(out, "w"))
print(out)
PY
}
printf "| compression_level | history_precision | bench-32 case files [MB] | write_case_file, first case [M instr] |\n|---|---|---|---|\n"
row() {
  local all first size instr
  all=$(study "$1" "$2" all)
  "$rodend" run "$all" --results-root "$tmp/r" -q --threads 2 >/dev/null
  size=$(du -cb "$tmp"/r/oc-"$1"-"$2"-all/cases/*.h5 | tail -1 | cut -f1)
  first=$(study "$1" "$2" first)
  valgrind --tool=callgrind --callgrind-out-file="$tmp/cg.out" "$rodend" run "$first" \
    --results-root "$tmp/r" -q -j 1 >/dev/null 2>&1
  instr=$(callgrind_annotate --inclusive=yes "$tmp/cg.out" 2>/dev/null |
    awk '/rodend::write_case_file/ && !done {gsub(",", "", $1); print $1; done = 1}')
  awk -v l="$1" -v p="$2" -v s="$size" -v i="$instr" \
    'BEGIN {printf "| %s | %s | %.1f | %.1f |\n", l, p, s / 1e6, i / 1e6}'
}
for l in "${levels[@]}"; do row "$l" float64; done
row 0 float32
row "${levels[2]:-2}" float32
