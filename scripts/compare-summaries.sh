#!/usr/bin/env bash
# Checks that a change leaves the results as they were: every shipped
# study (studies/*.json), every regression study (tests/regression/studies/*.json) and every test
# study (tests/studies/*.json) is run by the rodend of a BASE commit and by the rodend of this
# checkout (./build/rodend, built beforehand), with the same options; their summary.csv must be
# byte for byte the same, and so the case ids (the case_id column and the names of the case files).
#
# Columns that differ from one run to the next whatever the code (wall_time_s, started_utc,
# finished_utc) are blanked on both sides before the comparison; every other byte counts.
#
# Short runs: a study whose time.end is longer than END (default 0.05 s) runs with
# --set time.end=END on both sides (stated in the output; the case ids include it, on both sides).
# A study that refuses the override (exit 2 on the base) runs as shipped.
#
# Usage: bash scripts/compare-summaries.sh [BASE]   (default: git merge-base HEAD main)
#   END=0.05 JOBS=2 KEEP=1 (keeps the scratch directory) ONLY=regex (studies whose path matches)
#   NEW_RODEND=path (the rodend to check instead of ./build/rodend)
# Exit 0: all the same; 1: differences (listed); 2: a build or run failed.
set -uo pipefail
cd "$(dirname "$0")/.."
repo=$(pwd)
base=${1:-$(git merge-base HEAD main)}
base=$(git rev-parse --verify "$base^{commit}") || exit 2
end=${END:-0.05}
jobs=${JOBS:-2}
new_rodend="${NEW_RODEND:-$repo/build/rodend}"
[ -x "$new_rodend" ] || { echo "compare-summaries: build this checkout first ($new_rodend)" >&2; exit 2; }
work=$(mktemp -d /tmp/rodend-compare.XXXXXX)
tree="$work/base"
cleanup() {
  git -C "$repo" worktree remove --force "$tree" > /dev/null 2>&1 || true
  [ -n "${KEEP:-}" ] || rm -rf "$work"
}
trap cleanup EXIT

# 1. the base commit's rodend, in a scratch worktree (ccache when there is one)
git worktree add --detach "$tree" "$base" > /dev/null 2>&1 || { echo "cannot check out $base" >&2; exit 2; }
launcher=()
if command -v ccache > /dev/null; then
  export CCACHE_BASEDIR="$work"
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
fi
echo "compare-summaries: building rodend at $(git log -1 --format='%h %s' "$base" | cut -c1-80)"
if ! { cmake -S "$tree" -B "$tree/build" -DCMAKE_BUILD_TYPE=Release -DRODEND_BUILD_TESTS=OFF -DRODEND_PYTHON=OFF \
         -DRODEND_BUILD_BENCHMARKS=OFF          "${launcher[@]}" > "$work/base-configure.log" 2>&1 &&
       cmake --build "$tree/build" --target rodend -j"$jobs" > "$work/base-build.log" 2>&1; }; then
  tail -20 "$work/base-configure.log" "$work/base-build.log" >&2
  exit 2
fi
old_rodend="$tree/build/rodend"

# 2. the studies, run by both, compared
normalise() {  # summary.csv with the per-run columns blanked (by header name)
  /usr/bin/python3 - "$1" << 'EOF'
import csv, io, sys
volatile = {"wall_time_s", "started_utc", "finished_utc"}
rows = list(csv.reader(io.StringIO(open(sys.argv[1], newline="").read(), newline="")))
drop = [i for i, name in enumerate(rows[0]) if name in volatile]
for row in rows[1:]:
    for i in drop:
        row[i] = ""
out = io.StringIO()
csv.writer(out, lineterminator="\n").writerows(rows)
sys.stdout.write(out.getvalue())
EOF
}
status=0
count=0
differ=0
for study in studies/*.json tests/regression/studies/*.json tests/studies/*.json; do
  [[ -n "${ONLY:-}" && ! "$study" =~ $ONLY ]] && continue
  count=$((count + 1))
  name=$(basename "$study" .json)
  set_args=()
  study_end=$(/usr/bin/python3 -c "import json,sys; t=json.load(open(sys.argv[1])).get('time',{}); print(t.get('end', '') if isinstance(t, dict) else '')" "$study")
  if [ -n "$study_end" ] && /usr/bin/python3 -c "import sys; sys.exit(0 if float(sys.argv[1]) > float(sys.argv[2]) else 1)" "$study_end" "$end"; then
    set_args=(--set "time.end=$end")
  fi
  run_side() {  # rodend, results root, log
    "$1" run -q -j "$jobs" --results-root "$2" "${set_args[@]}" "$repo/$study" > "$3" 2>&1
  }
  run_side "$old_rodend" "$work/old" "$work/$name.old.log"
  old_rc=$?
  if [ "$old_rc" = 2 ] && [ ${#set_args[@]} -gt 0 ]; then
    set_args=()  # the study refuses the short end time: as shipped
    rm -rf "$work/old"
    run_side "$old_rodend" "$work/old" "$work/$name.old.log"
    old_rc=$?
  fi
  run_side "$new_rodend" "$work/new" "$work/$name.new.log"
  new_rc=$?
  label="$study ${set_args[*]:-(as shipped)}"
  old_dir=$(ls -d "$work"/old/*/ 2> /dev/null | head -1)
  new_dir=$(ls -d "$work"/new/*/ 2> /dev/null | head -1)
  problem=""
  if [ "$old_rc" != "$new_rc" ]; then
    problem="exit $old_rc before, $new_rc after"
  elif [ "$old_rc" = 2 ]; then
    problem="refused by both (exit 2): $(tail -1 "$work/$name.new.log")"
  elif [ -z "$old_dir" ] || [ -z "$new_dir" ] || [ ! -f "$old_dir/summary.csv" ] || [ ! -f "$new_dir/summary.csv" ]; then
    problem="no summary.csv"
  elif ! cmp -s <(head -1 "$old_dir/summary.csv") <(head -1 "$new_dir/summary.csv"); then
    problem="summary.csv header differs"
  elif ! cmp -s <(normalise "$old_dir/summary.csv") <(normalise "$new_dir/summary.csv"); then
    problem="summary.csv differs: $(diff <(normalise "$old_dir/summary.csv") <(normalise "$new_dir/summary.csv") | head -3 | cut -c1-200 | tr '\n' ' ')"
  elif ! cmp -s <(ls "$old_dir/cases") <(ls "$new_dir/cases"); then
    problem="case files differ: $(diff <(ls "$old_dir/cases") <(ls "$new_dir/cases") | head -3 | tr '\n' ' ')"
  fi
  rows=$([ -n "$new_dir" ] && [ -f "$new_dir/summary.csv" ] && echo $(($(wc -l < "$new_dir/summary.csv") - 1)) || echo 0)
  if [ -n "$problem" ]; then
    echo "DIFFERENT  $label: $problem"
    differ=$((differ + 1))
    [ "$old_rc" = 2 ] || status=1
  else
    echo "same       $label ($rows cases, exit $new_rc)"
  fi
  rm -rf "$work/old" "$work/new"
done
echo "compare-summaries: $count studies against $(git rev-parse --short "$base"); $differ different"
exit $status
