#!/usr/bin/env bash
# Proves the waveform recipe: an input waveform is one line of core/scenes/waveforms.def plus
# its formula in Waveform::at (core/scenes/drivers.cpp), and nothing else. In a throwaway git
# worktree of HEAD it adds the waveform "throwaway", offset + A (1 - cos(2 pi f tau))/2 over
# `cycles` periods of one frequency, checks with git that only those two lines changed, builds
# rodend there (Release) and checks that the waveform arrives everywhere:
#   `rodend choices --json`: in the menus waveforms, motion_shapes and hinge_moments (before
#   profile), and `rodend params servo-actuator --json` as an allowed command.shape;
#   a run of servo-actuator commanded by it: status ok, its actuator_command history equal to the
#   formula at every sample (1e-12 m);
#   a run of rod-end-actuator whose hinge moment is the waveform: status ok.
# Cost: one Release build of rodend (every C++ file of core/, sweep/ and app/, about 150), then
# 2 cases. Alone, or with the others by scripts/prove.sh (CTest: prove).
# Usage: bash scripts/prove-waveform.sh
source "$(dirname "$0")/prove-common.sh"

recipe() {
# 1. the waveform: one catalogue line, and its formula
echo 'RODEND_CHOICE(throwaway, "throwaway", "offset + A (1 - cos(2 pi f tau))/2, added by scripts/prove-waveform.sh", true)' \
  >> core/scenes/waveforms.def
sed -i 's|^  if (kind == Kind::triangle) {$|  if (kind == Kind::throwaway) return {offset + 0.5 * amplitude * (1.0 - std::cos(kTwoPi * phase)), 0.5 * amplitude * kTwoPi * f * std::sin(kTwoPi * phase), 0.5 * amplitude * kTwoPi * kTwoPi * f * f * std::cos(kTwoPi * phase)};\n&|' \
  core/scenes/drivers.cpp
prove_lines prove-waveform core/scenes/waveforms.def 1 0
prove_lines prove-waveform core/scenes/drivers.cpp 1 0
prove_changed prove-waveform " M core/scenes/drivers.cpp" " M core/scenes/waveforms.def"
}

check() {
# 2. every place the new thing should appear
./build/rodend choices --json > "$work/choices.json"
./build/rodend params servo-actuator --json > "$work/params.json"
cat > "$work/wave.json" <<'JSON'
{"name": "wave", "scene": "servo-actuator", "time": {"end": 0.6, "sample_interval": 1e-3},
 "parameters": {"command.shape": "throwaway", "command.amplitude": 0.004,
                "command.frequency": 5.0, "command.offset": 0.001, "command.start_time": 0.1,
                "command.cycles": 2},
 "signals": ["actuator_command"]}
JSON
cat > "$work/hinge.json" <<'JSON'
{"name": "hinge", "scene": "rod-end-actuator", "time": {"end": 0.05, "sample_interval": 1e-3},
 "parameters": {"hinge.kind": "throwaway", "hinge.amplitude": 50.0, "hinge.frequency": 40.0}}
JSON
./build/rodend run "$work/wave.json" --results-root "$work/out" -q
./build/rodend run "$work/hinge.json" --results-root "$work/out" -q
/usr/bin/python3 - "$work" <<'PY'
import csv, json, math, sys
import h5py, numpy as np
work = sys.argv[1]
menus = json.load(open(f"{work}/choices.json"))
names = {k: [c["name"] for c in m["choices"]] for k, m in menus.items()}
assert names["waveforms"][-1] == "throwaway", names["waveforms"]
for menu in ("motion_shapes", "hinge_moments"):
    assert names[menu][-2:] == ["throwaway", "profile"], (menu, names[menu])
print("rodend choices: throwaway in waveforms, motion_shapes and hinge_moments")
shapes = json.load(open(f"{work}/params.json"))["command.shape"]["choices"]
assert shapes == names["motion_shapes"], shapes
print("rodend params servo-actuator --json: throwaway an allowed command.shape")
row = next(csv.DictReader(open(f"{work}/out/wave/summary.csv")))
assert row["status"] == "ok", row["message"]
with h5py.File(f"{work}/out/wave/cases/{row['case_id']}.h5", "r") as f:
    t = f["signals/time"][:]
    x = f["signals/actuator_command"][:]
tau = t - 0.1
inside = (tau >= 0) & (tau <= 2 / 5.0)
want = np.where(inside, 0.001 + 0.002 * (1 - np.cos(2 * math.pi * 5.0 * tau)), 0.001)
err = float(np.max(np.abs(x - want)))
print(f"servo-actuator commanded by throwaway: {len(t)} samples, largest error {err:.2e} m")
assert err < 1e-12, err
hinge = next(csv.DictReader(open(f"{work}/out/hinge/summary.csv")))
assert hinge["status"] == "ok", hinge["message"]
print("rod-end-actuator with hinge.kind throwaway: ok")
print("prove-waveform: ok")
PY
}

prove_main
