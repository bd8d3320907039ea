#!/usr/bin/env bash
# Proves the recipes of a design method, a distribution and a metric (docs/architecture.md): each
# is one catalogue line plus the code that computes it, and nothing else. In a throwaway git
# worktree of HEAD it adds
#   - a design method "throwaway": one line of sweep/design_methods.def and its draw, one line
#     appended to sweep/design.cpp (antithetic Monte Carlo: the monte-carlo points u as 1 - u);
#   - a distribution "throwaway": one line of sweep/distributions.def, its quantile, mean and std
#     (one case line in each of the three switches of sweep/design.cpp: log-uniform on
#     [lower, upper]) and its OpenTURNS form (one line of python/rodend/analysis/distributions.py);
#   - a metric "throwaway_metric": one line of sweep/metrics.def and its computation, one line in
#     MetricsAccumulator::finish (sweep/metrics.cpp): twice max_contact_force;
# checks with git that nothing else changed, builds rodend there, runs `bash scripts/gen-docs.sh`
# (which may rewrite only generated files), and checks that the three arrive everywhere:
#   `rodend schema` and `rodend choices` list the method and the distribution; a study of the new method and
#   distribution runs, design.json records them; its values are exactly the mirror of a
#   monte-carlo study of the same seed (x_throwaway x_monte_carlo = lower x upper, to 1e-12);
#   the metric is a summary column equal to 2 max_contact_force; `rodend analyze` analyses the
#   metric (moments, ranking) over the new design, the distribution read by OpenTURNS.
# Cost: one Release build of the rodend target (97 compile units; ccache helps little, the
# catalogues being in headers most units include) and 32 cases of gravity-drop of 0.05 s.
# Alone, or with the others by scripts/prove.sh (CTest: prove, label prove).
# Usage: bash scripts/prove-catalogues.sh
source "$(dirname "$0")/prove-common.sh"

recipe() {
# 1. the method: one catalogue line and its draw
echo 'RODEND_CHOICE(throwaway, "throwaway", "antithetic Monte Carlo (1 - u), added by scripts/prove-catalogues.sh", draw_throwaway, true, true, 0, 1, 1)' \
  >> sweep/design_methods.def
echo 'void rodend::draw_throwaway(Design& d) { draw_monte_carlo(d); for (double& u : d.unit) u = 1.0 - u; }' \
  >> sweep/design.cpp
# 2. the distribution: one catalogue line, its quantile, mean and std, its OpenTURNS form
echo 'RODEND_CHOICE(throwaway, "throwaway", "log-uniform on [lower, upper], added by scripts/prove-catalogues.sh", ({"lower", "upper"}), true)' \
  >> sweep/distributions.def
awk '
  /^    case DistributionKind::uniform:$/ {
    n++
    if (n == 1) print "    case DistributionKind::throwaway: return lower * std::pow(upper / lower, u);"
    if (n == 2) print "    case DistributionKind::throwaway: return (upper - lower) / std::log(upper / lower);"
    if (n == 3) print "    case DistributionKind::throwaway: return std::sqrt((upper * upper - lower * lower) / (2.0 * std::log(upper / lower)) - moment_mean() * moment_mean());"
  }
  { print }' sweep/design.cpp > "$work/design.cpp"
mv "$work/design.cpp" sweep/design.cpp
sed -i 's|^    "uniform": lambda p: ot.Uniform(p\["lower"\], p\["upper"\]),$|&\n    "throwaway": lambda p: ot.LogUniform(math.log(p["lower"]), math.log(p["upper"])),|' \
  python/rodend/analysis/distributions.py
# 3. the metric: one catalogue line and its computation
echo 'RODEND_METRIC(throwaway_metric, "N", "twice max_contact_force, added by scripts/prove-catalogues.sh")' \
  >> sweep/metrics.def
sed -i 's|^  at(v, MetricId::max_quaternion_norm_error) = stats.max_quaternion_norm_error;$|&\n  at(v, MetricId::throwaway_metric) = 2.0 * at(v, MetricId::max_contact_force);|' \
  sweep/metrics.cpp

for f in sweep/design_methods.def sweep/distributions.def sweep/metrics.def sweep/metrics.cpp \
  python/rodend/analysis/distributions.py; do
  prove_lines prove-catalogues "$f" 1 0
done
prove_lines prove-catalogues sweep/design.cpp 4 0
prove_changed prove-catalogues " M python/rodend/analysis/distributions.py" " M sweep/design.cpp" \
  " M sweep/design_methods.def" " M sweep/distributions.def" " M sweep/metrics.cpp" \
  " M sweep/metrics.def"
}

check() {
prove_generated prove-catalogues
grep -q '"throwaway"' python/rodend/analysis/catalogue.py ||
  { echo "prove-catalogues: the Python catalogue lacks the method" >&2; exit 1; }

# 3. the schema, a study of the new method and distribution beside monte-carlo, the analysis
./build/rodend schema > "$work/schema.json"
./build/rodend choices --json > "$work/choices.json"
for kind in monte-carlo throwaway; do
  cat > "$work/$kind.json" << JSON
{"name": "$kind", "scene": "gravity-drop", "time": {"end": 0.05, "sample_interval": 1e-3},
 "design": {"method": "$kind", "size": 16, "seed": 3, "factors": [
   {"key": "parameters.contact.restitution", "distribution": "throwaway", "lower": 0.3, "upper": 0.9}]}}
JSON
  ./build/rodend run "$work/$kind.json" --results-root "$work/out" -q
done
./build/rodend analyze "$work/out/throwaway" --metric throwaway_metric --no-plots --bootstrap 20 \
  > "$work/analyze.txt"
/usr/bin/python3 - "$work" << 'PY'
import csv, json, math, sys
work = sys.argv[1]
schema = json.dumps(json.load(open(f"{work}/schema.json")))
assert schema.count('"throwaway"') >= 2, "rodend schema lacks the method or the distribution"
choices = json.load(open(f"{work}/choices.json"))
assert "throwaway" in [c["name"] for c in choices["design_methods"]["choices"]], choices
assert "throwaway" in [c["name"] for c in choices["distributions"]["choices"]], choices
design = json.load(open(f"{work}/out/throwaway/design.json"))
f = design["factors"][0]
assert design["method"] == "throwaway" and f["distribution"] == "throwaway", design
mean = (0.9 - 0.3) / math.log(3.0)
assert abs(f["mean"] - mean) < 1e-12, (f["mean"], mean)
rows = {k: list(csv.DictReader(open(f"{work}/out/{k}/summary.csv")))
        for k in ("monte-carlo", "throwaway")}
key = "parameters.contact.restitution"
for a, b in zip(rows["monte-carlo"], rows["throwaway"]):
    product = float(a[key]) * float(b[key])
    assert abs(product - 0.27) < 1e-12, product  # lower x upper: the mirrored quantile
    assert b["status"] == "ok", b
    assert float(b["throwaway_metric"]) == 2 * float(b["max_contact_force"]), b
analysis = json.load(open(f"{work}/out/throwaway/analysis/analysis.json"))
m = analysis["groups"][0]["metrics"]["throwaway_metric"]
assert m["used"] == 16 and "distribution" in m and m["ranking"], m
print(f"design.json: {design['method']}, {f['distribution']} mean {f['mean']:.6f}")
print("values: x_throwaway x_monte_carlo = lower x upper in all 16 points")
print("metric: throwaway_metric = 2 max_contact_force in all 16 cases;",
      f"analysed: mean {m['distribution']['mean']:.6g}")
print("prove-catalogues: ok")
PY
}

prove_main
