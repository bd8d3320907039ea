"""The table `rodend analyze` prints: per grid point and metric, the metric's spread (mean, std,
5/50/95 % quantiles, P(metric > threshold), each with its interval) and its factors ranked by
importance with the measures beside, every column labelled, values in the shown units
(display.py: mrad, mm)."""
from . import display as dp


def _header(m, r, where):
    shown = dp.unit(r["units"])[0]
    return (f"\n{m} [{shown}]" + (f" at {where}" if where else "")
            + f": {r['used']} cases used, {r['failed']} failed, {r['non_finite']} non-finite")


def _spread(m, r, level):
    d, si = r.get("distribution"), r["units"]
    if not d:
        return []
    shown = dp.unit(si)[0]
    what = d.get("sample") or "independent points"
    kind = d.get("mean_interval_kind") or "none"
    lines = [f"  spread over {d['n']} {what}; {level} intervals ({kind} for the mean)",
             f"    {'quantity':<22}{'value':>11}  interval"]
    rows = [("mean", d["mean"], d.get("mean_interval")), ("std", d["std"], d.get("std_interval"))]
    rows += [(f"{float(p) * 100:g} % quantile", v, (d.get("quantile_intervals") or {}).get(p))
             for p, v in d["quantiles"].items()]
    for name, v, iv in rows:
        lines.append(f"    {name:<22}{dp.g(dp.scaled(v, si), 11)}  "
                     f"{dp.interval(dp.scaled(iv, si))}")
    for e in r.get("exceedance", []):
        name = f"P(> {dp.g(dp.scaled(e['threshold'], si))}{dp.suffix(si)})"
        lines.append(f"    {name:<22}{dp.g(e['probability'], 11)}  "
                     f"{dp.interval(e.get('interval'))}  ({e['exceed']} of {e['n']})")
    return lines


def _extras(r):
    """[(column, values, intervals or None, scaled by the metric's unit)] beside the ranking."""
    s, mo, c, k = r.get("sobol", {}), r.get("morris"), r.get("chaos", {}), r.get("correlation")
    measure = r["ranking"]["measure"]
    out = []
    if "first_order" in s:
        out.append(("first order", s["first_order"], s.get("first_order_interval"), False))
    if mo:
        out += [("σ", mo["sigma"], None, True), ("μ", mo["mu"], None, True)]
    if "total" in c:
        out.append(("chaos first", c["first_order"], None, False))
        if measure != "chaos_total":
            out.append(("chaos total", c["total"], None, False))
    if k:
        out += [("SRC", k["src"], None, False), ("PRCC", k["prcc"], None, False),
                ("Spearman", k["spearman"], None, False)]
    return out


def _ranking(r, keys, level):
    rk = r.get("ranking")
    if not rk:
        return []
    si = r["units"] if rk["units"] != "1" else ""
    unit = f" [{dp.unit(si)[0]}]" if si else " [1]"
    width = max([len("factor")] + [len(dp.short(k)) for k in keys])
    extras = _extras(r)
    head = f"    {'rank':>4}  {'factor':<{width}}  {'value':>10}  {level + ' interval':<22}"
    head += "".join(f"  {name:>{max(10, len(name))}}" for name, *_ in extras)
    lines = [f"  factors ranked by {rk['by']}{unit}", head]
    for f in rk["factors"]:
        i = keys.index(f["factor"])
        row = (f"    {f['rank']:>4}  {dp.short(f['factor']):<{width}}  "
               f"{dp.g(dp.scaled(f['value'], si), 10)}  "
               f"{dp.interval(dp.scaled(f['interval'], si)):<22}")
        for name, values, _, per_metric in extras:
            v = dp.scaled(values[i], r["units"]) if per_metric else values[i]
            row += f"  {dp.g(v, max(10, len(name)))}"
        lines.append(row)
    return lines


def _notes(r):
    c, k, s = r.get("chaos", {}), r.get("correlation"), r.get("sobol", {})
    out = []
    if "q2_loo" in c and c.get("q2_loo") is not None:
        out.append(f"  chaos: {c['method']}, {c['terms']} terms, degree {c['degree']}, "
                   f"Q² (leave-one-out) {c['q2_loo']:.4f}")
    elif c.get("skipped"):
        out.append(f"  chaos: skipped: {c['skipped']}")
    if k:
        out.append(f"  linear fit R² {k['r2_linear']:.3f} over {k['n']} points (SRC² are shares "
                   "of the variance when it is close to 1)")
    if "groups" in s:
        out.append(f"  Saltelli: {s['groups']} complete row groups, {s['removed_groups']} removed")
    if s.get("skipped"):
        out.append(f"  Saltelli: skipped: {s['skipped']}")
    return out


def table(doc):
    """Every grid point's and metric's spread and ranking, as lines of text."""
    lines, keys = [], doc["design"]["factor_keys"]
    level = f"{doc['confidence'] * 100:g} %"
    for g in doc["groups"]:
        where = ", ".join(f"{k} = {v}" for k, v in g["grid"].items())
        for m, r in g["metrics"].items():
            lines.append(_header(m, r, where))
            lines += _spread(m, r, level) + _ranking(r, keys, level) + _notes(r)
    return "\n".join(lines).lstrip("\n")
