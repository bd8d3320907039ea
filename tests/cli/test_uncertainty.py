#!/usr/bin/env python3
"""Sampled designs through the whole path (issue 30 item 6): a study with a design block, run
by `rodend run`, analysed by `rodend analyze`, drawn into `rodend report`, with answers known in
closed form.

gravity-drop: the ball falls from the socket's centre, so it meets the socket after falling the
clearance c, at the speed sqrt(2 g c) whatever the restitution e. With c and e sampled
(Saltelli), first_impact_speed depends on c alone: its total index for e is 0 and for c 1,
within the bootstrap intervals.

The first impact's largest penetration is a product of independent factors. Hertz contact of a
ball of radius R in a conformal socket, K = 4/3 E* sqrt(R*), R* = R (R + c) / c, scaled by
s = contact.stiffness_scale; the energy balance of the impact, (1/2) m v^2 = (2/5) s K d^(5/2)
for the elastic law, and Lankarani-Nikravesh's damping, a factor h(e) of the restitution alone
(the law is homogeneous in K and v), give d = f(c) g(s) with f(c) ~ (c / sqrt(R*(c)))^(2/5)
(v^2 ~ c) and g(s) = s^(-2/5) (gravity's work during the contact, m g d, is d / c ~ 1 % of the
impact energy and is left out). For independent C and S, Var[f g] = E[f^2] E[g^2] -
E[f]^2 E[g]^2 and the first-order indices are S_c = Var[f] E[g]^2 / Var[f g], S_s = E[f]^2
Var[g] / Var[f g]: the test computes them (f's moments by quadrature, g's in closed form) and
asks that each lies within the estimated interval.

Two discrete factors with unequal weights (the clearance and the restitution) through
monte-carlo, latin-hypercube and saltelli designs: analysed without error, the chaos giving the
first impact's speed to the clearance alone.

A file design (a CSV of points): each row one case with the file's values, the first impact's
speed sqrt(2 g c) of each, and the clearance ranked first by |PRCC|, without a chaos.
"""
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

from common import assert_same_results, check, finish, run, write_study

R_BALL = 0.01  # m: contact.ball_radius of gravity-drop (rodend params gravity-drop)
C_LO, C_HI = 1e-4, 5e-4  # m: the clearance's band
S_LO, S_HI = 0.5, 2.0  # 1: the stiffness scale's band


def study(name, factors, metric_signals):
    return {"name": name, "scene": "gravity-drop",
            # the first impact comes at sqrt(2 c / g) <= 10.1 ms; 15 ms holds it and its rebound
            "time": {"end": 0.015, "sample_interval": 1e-3},
            "signals": metric_signals,
            "design": {"method": "saltelli", "base": "sobol", "size": 256, "seed": 7,
                       "factors": factors}}


def analyze(folder, metric):
    r = run(["analyze", folder, "--metric", metric, "--bootstrap", "300"])
    check(r.returncode == 0, f"rodend analyze {folder}: exit {r.returncode}\n{r.stderr}")
    with open(os.path.join(folder, "analysis", "analysis.json")) as f:
        doc = json.load(f)
    return doc["groups"][0]["metrics"][metric]["sobol"], r.stdout


def doc_metric(folder, metric):
    with open(os.path.join(folder, "analysis", "analysis.json")) as f:
        return json.load(f)["groups"][0]["metrics"][metric]


def within(value, interval, what):
    lo, hi = interval
    check(lo <= value <= hi, f"{what}: {value:.4f} outside the interval [{lo:.4f}, {hi:.4f}]")


def analytic_indices():
    c = np.linspace(C_LO, C_HI, 200001)
    f = (c / np.sqrt(R_BALL * (R_BALL + c) / c)) ** 0.4
    ef, ef2 = np.trapz(f, c) / (C_HI - C_LO), np.trapz(f * f, c) / (C_HI - C_LO)
    eg = (S_HI ** 0.6 - S_LO ** 0.6) / (0.6 * (S_HI - S_LO))
    eg2 = (S_HI ** 0.2 - S_LO ** 0.2) / (0.2 * (S_HI - S_LO))
    var = ef2 * eg2 - ef ** 2 * eg ** 2
    return (ef2 - ef ** 2) * eg ** 2 / var, ef ** 2 * (eg2 - eg ** 2) / var


with tempfile.TemporaryDirectory() as root:
    clearance = {"key": "parameters.contact.clearance", "distribution": "uniform",
                 "lower": C_LO, "upper": C_HI}
    # 1. a metric of the clearance alone
    doc = study("drop-speed", [clearance, {"key": "parameters.contact.restitution",
                                           "distribution": "uniform", "lower": 0.5,
                                           "upper": 0.95}], ["eccentricity"])
    path = write_study(os.path.join(root, "drop-speed.json"), doc)
    r = run(["run", path, "-q", "-j", "2", "--results-root", root])
    check(r.returncode == 0, f"run: exit {r.returncode}\n{r.stderr}")
    folder = os.path.join(root, "drop-speed")
    check(os.path.isfile(os.path.join(folder, "design.json")), "no design.json")
    s, table = analyze(folder, "first_impact_speed")
    print(table)
    within(1.0, s["total_interval"][0], "total index of the clearance")
    within(0.0, s["total_interval"][1], "total index of the restitution")
    within(1.0, s["first_order_interval"][0], "first-order index of the clearance")
    check(abs(s["total"][1]) < 1e-9, f"restitution's total index {s['total'][1]}: expected 0 "
          "(A and A with the restitution from B give the same impact speed)")

    # 2. a product of independent factors: the first-order indices in closed form
    doc = study("drop-penetration", [clearance, {"key": "parameters.contact.stiffness_scale",
                                                 "distribution": "uniform", "lower": S_LO,
                                                 "upper": S_HI}], ["penetration"])
    path = write_study(os.path.join(root, "drop-penetration.json"), doc)
    r = run(["run", path, "-q", "-j", "2", "--results-root", root])
    check(r.returncode == 0, f"run: exit {r.returncode}\n{r.stderr}")
    folder = os.path.join(root, "drop-penetration")
    s, table = analyze(folder, "max_penetration")
    print(table)
    s_c, s_s = analytic_indices()
    print(f"closed form: S_clearance {s_c:.4f}, S_stiffness_scale {s_s:.4f}")
    within(s_c, s["first_order_interval"][0], "first-order index of the clearance")
    within(s_s, s["first_order_interval"][1], "first-order index of the stiffness scale")
    # the chaos surrogate of the A and B blocks: its indices are those of the fitted function,
    # with no sampling interval; 0.02 covers the left-out gravity work (~1 % of d) and the
    # quadrature
    chaos = doc_metric(folder, "max_penetration")["chaos"]
    check(abs(chaos["first_order"][0] - s_c) < 0.02 and abs(chaos["first_order"][1] - s_s) < 0.02,
          f"chaos first-order indices {chaos['first_order']} vs closed form {s_c:.4f}, {s_s:.4f}")
    # the interaction is Var f Var g / Var[f g]: the totals exceed the first orders by it
    within(1.0 - s_s, s["total_interval"][0], "total index of the clearance")
    within(1.0 - s_c, s["total_interval"][1], "total index of the stiffness scale")

    # the printed table: the spread with intervals and the factors ranked, labelled
    check("factors ranked by total Sobol' index (Saltelli) [1]" in table and
          "95 % quantile" in table and "[mm]" in table,
          f"the printed table lacks the ranking, the quantiles or the unit:\n{table}")
    rank = doc_metric(folder, "max_penetration")["ranking"]
    want = ["parameters.contact.clearance", "parameters.contact.stiffness_scale"]
    if s_s > s_c:
        want.reverse()
    check([f["factor"] for f in rank["factors"]] == want, f"ranking {rank}: expected {want}")

    # 3. the report opens with the answers; its figures are grouped by question, captioned
    r = run(["analyze", folder, "--metric", "max_penetration", "--threshold",
             "max_penetration=1e-6", "--bootstrap", "100"])
    check(r.returncode == 0, f"analyze with a threshold: exit {r.returncode}\n{r.stderr}")
    exc = doc_metric(folder, "max_penetration")["exceedance"][0]
    r = run(["report", folder])
    check(r.returncode == 0, f"report: exit {r.returncode}\n{r.stderr}")
    page = open(os.path.join(folder, "report.html"), encoding="utf-8").read()
    answers, figures = page.find("<h2 id=\"answers\">Answers"), page.find("<h2>Figures")
    check(0 < answers < figures < page.find("<h2>Summary"),
          "the report does not open with the answers, then the figures and the summary")
    first = page[answers:figures]
    check(f"({exc['exceed']} of {exc['n']})" in first and "P(&gt; 0.001 mm)" in first,
          "the answers lack the exceedance probability")
    check("contact.clearance" in first and
          "by total Sobol' index (Saltelli) [1]" in first, "the answers lack the ranking")
    check("<h3>Which factors drive each metric?</h3>" in page and
          "against each factor at every usable case" in page,
          "the figures are not grouped by question and captioned")
    check(page.index("Which factors drive") < page.index("How is each metric spread"),
          "the questions are not in their order")
    size = os.path.getsize(os.path.join(folder, "report.html"))
    check(size < 2_000_000, f"report of {size} bytes: expected under 2 MB")
    summary = page[page.find("<h2>Summary"):page.find("<h2>Provenance")]
    check("<th>max_penetration [m]</th>" in summary and "wall_time_s" not in summary,
          "the summary table is not limited to the grid axes and the key metrics")
    check("95 % intervals in brackets." in first, "the answers do not give the intervals' level")
    # the report's level as analyze prints it: 99.9 %, not rounded; none from a bootstrap with
    # --bootstrap 0 (main printed "99.9 % intervals in brackets." and no word of the bootstrap)
    r = run(["analyze", folder, "--metric", "max_penetration", "--no-plots", "--bootstrap", "0",
             "--confidence", "0.999"])
    check(r.returncode == 0 and "no intervals (bootstrap 0)" in r.stdout,
          f"analyze --bootstrap 0: exit {r.returncode}\n{r.stderr}")
    r = run(["report", folder])
    page = open(os.path.join(folder, "report.html"), encoding="utf-8").read()
    check(r.returncode == 0 and "99.9 % intervals in brackets (no intervals from a bootstrap: "
          "bootstrap 0)." in page, "the report's answers do not say bootstrap 0 gave no intervals")

    # 4. rodend analyze of a folder without a design: exit 2 with a message
    plain = write_study(os.path.join(root, "plain.json"),
                        {"name": "plain", "scene": "gravity-drop",
                         "time": {"end": 0.001, "sample_interval": 1e-3}})
    run(["run", plain, "-q", "--results-root", root])
    r = run(["analyze", os.path.join(root, "plain")])
    check(r.returncode == 2 and "design" in r.stderr,
          f"analyze without a design: exit {r.returncode}, {r.stderr!r}")
    # 5. a design is an axis like any other: two shards merged are the whole run, bit for bit
    small = {"name": "drop-small", "scene": "gravity-drop",
             "time": {"end": 0.012, "sample_interval": 1e-3},
             "design": {"method": "latin-hypercube", "size": 6, "seed": 3, "factors": [clearance]}}
    path = write_study(os.path.join(root, "drop-small.json"), small)
    whole, shards = os.path.join(root, "whole"), os.path.join(root, "shards")
    for args in (["--results-root", whole], ["--results-root", shards, "--shard", "1/2"],
                 ["--results-root", shards, "--shard", "2/2"]):
        r = run(["run", path, "-q"] + args)
        check(r.returncode == 0, f"run {args}: exit {r.returncode}\n{r.stderr}")
    r = run(["merge", os.path.join(shards, "drop-small")])
    check(r.returncode == 0, f"merge: exit {r.returncode}\n{r.stderr}")
    assert_same_results(os.path.join(whole, "drop-small"), os.path.join(shards, "drop-small"),
                        "a designed study in two shards")
    # 6. two discrete factors with unequal weights, through monte-carlo, latin-hypercube and
    # saltelli (main: OpenTURNS's TypeError "Undefined symbol: 'nan'"): the first impact's
    # speed depends on the clearance, so the chaos gives it all but a trace of the variance
    for method in ("monte-carlo", "latin-hypercube", "saltelli"):
        doc = {"name": f"discrete-{method}", "scene": "gravity-drop",
               "time": {"end": 0.012, "sample_interval": 1e-3},
               "design": {"method": method, "size": 16 if method == "saltelli" else 32,
                          "seed": 5, "factors": [
                              {"key": "parameters.contact.clearance", "distribution": "discrete",
                               "values": [1e-4, 3e-4, 5e-4], "weights": [6, 3, 1]},
                              {"key": "parameters.contact.restitution",
                               "distribution": "discrete", "values": [0.3, 0.9],
                               "weights": [0.8, 0.2]}]}}
        path = write_study(os.path.join(root, f"discrete-{method}.json"), doc)
        r = run(["run", path, "-q", "--results-root", root])
        check(r.returncode == 0, f"discrete {method}: run exit {r.returncode}\n{r.stderr}")
        folder = os.path.join(root, f"discrete-{method}")
        r = run(["analyze", folder, "--metric", "first_impact_speed", "--no-plots"])
        check(r.returncode == 0 and "Traceback" not in r.stderr,
              f"discrete {method}: analyze exit {r.returncode}\n{r.stderr[-600:]}")
        if r.returncode == 0:
            c = doc_metric(folder, "first_impact_speed")["chaos"]
            # the restitution reaches the metric only inside the impact's first step: 1.4e-5 of
            # its variance, measured; a swapped or misread factor would give it most of it
            check(c.get("first_order", [0])[0] > 0.999 and c.get("total", [0, 1])[1] < 1e-3,
                  f"discrete {method}: chaos {c.get('first_order')}, {c.get('total')}, "
                  f"{c.get('validation') or c.get('skipped')}")
    # 7. a file design: twelve points of clearance and restitution from a CSV, each row one case
    # with the file's values; the first impact's speed sqrt(2 g c) ranks the clearance first by
    # |PRCC| (the restitution acts only inside the impact's first step), no chaos without
    # distributions, and the analysis's mean is the one of the twelve cases
    clearances = [1e-4 + 3.5e-5 * i for i in range(12)]
    restitutions = [0.3 + 0.05 * ((5 * i) % 12) for i in range(12)]
    with open(os.path.join(root, "points.csv"), "w") as f:
        f.write("# clearance and restitution of twelve parts\n"
                "parameters.contact.clearance,parameters.contact.restitution\n")
        f.writelines(f"{c!r},{e!r}\n" for c, e in zip(clearances, restitutions))
    doc = {"name": "from-file", "scene": "gravity-drop",
           "time": {"end": 0.012, "sample_interval": 1e-3},
           "design": {"method": "file", "file": "points.csv"}}
    path = write_study(os.path.join(root, "from-file.json"), doc)
    r = run(["run", path, "-q", "--results-root", root])
    check(r.returncode == 0, f"file design: run exit {r.returncode}\n{r.stderr}")
    folder = os.path.join(root, "from-file")
    import csv
    with open(os.path.join(folder, "summary.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    check([float(x["parameters.contact.clearance"]) for x in rows] == clearances and
          [int(x["design.sample"]) for x in rows] == list(range(12)),
          "file design: the summary's clearances are not the file's, row by row")
    speed = np.array([float(x["first_impact_speed"]) for x in rows])
    check(np.allclose(speed, np.sqrt(2 * 9.81 * np.array(clearances)), rtol=0.01),
          f"file design: first impact speeds {speed} are not sqrt(2 g c)")
    r = run(["analyze", folder, "--metric", "first_impact_speed", "--no-plots"])
    check(r.returncode == 0 and "Traceback" not in r.stderr,
          f"file design: analyze exit {r.returncode}\n{r.stderr[-600:]}")
    if r.returncode == 0:
        m = doc_metric(folder, "first_impact_speed")
        check(abs(m["distribution"]["mean"] - speed.mean()) < 1e-12 * speed.mean(),
              f"file design: mean {m['distribution']['mean']} is not the cases' {speed.mean()}")
        rank = m["ranking"]
        check(rank["measure"] == "abs_prcc" and
              rank["factors"][0]["factor"] == "parameters.contact.clearance" and
              rank["factors"][0]["value"] > 0.99,
              f"file design: ranking {rank}")
        check("skipped" in m["chaos"], f"file design: a chaos without distributions {m['chaos']}")
finish("uncertainty")
