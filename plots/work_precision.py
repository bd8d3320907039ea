#!/usr/bin/python3
"""Work-precision study: runs the shipped studies for one scene (every method of the integrator
menu at a ladder of tolerances, rk4 at a ladder of steps, and the references), measures the error
of well-conditioned quantities against a reference computed with a *different* high-order method
at a much tighter tolerance, and the cost (right-hand-side calls, steps, wall time: minimum of
the repeats), then writes a table and the work-precision diagram.

    /usr/bin/python3 plots/work_precision.py --scene rod-end-kinematic [--repeats 3] [--threads 1]

Studies: studies/work-precision-<scene>.json (the tolerance ladder of every adaptive method),
work-precision-rk4-<scene>.json (rk4's steps), work-precision-reference-<scene>.json (the
references) and, where shipped, work-precision-tight-<scene>.json (the preset method at
tolerances tighter than the ladder, for the reference preset).

Outputs in results/work-precision-<scene>/: table.csv, table.md, presets.md and
work_precision.png (error against cost, log-log, one line per method).

Errors (per case, then the largest over the clearance cases of a configuration):
  relative error |x - x_ref| / |x_ref| of first_contact_time, first_impact_speed,
  first_impact_peak_force, max_contact_force, wear_integral, max_eccentricity and
  max_chamber_pressure (actuator scenes); final_surface_angle relative to the reference's largest
  |surface angle| (the final angle itself is near zero); and the pointwise eccentricity history
  up to the first impact, relative to the clearance. Actuator scenes (the study records
  chamber_pressures) add the peak pressure of each chamber over the samples,
  peak_pressure_chamber1 and peak_pressure_chamber2, relative to that chamber's pressure swing
  (max - min) in the reference run: in rod-end-actuator the pressures swing by about 8 % (9.9 to
  10.7 MPa), so an error relative to the pressure itself (max_chamber_pressure) hardly moves. Final-state errors
  after many impacts are chaotic and are not used.

Preset candidates (presets.md): the cheapest configurations whose largest error is <= 10 % (fast)
and <= 1 % (balanced), once by right-hand-side calls (deterministic) and once by wall time, and
the most accurate configuration measured.
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# the package rodend beside plots/ (its reader needs no compiled module), else an installed one
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "python"))
from rodend import Study, summary_rows  # noqa: E402

METRICS = ["first_contact_time", "first_impact_speed", "first_impact_peak_force",
           "max_contact_force", "wear_integral", "max_eccentricity", "final_surface_angle",
           "max_chamber_pressure"]


def run(rodend, study, root, threads):
    r = subprocess.run([rodend, "run", study, "--results-root", root, "-q", "--threads", str(threads)],
                       capture_output=True, text=True)
    if r.returncode not in (0, 1):
        sys.exit(f"work_precision: {study}: {r.stderr.strip()}")


_STUDIES = {}


def study(study_dir):
    """The results folder read once (the package's reader: python/rodend/study.py)."""
    if study_dir not in _STUDIES:
        _STUDIES[study_dir] = Study(study_dir)
    return _STUDIES[study_dir]


def rows(study_dir):
    return summary_rows(study_dir)


def history(study_dir, case_id, name):
    return study(study_dir).case(case_id).signals("time", name)


def case_features(study_dir, case_id):
    """The features of a case's scene (root attribute features_json; guessed from the recorded
    signals for files written before it)."""
    return set(study(study_dir).case(case_id).features)


def parse_args():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default="rod-end-kinematic")
    ap.add_argument("--rodend", default="./build/rodend")
    ap.add_argument("--repeats", type=int, default=3, help="runs for the minimum wall time")
    ap.add_argument("--threads", type=int, default=1, help="threads over cases (1: cleanest timing)")
    ap.add_argument("--skip-run", action="store_true", help="analyse existing results only")
    ap.add_argument("--no-title", action="store_true", help="no figure title (for publication)")
    return ap.parse_args()


def study_files(scene):
    """{role: study file} of the scene: the ladder, rk4's steps, the references and, where
    shipped, the preset method at tolerances tighter than the ladder."""
    studies = {"adaptive": f"studies/work-precision-{scene}.json",
               "rk4": f"studies/work-precision-rk4-{scene}.json",
               "reference": f"studies/work-precision-reference-{scene}.json"}
    tight = f"studies/work-precision-tight-{scene}.json"
    if os.path.exists(tight):
        studies["tight"] = tight
    return studies


def metric_errors(r, ref, ok):
    """Relative error of each metric of row r against the reference row (inf when not ok)."""
    err = {}
    for m in METRICS:
        if m not in r or not np.isfinite(float(ref[m])):
            continue
        x, xr = float(r[m]), float(ref[m])
        scale = abs(float(ref["max_surface_angle"])) if m == "final_surface_angle" else abs(xr)
        err[m] = abs(x - xr) / scale if ok and scale > 0 else math.inf
    return err


def history_errors(run_dir, r, ref_dir, ref, ok):
    """The pointwise eccentricity history up to the first impact (relative to the clearance)
    and, for actuator scenes, each chamber's peak pressure relative to its swing in the
    reference."""
    err = {}
    c = float(r["parameters.contact.clearance"])
    t1 = float(ref["first_contact_time"])
    t, e = history(run_dir, r["case_id"], "eccentricity")
    tr, er = history(ref_dir, ref["case_id"], "eccentricity")
    m_ = (t < t1) & (tr[: len(t)] < t1) if len(t) == len(tr) else np.zeros(0, bool)
    err["history_before_first_impact"] = (float(np.max(np.abs(e[m_] - er[m_]))) / c
                                          if ok and m_.any() else math.inf)
    if "actuator" in case_features(ref_dir, ref["case_id"]):
        _, p = history(run_dir, r["case_id"], "chamber_pressures")
        _, pr = history(ref_dir, ref["case_id"], "chamber_pressures")
        for j in range(pr.shape[1]):
            swing = float(np.max(pr[:, j]) - np.min(pr[:, j]))
            err[f"peak_pressure_chamber{j + 1}"] = (
                abs(float(np.max(p[:, j])) - float(np.max(pr[:, j]))) / swing
                if ok and len(p) == len(pr) and swing > 0 else math.inf)
    return err


def measure(out, names, measured, repeats, refs, ref_dir):
    """{(method, setting): [per-case {ok, rhs_calls, steps, wall, err}]} of the measured runs."""
    configs = {}
    for key in measured:
        per_repeat = [rows(os.path.join(out, f"run{k}", names[key])) for k in range(repeats)]
        run_dir = os.path.join(out, "run0", names[key])
        for i, r in enumerate(per_repeat[0]):
            method = "rk4" if key == "rk4" else r["integrator.method"]
            setting = float(r["integrator.step"]) if key == "rk4" else float(r["integrator.rel_tol"])
            ref_method = "fehlberg78" if method == "dopri5" else "dopri5"
            ref = refs[(float(r["parameters.contact.clearance"]), ref_method)]
            ok = all(p[i]["status"] == "ok" for p in per_repeat)
            err = {**metric_errors(r, ref, ok), **history_errors(run_dir, r, ref_dir, ref, ok)}
            configs.setdefault((method, setting), []).append({
                "ok": ok,
                "rhs_calls": float(r["rhs_calls"]),
                "steps": float(r["steps_accepted"]) + float(r["steps_rejected"]),
                "wall": min(float(p[i]["wall_time_s"]) for p in per_repeat),
                "err": err})
    return configs


def tabulate(configs):
    """One row per configuration: its totals and the worst error of each metric over the cases."""
    table = []
    for (method, setting), cases in sorted(configs.items()):
        metrics = sorted({m for c in cases for m in c["err"]})
        worst = {m: max(c["err"].get(m, 0.0) for c in cases) for m in metrics}
        table.append({"method": method, "setting": setting,
                      "ok": all(c["ok"] for c in cases),
                      "rhs_calls": sum(c["rhs_calls"] for c in cases),
                      "steps": sum(c["steps"] for c in cases),
                      "wall_s": sum(c["wall"] for c in cases),
                      "max_error": max(worst.values()), **{"err_" + m: v for m, v in worst.items()}})
    cols = []
    for t in table:
        cols += [k for k in t if k not in cols]
    return table, cols


def write_csv(path, table, cols):
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=cols, restval=float("nan"))
        w.writeheader()
        w.writerows(table)


def preset_candidates(table):
    """The cheapest configuration within each error target, by right-hand-side calls
    (deterministic) and by wall time (min of the repeats). The two disagree where a method
    does much work outside the right-hand side (CVODE: many short steps, its own linear
    algebra)."""
    def cheapest(limit, cost):
        good = [t for t in table if t["ok"] and t["max_error"] <= limit]
        return min(good, key=lambda t: t[cost]) if good else None
    choice = {}
    for name, limit in (("fast (<= 10 %)", 0.10), ("balanced (<= 1 %)", 0.01)):
        choice[name + ", by RHS calls"] = cheapest(limit, "rhs_calls")
        choice[name + ", by wall time"] = cheapest(limit, "wall_s")
    choice["most accurate measured"] = min((t for t in table if t["ok"]), key=lambda t: t["max_error"])
    return choice


def fmt_setting(t):
    return f"step {t['setting']:g} s" if t["method"] == "rk4" else f"tol {t['setting']:g}"


def write_table_md(path, table, errs):
    with open(path, "w") as f:
        f.write("| method | setting | " + " | ".join(e[4:] for e in errs) +
                " | max error | RHS calls | steps | wall [s] |\n")
        f.write("|---" * (len(errs) + 6) + "|\n")
        for t in table:
            f.write(f"| {t['method']} | {fmt_setting(t)} | " +
                    " | ".join(f"{t.get(e, float('nan')):.2g}" for e in errs) +
                    f" | {t['max_error']:.2g} | {t['rhs_calls']:.3g} | {t['steps']:.3g} | {t['wall_s']:.3g} |\n")


def stiff_measure(table, choice):
    """The fastest configuration within 1 % against the fastest dopri5 within 1 %, by wall
    time (min of the repeats): a line of presets.md, or '' when either is missing."""
    best = choice["balanced (<= 1 %), by wall time"]
    explicit = [t for t in table if t["ok"] and t["max_error"] <= 0.01 and t["method"] == "dopri5"]
    if not (best and explicit):
        return ""
    d5 = min(explicit, key=lambda t: t["wall_s"])
    return (f"\nFastest within 1 % against the fastest dopri5 within 1 % (wall time): "
            f"{d5['wall_s'] / best['wall_s']:.2f}x ({best['method']} {fmt_setting(best)}, "
            f"{best['wall_s']:.3g} s, against dopri5 {fmt_setting(d5)}, {d5['wall_s']:.3g} s)\n")


def reference_gap(refs):
    """How far the two references are apart (the floor of the errors measured against them):
    a line of presets.md, or '' when there is only one."""
    gap = {}
    for (c, method), r in refs.items():
        other = refs.get((c, "dopri5" if method == "fehlberg78" else "fehlberg78"))
        if method != "fehlberg78" or other is None:
            continue
        for m in METRICS:
            if m == "final_surface_angle" or m not in r or not np.isfinite(float(other[m])):
                continue
            if float(other[m]) != 0:
                gap[m] = max(gap.get(m, 0.0), abs(float(r[m]) - float(other[m])) / abs(float(other[m])))
    if not gap:
        return ""
    return ("\nThe two references (fehlberg78 and dopri5 at 1e-11) differ by (largest relative "
            "difference over the cases): " +
            ", ".join(f"{m} {v:.2g}" for m, v in sorted(gap.items(), key=lambda kv: -kv[1])) + "\n")


def write_presets_md(path, table, choice, errs, refs):
    with open(path, "w") as f:
        f.write("| candidate | method | setting | max error | worst metric | RHS calls | wall [s] |\n|---|---|---|---|---|---|---|\n")
        for name, t in choice.items():
            if t is None:
                f.write(f"| {name} | (none reaches it) | | | | | |\n")
                continue
            worst = max(errs, key=lambda e: t.get(e, 0.0))
            f.write(f"| {name} | {t['method']} | {fmt_setting(t)} | {t['max_error']:.2g} | {worst[4:]} | "
                    f"{t['rhs_calls']:.3g} | {t['wall_s']:.3g} |\n")
        f.write(stiff_measure(table, choice))
        f.write(reference_gap(refs))


def figure(table, png, scene, title):
    fig, axes = plt.subplots(1, 2, figsize=(12, 5))
    for method in sorted({t["method"] for t in table}):
        pts = sorted((t["rhs_calls"], t["wall_s"], t["max_error"]) for t in table
                     if t["method"] == method and t["ok"] and np.isfinite(t["max_error"]))
        if not pts:
            continue
        x1, x2, y = zip(*pts)
        axes[0].loglog(x1, y, "o-", label=method)
        axes[1].loglog(x2, y, "o-", label=method)
    for ax, xl in zip(axes, ["right-hand-side calls (sum over the cases)", "wall time [s] (min of repeats, sum over the cases)"]):
        ax.axhline(0.01, color="k", ls="--", lw=0.8)
        ax.set_xlabel(xl)
        ax.set_ylabel("largest relative error over the metrics [-]")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=8)
    if title:
        fig.suptitle(f"Work-precision, {scene}: thesis clearance study, one cycle per case "
                     "(dashed: 1 % error)")
    fig.tight_layout()
    fig.savefig(png, dpi=150)


def main():
    a = parse_args()
    out = os.path.join("results", "work-precision-" + a.scene)
    os.makedirs(out, exist_ok=True)
    studies = study_files(a.scene)
    measured = [k for k in ("adaptive", "rk4", "tight") if k in studies]
    names = {k: json.load(open(v))["name"] for k, v in studies.items()}
    if not a.skip_run:
        run(a.rodend, studies["reference"], os.path.join(out, "ref"), a.threads)
        for k in range(a.repeats):
            for key in measured:
                run(a.rodend, studies[key], os.path.join(out, f"run{k}"), a.threads)

    ref_dir = os.path.join(out, "ref", names["reference"])
    refs = {}  # (clearance, reference method) -> row
    for r in rows(ref_dir):
        refs[(float(r["parameters.contact.clearance"]), r["integrator.method"])] = r
    table, cols = tabulate(measure(out, names, measured, a.repeats, refs, ref_dir))
    write_csv(os.path.join(out, "table.csv"), table, cols)
    errs = [k for k in cols if k.startswith("err_")]
    write_table_md(os.path.join(out, "table.md"), table, errs)
    write_presets_md(os.path.join(out, "presets.md"), table, preset_candidates(table), errs, refs)
    png = os.path.join(out, "work_precision.png")
    figure(table, png, a.scene, not a.no_title)
    print(open(os.path.join(out, "presets.md")).read())
    print("wrote", png, os.path.join(out, "table.md"))


if __name__ == "__main__":
    main()
