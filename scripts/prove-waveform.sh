#!/usr/bin/env bash
# Proves the waveform recipe: an input waveform is one line of core/scenes/waveforms.def plus
# its class (core/scenes/input_waveforms.hpp: its declaration; input_waveforms.cpp: its reader
# and formula), and nothing else. In a throwaway git worktree of HEAD it adds the waveform
# "throwaway", offset + A (1 - cos(2 pi f tau))/2 over `cycles` periods of one frequency, checks
# with git that only those three files changed, builds rodend there (Release) and checks that
# the waveform arrives everywhere:
#   `rodend choices --json`: in the menus waveforms, motion_shapes and hinge_moments (before
#   profile) and load_kinds (last), and `rodend params servo-actuator --json` as an allowed
#   command.shape;
#   a run of servo-actuator commanded by it: status ok, its actuator_command history equal to the
#   formula at every sample (1e-12 m);
#   a run of rod-end-actuator whose hinge moment is the waveform: status ok;
#   a run of free-body whose force is the waveform: status ok, the velocity after its whole
#   periods the force's impulse over the mass (1e-9 relative).
# Cost: one Release build of rodend (every C++ file of core/, sweep/ and app/, about 150), then
# 3 cases. Alone, or with the others by scripts/prove.sh (CTest: prove).
# Usage: bash scripts/prove-waveform.sh
source "$(dirname "$0")/prove-common.sh"

recipe() {
# 1. the waveform: one catalogue line, and its class (declaration; reader and formula)
echo 'RODEND_CHOICE(throwaway, "throwaway", "offset + A (1 - cos(2 pi f tau))/2, added by scripts/prove-waveform.sh", ThrowawayWave)' \
  >> core/scenes/waveforms.def
sed -i '$d' core/scenes/input_waveforms.hpp
cat >> core/scenes/input_waveforms.hpp <<'CPP'
/// throwaway: offset + A (1 - cos(2 pi f tau))/2, added by scripts/prove-waveform.sh.
class ThrowawayWave final : public PeriodicWaveform {
 public:
  using PeriodicWaveform::PeriodicWaveform;
  static InputPtr read(const InputKeys& in);

 protected:
  Sample inside(double tau) const override;
};

}  // namespace rodend
CPP
sed -i '$d' core/scenes/input_waveforms.cpp
cat >> core/scenes/input_waveforms.cpp <<'CPP'
InputPtr ThrowawayWave::read(const InputKeys& in) {
  const WaveformLevel l = read_waveform_level(in);
  return std::make_shared<ThrowawayWave>(l, read_wave_periods(in));
}

Input::Sample ThrowawayWave::inside(double tau) const {
  const double A = level().amplitude, f = periods().frequency, phase = kTwoPi * f * tau;
  const double c = std::cos(phase), s = std::sin(phase);
  return {level().offset + 0.5 * A * (1.0 - c), 0.5 * A * kTwoPi * f * s,
          0.5 * A * kTwoPi * kTwoPi * f * f * c};
}

}  // namespace rodend
CPP
prove_lines prove-waveform core/scenes/waveforms.def 1 0
prove_lines prove-waveform core/scenes/input_waveforms.hpp 10 0
prove_lines prove-waveform core/scenes/input_waveforms.cpp 12 0
prove_changed prove-waveform " M core/scenes/input_waveforms.cpp" " M core/scenes/input_waveforms.hpp" \
  " M core/scenes/waveforms.def"
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
cat > "$work/load.json" <<'JSON'
{"name": "load", "scene": "free-body", "time": {"end": 1.0, "sample_interval": 1e-2},
 "integrator": {"method": "dopri5", "abs_tol": 1e-12, "rel_tol": 1e-12},
 "parameters": {"force.kind": "throwaway", "force.frequency": 4.0, "force.cycles": 2,
                "force.start_time": 0.2},
 "signals": ["body_velocity"]}
JSON
./build/rodend run "$work/hinge.json" --results-root "$work/out" -q
./build/rodend run "$work/load.json" --results-root "$work/out" -q
/usr/bin/python3 - "$work" <<'PY'
import csv, json, math, sys
import h5py, numpy as np
work = sys.argv[1]
menus = json.load(open(f"{work}/choices.json"))
names = {k: [c["name"] for c in m["choices"]] for k, m in menus.items()}
assert names["waveforms"][-1] == "throwaway", names["waveforms"]
for menu in ("motion_shapes", "hinge_moments"):
    assert names[menu][-2:] == ["throwaway", "profile"], (menu, names[menu])
assert names["load_kinds"][-1] == "throwaway", names["load_kinds"]
print("rodend choices: throwaway in waveforms, motion_shapes, hinge_moments and load_kinds")
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
load = next(csv.DictReader(open(f"{work}/out/load/summary.csv")))
assert load["status"] == "ok", load["message"]
with h5py.File(f"{work}/out/load/cases/{load['case_id']}.h5", "r") as f:
    v = f["signals/body_velocity"][-1]
# the force [3, 6, 9] N (1 - cos)/2 over 2 periods at 4 Hz: impulse A x 0.5 s / 2, mass 1 kg
want = np.array([3.0, 6.0, 9.0]) * 0.25
err = float(np.max(np.abs(v - want)) / np.max(want))
print(f"free-body with force.kind throwaway: final velocity {v}, relative error {err:.1e}")
assert err < 1e-9, err
print("prove-waveform: ok")
PY
}

prove_main
