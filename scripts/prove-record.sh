#!/usr/bin/env bash
# Proves the record recipe of docs/architecture.md: a new field of the case record is
# one line of sweep/case_record.def plus the code that computes it. In a throwaway git worktree of
# HEAD it adds
#   - the line RODEND_RECORD_FIELD(throwaway, real, run, "throwaway_s", "s", ...) and
#   - its computation, one line in start_record (sweep/case_observer.cpp): the case's index / 8,
# checks with git that nothing else changed, builds rodend and the Python module there, and
# checks that the field arrives everywhere the record goes:
#   the case file's root attribute (h5py), summary.csv and summary.h5 (written from the record
#   spool: the spool's round trip), the same after `rodend merge` (the summary rebuilt from the
#   case files: the case file read back), and the dictionary of rodend.run_case (Python); and
#   that `rodend analyze` of a designed study does not take the field for a metric (the analysis
#   reads the record's fields from sweep/case_record.def, through
#   python/rodend/analysis/catalogue.py, which scripts/gen-docs.sh regenerates: the only file it
#   changes).
# Cost: one Release build of rodend and the Python module (the 97 compile units of rodend and the
# module's) and 11 short cases. Alone, or with the others by scripts/prove.sh (CTest: prove). Exit 77 (skipped) outside a
# git checkout.
# Usage: bash scripts/prove-record.sh
source "$(dirname "$0")/prove-common.sh"

recipe() {
# 1. the field: one catalogue line, and its computation
echo 'RODEND_RECORD_FIELD(throwaway, real, run, "throwaway_s", "s", "a field added by scripts/prove-record.sh: case_index / 8")' \
  >> sweep/case_record.def
sed -i 's|^  rec.started_utc = utc_now();$|&\n  rec.throwaway = static_cast<double>(spec.index) / 8;|' sweep/case_observer.cpp
grep -q 'rec.throwaway' sweep/case_observer.cpp || { echo "prove-record: start_record not found" >&2; exit 1; }
prove_lines prove-record sweep/case_record.def 1 0
prove_lines prove-record sweep/case_observer.cpp 1 0
prove_changed prove-record " M sweep/case_observer.cpp" " M sweep/case_record.def"
}

check() {
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
PY

# 4. the generated Python catalogue follows, and the analysis does not read the field as a metric
prove_generated prove-record
grep -q '"throwaway_s"' python/rodend/analysis/catalogue.py ||
  { echo "prove-record: the Python catalogue lacks the field" >&2; exit 1; }
cat > "$work/mc.json" << 'JSON'
{"name": "mc", "scene": "gravity-drop", "time": {"end": 0.01, "sample_interval": 1e-3},
 "design": {"method": "monte-carlo", "size": 8, "seed": 1, "factors": [
   {"key": "parameters.contact.restitution", "distribution": "uniform", "lower": 0.3, "upper": 0.9}]}}
JSON
./build/rodend run "$work/mc.json" --results-root "$work/out" -q
./build/rodend analyze "$work/out/mc" --no-plots --bootstrap 0 > /dev/null
/usr/bin/python3 - "$work" << 'PY'
import json, sys
analysis = json.load(open(f"{sys.argv[1]}/out/mc/analysis/analysis.json"))
metrics = list(analysis["groups"][0]["metrics"])
assert "throwaway_s" not in metrics, f"the record field throwaway_s was analysed as a metric: {metrics}"
assert metrics, "no metric analysed"
print(f"rodend analyze: {len(metrics)} metrics analysed, throwaway_s not among them")
print("prove-record: ok")
PY
}

prove_main
