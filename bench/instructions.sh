#!/usr/bin/env bash
# Instructions per case (callgrind, deterministic: meaningful on a busy machine) of one case of
# each scene, for one or more rodend binaries (e.g. a build of git c2b540e and the current one):
# the first case of each regression study (tests/regression/studies/, grid removed: the scene's
# defaults with the study's settings), impact-pair with its defaults (1 ms, sampled every 1 us),
# and the headline, studies/rod-end-kinematic.json (one thesis cycle, every signal recorded).
# Also instructions per right-hand-side call of rod-end-kinematic (Scene::derivatives,
# inclusive, over its calls) in that headline run.
#
#   bash bench/instructions.sh ./build/rodend [/path/to/other/rodend ...]
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -ge 1 ] || set -- ./build/rodend
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for s in tests/regression/studies/reg-{free-body,gravity-drop,spring-contact,servo-actuator,rod-end-kinematic,rod-end-actuator}.json; do
  /usr/bin/python3 -c "import json,sys; d=json.load(open(sys.argv[1])); d.pop('grid', None); d['name']=d['name']+'-1'; json.dump(d, open(sys.argv[2], 'w'))" "$s" "$tmp/$(basename "$s")"
done
echo '{"name": "impact-pair-1", "scene": "impact-pair", "time": {"end": 1e-3, "sample_interval": 1e-6}}' > "$tmp/impact-pair.json"
cp studies/rod-end-kinematic.json "$tmp/headline-rod-end-kinematic.json"
printf "| case |"; for b in "$@"; do printf " %s [M instr] |" "$b"; done; printf "\n|---|"; for _ in "$@"; do printf -- "---|"; done; printf "\n"
for study in "$tmp"/reg-*.json "$tmp/impact-pair.json" "$tmp/headline-rod-end-kinematic.json"; do
  printf "| %s |" "$(basename "$study" .json)"
  n=0
  for b in "$@"; do
    n=$((n + 1))
    out="$tmp/cg.$n.out"
    valgrind --tool=callgrind --callgrind-out-file="$out" "$b" run "$study" --results-root "$tmp/r$n" -q -j 1 >/dev/null 2>&1 || true
    total=$(callgrind_annotate "$out" 2>/dev/null | awk '/PROGRAM TOTALS/ {gsub(",", "", $1); print $1}')
    extra=""
    if [[ "$study" == *headline* ]]; then
      rhs=$(callgrind_annotate --inclusive=yes "$out" 2>/dev/null |
        awk '/RodEndKinematicScene::derivatives/ && !done {gsub(",", "", $1); print $1; done = 1}')
      calls=$(PYTHONPATH="$PWD/python" /usr/bin/python3 -c "import sys, rodend; print(rodend.summary_rows(sys.argv[1])[0]['rhs_calls'])" "$tmp/r$n/rod-end-kinematic" 2>/dev/null || echo 0)
      extra=$(awk -v r="$rhs" -v c="$calls" 'BEGIN {if (c > 0) printf " (rhs: %.0f instr/call over %d calls)", r / c, c}')
    fi
    rm -rf "$tmp/r$n"
    awk -v t="$total" -v e="$extra" 'BEGIN {printf " %.1f%s |", t / 1e6, e}'
  done
  printf "\n"
done
