#!/usr/bin/env bash
# Proves the record recipe of docs/architecture.md (issue 32): a new field of the case record is
# one line of sweep/case_record.def plus the code that computes it. In a throwaway git worktree of
# HEAD it adds
#   - the line RODEND_RECORD_FIELD(throwaway, real, run, "throwaway_s", "s", ...) and
#   - its computation, one line in start_record (sweep/case_observer.cpp): the case's index / 8,
# checks with git that nothing else changed, builds rodend and the Python module there, and
# checks that the field arrives everywhere the record goes:
#   the case file's root attribute (h5py), summary.csv and summary.h5 (written from the record
#   spool: the spool's round trip), the same after `rodend merge` (the summary rebuilt from the
#   case files: the case file read back), and the dictionary of rodend.run_case (Python).
# Cost: one Release build of rodend and the Python module, then 4 cases. In CTest as prove.record
# (label prove) when configured with -DRODEND_PROVE_TESTS=ON.
# Usage: bash scripts/prove-record.sh
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$(pwd)
work=$(mktemp -d)
tree="$work/tree"
cleanup() {
  git -C "$repo" worktree remove --force "$tree" > /dev/null 2>&1 || true
  rm -rf "$work"
}
trap cleanup EXIT
git worktree add --detach "$tree" HEAD > /dev/null
cd "$tree"

# 1. the field: one catalogue line, and its computation
echo 'RODEND_RECORD_FIELD(throwaway, real, run, "throwaway_s", "s", "a field added by scripts/prove-record.sh: case_index / 8")' \
  >> sweep/case_record.def
sed -i 's|^  rec.started_utc = utc_now();$|&\n  rec.throwaway = static_cast<double>(spec.index) / 8;|' sweep/case_observer.cpp
grep -q 'rec.throwaway' sweep/case_observer.cpp || { echo "prove-record: start_record not found" >&2; exit 1; }
for f in sweep/case_record.def sweep/case_observer.cpp; do
  n=$(git diff --numstat -- "$f" | awk '{print $1 "+" $2 "-"}')
  [ "$n" = "1+0-" ] || { echo "prove-record: $f changed by $n lines, expected one added" >&2; exit 1; }
done
changed=$(git status --porcelain | sort)
expected=$(printf '%s\n' " M sweep/case_observer.cpp" " M sweep/case_record.def" | sort)
echo "files the recipe touched:"
echo "$changed"
[ "$changed" = "$expected" ] || { echo "prove-record: expected exactly: $expected" >&2; exit 1; }

# 2. build rodend and the Python module
launcher=()
export CCACHE_BASEDIR="$work"
if command -v ccache > /dev/null; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
fi
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DRODEND_WERROR=ON -DRODEND_BUILD_TESTS=OFF \
  -DRODEND_BUILD_BENCHMARKS=OFF "${launcher[@]}" > /dev/null
cmake --build build --target rodend _rodend -j"$(nproc)" > "$work/build.log" 2>&1 ||
  { tail -30 "$work/build.log"; exit 1; }

# 3. a study of three cases, its summary, the case files, a merge, the Python dictionary
cat > "$work/rec.json" << 'JSON'
{"name": "rec", "scene": "gravity-drop", "time": {"end": 0.01, "sample_interval": 1e-3},
 "grid": [{"key": "parameters.contact.restitution", "values": [0.3, 0.5, 0.7]}]}
JSON
./build/rodend run "$work/rec.json" --results-root "$work/out" -q
cp "$work/out/rec/summary.csv" "$work/run-summary.csv"
rm "$work/out/rec/summary.csv" "$work/out/rec/summary.h5"
./build/rodend merge "$work/out/rec" > /dev/null
PYTHONPATH="$tree/python" RODEND_BUILD_DIR="$tree/build" /usr/bin/python3 - "$work" << 'PY'
import csv, sys
import h5py
work = sys.argv[1]
out = f"{work}/out/rec"
for label, path in (("run", f"{work}/run-summary.csv"), ("merge", f"{out}/summary.csv")):
    rows = list(csv.DictReader(open(path)))
    got = [float(r["throwaway_s"]) for r in rows]
    want = [int(r["case_index"]) / 8 for r in rows]
    assert got == want, (label, got, want)
    print(f"summary.csv after {label}: throwaway_s = {got}")
    for r in rows:
        with h5py.File(f"{out}/cases/{r['case_id']}.h5", "r") as f:
            assert float(f.attrs["throwaway_s"]) == int(r["case_index"]) / 8
with h5py.File(f"{out}/summary.h5", "r") as f:
    col = f["summary/throwaway_s"]
    assert col.attrs["units"] in ("s", b"s"), col.attrs["units"]
    print("summary.h5: throwaway_s", list(col[:]), "units", col.attrs["units"])
print("case files: root attribute throwaway_s present in each")
import rodend
case = rodend.run_case("gravity-drop", time={"end": 0.01, "sample_interval": 1e-3})
assert case.throwaway_s == 0.0, case.throwaway_s
print("rodend.run_case(...).throwaway_s =", case.throwaway_s)
print("prove-record: ok")
PY
