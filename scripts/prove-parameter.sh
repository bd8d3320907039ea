#!/usr/bin/env bash
# Proves the scene-parameter recipe: a parameter of a scene is one leaf of its scene file
# (core/scenes/<scene>.params.json: value, unit, source, note) plus the line of code that reads
# it, and nothing else. In a throwaway git worktree of HEAD it adds to gravity-drop the leaf
# "throwaway_gravity_scale" (1, assumed) and multiplies the scene's gravity by it, checks with git
# that only those two lines changed, builds rodend there (Release) and checks that the parameter
# arrives everywhere a parameter goes:
#   `rodend params gravity-drop` with its unit and provenance;
#   a study's grid over parameters.throwaway_gravity_scale: both cases ok, the first contact
#   after a fall of the clearance c from rest at t = sqrt(2 c / (s g)), so a scale of 1/4
#   doubles the time (to 1e-6 relative), and the value in summary.csv as its grid column;
#   `--set parameters.throwaway_gravity_scale=\"x\"`: exit 2, the message naming the key.
# Cost: one Release build of rodend (every C++ file of core/, sweep/ and app/, about 150), then
# 2 cases of about 1e3 steps. Alone, or with the others by scripts/prove.sh (CTest: prove). Usage: bash scripts/prove-parameter.sh
source "$(dirname "$0")/prove-common.sh"

recipe() {
# 1. the parameter: one leaf in the scene file, one line of code reading it
sed -i 's|^  "parameters": {$|&\n    "throwaway_gravity_scale": {"value": 1.0, "unit": "1", "source": "assumed", "note": "added by scripts/prove-parameter.sh: a factor on gravity"},|' \
  core/scenes/gravity-drop.params.json
sed -i 's|^        gravity_(p.vec3("gravity")),$|        gravity_(p.vec3("gravity") * p.number("throwaway_gravity_scale")),|' \
  core/scenes/gravity_drop.cpp
prove_lines prove-parameter core/scenes/gravity-drop.params.json 1 0
prove_lines prove-parameter core/scenes/gravity_drop.cpp 1 1
prove_changed prove-parameter " M core/scenes/gravity-drop.params.json" " M core/scenes/gravity_drop.cpp"
}

check() {
# 2. every place the new thing should appear
./build/rodend params gravity-drop | grep '^throwaway_gravity_scale = 1.0 \[1\]  (assumed: ' ||
  { echo "prove-parameter: rodend params gravity-drop does not list it" >&2; exit 1; }
cat > "$work/scale.json" <<'JSON'
{"name": "scale", "scene": "gravity-drop", "time": {"end": 0.05, "sample_interval": 1e-3},
 "grid": [{"key": "parameters.throwaway_gravity_scale", "values": [1.0, 0.25]}]}
JSON
./build/rodend run "$work/scale.json" --results-root "$work/out" -q
status=0
./build/rodend run "$work/scale.json" --results-root "$work/out2" -q \
  --set 'parameters.throwaway_gravity_scale="x"' 2> "$work/set.err" || status=$?
cat "$work/set.err"
[ "$status" = 2 ] && grep -q 'parameters.throwaway_gravity_scale' "$work/set.err" ||
  { echo "prove-parameter: a text for the number: exit $status, expected 2 naming the key" >&2; exit 1; }
/usr/bin/python3 - "$work" <<'PY'
import csv, sys
work = sys.argv[1]
rows = {float(r["parameters.throwaway_gravity_scale"]): r
        for r in csv.DictReader(open(f"{work}/out/scale/summary.csv"))}
assert all(r["status"] == "ok" for r in rows.values()), rows
t1, t4 = (float(rows[s]["first_contact_time"]) for s in (1.0, 0.25))
print(f"first contact: {t1:.9g} s at scale 1, {t4:.9g} s at scale 1/4, ratio {t4 / t1:.9f}")
assert abs(t4 / t1 - 2.0) < 2e-6, t4 / t1
print("prove-parameter: ok")
PY
}

prove_main
