#!/usr/bin/env bash
# Proves the two recipes of docs/architecture.md: a contact law is its own file plus
# one catalogue line, and a scene is its code, its scene file naming parts, plus one
# registration line. In a throwaway git worktree of HEAD it adds
#   - a law "throwaway" (core/laws/throwaway.cpp, chi = 1.2 (1 - c_r), and one line in
#     core/laws/normal_laws.def), and
#   - a scene "throwaway-drop" (core/scenes/throwaway_drop.cpp, core/scenes/throwaway-drop.params.json,
#     and one line in core/scenes/scenes.def), built from gravity-drop's code and parts,
# checks with git that nothing else changed, builds rodend there, and runs one case of each:
# the law in gravity-drop and impact-pair, the scene with the new law. Fails unless both runs
# are ok and the law's achieved restitution lies between those of Hertz (1) and Hunt-Crossley.
# Takes a few minutes (a build of rodend); scripts/prove.sh runs it with the others (CTest: prove).
# Exit 77 (skipped) outside a git checkout. Usage: bash scripts/prove-recipes.sh
source "$(dirname "$0")/prove-common.sh"

recipe() {
# 1. the law: its own file and one catalogue line
sed -e 's/Hunt-Crossley: chi = 3(1 - c_r)\/2 (model-notes §3)/Throwaway law of scripts\/prove-recipes.sh: chi = 1.2 (1 - c_r)/' \
    -e 's/"hunt-crossley"/"throwaway"/' -e 's/1\.5 \* (1\.0 - cr)/1.2 * (1.0 - cr)/' \
    -e 's/hunt_crossley_law/throwaway_law/' core/laws/hunt_crossley.cpp > core/laws/throwaway.cpp
echo 'RODEND_NORMAL_LAW(throwaway_law)' >> core/laws/normal_laws.def

# 2. the scene: its code, its scene file (naming parts), one registration line
sed -e 's/gravity-drop/throwaway-drop/g' -e 's/GravityDropScene/ThrowawayDropScene/g' \
    -e 's/make_gravity_drop_scene/make_throwaway_drop_scene/g' \
    core/scenes/gravity_drop.cpp > core/scenes/throwaway_drop.cpp
sed -e 's/"gravity-drop"/"throwaway-drop"/' core/scenes/gravity-drop.params.json \
  > core/scenes/throwaway-drop.params.json
echo 'RODEND_SCENE("throwaway-drop", make_throwaway_drop_scene, "gravity-drop again, added by scripts/prove-recipes.sh")' \
  >> core/scenes/scenes.def
grep -q make_throwaway_drop_scene core/scenes/throwaway_drop.cpp

prove_changed prove-recipes " M core/laws/normal_laws.def" " M core/scenes/scenes.def" \
  "?? core/laws/throwaway.cpp" "?? core/scenes/throwaway-drop.params.json" \
  "?? core/scenes/throwaway_drop.cpp"
prove_lines prove-recipes core/laws/normal_laws.def 1 0
prove_lines prove-recipes core/scenes/scenes.def 1 0
}

check() {
cat > "$work/law.json" <<'JSON'
{"name": "law", "scene": "impact-pair", "time": {"end": 2e-3, "sample_interval": 1e-5},
 "parameters": {"contact.restitution": 0.5},
 "grid": [{"key": "parameters.contact.law", "values": ["hertz", "throwaway", "hunt-crossley"]}]}
JSON
cat > "$work/scene.json" <<'JSON'
{"name": "scene", "scene": "throwaway-drop", "time": {"end": 0.05, "sample_interval": 1e-3},
 "parameters": {"contact.law": "throwaway", "contact.restitution": 0.5}}
JSON
./build/rodend choices --json > "$work/choices.json"
/usr/bin/python3 - "$work/choices.json" <<'PY'
import json, sys
menus = json.load(open(sys.argv[1]))
names = {k: [c["name"] for c in m["choices"]] for k, m in menus.items()}
assert names["normal_laws"][-1] == "throwaway", names["normal_laws"]
assert names["scenes"][-1] == "throwaway-drop", names["scenes"]
print("rodend choices: throwaway a normal law, throwaway-drop a scene")
PY
./build/rodend run "$work/law.json" --results-root "$work/out" -q
./build/rodend run "$work/scene.json" --results-root "$work/out" -q
PYTHONPATH="$tree/python" /usr/bin/python3 - "$work/out" <<'PY'
import sys
from rodend import summary_rows
out = sys.argv[1]
law = {r["parameters.contact.law"]: r for r in summary_rows(f"{out}/law")}
scene = summary_rows(f"{out}/scene")
e = {k: float(r["first_impact_restitution"]) for k, r in law.items()}
print("achieved restitution, impact-pair, c_r 0.5:", ", ".join(f"{k} {v:.4f}" for k, v in e.items()))
print("scene throwaway-drop:", scene[0]["status"], "impacts", scene[0]["impact_count"])
assert all(r["status"] == "ok" for r in law.values()), "a law case failed"
assert scene[0]["status"] == "ok" and scene[0]["scene"] == "throwaway-drop", "the scene case failed"
# chi = 1.2 (1 - c_r) damps less than Hunt-Crossley's 1.5 (1 - c_r) and more than Hertz's 0
assert e["hunt-crossley"] < e["throwaway"] < e["hertz"], e
print("prove-recipes: ok")
PY
}

prove_main
