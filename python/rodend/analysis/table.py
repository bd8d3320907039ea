"""The table `rodend analyze` prints: per grid point and metric, the metric's spread (mean, std,
5/50/95 % quantiles, P(metric > threshold), each with its interval) and its factors ranked by
importance with the measures beside, every column labelled, values in the shown units
(display.py: mrad, mm). The intervals' level is printed as given ("99.9 %", never rounded up
to 100 %); with --bootstrap 0 the bootstrap intervals (the std's, the ranking's measures', a
Morris design's spread) are absent and the table says so. A chaos that fails its validation
(chaos.py) has its indices withheld: the table says so and why, and never ranks by them."""
from . import display as dp


def _level(doc):
    """"95 %", "99.9 %": the confidence as given (10 significant digits, not rounded up)."""
    return f"{100 * doc['confidence']:.10g} %"


def _intervals(doc):
    """"95 % intervals", "99.9 % intervals", or "no intervals (bootstrap 0)" for the bootstrap
    intervals (the Sobol, Morris, PRCC and std intervals are bootstrap intervals)."""
    if doc["bootstrap"] == 0:
        return "no intervals (bootstrap 0)"
    return f"{_level(doc)} intervals"


def _header(m, r, where):
    shown = dp.unit(r["units"])[0]
    return (f"\n{m} [{shown}]" + (f" at {where}" if where else "")
            + f": {r['used']} cases used, {r['failed']} failed, {r['non_finite']} non-finite")


def _spread_level(d, doc):
    """The spread's interval heading: its level and the mean's interval kind; none when the
    spread's intervals are all bootstrap ones and there is no bootstrap; the std's absent."""
    kind = d.get("mean_interval_kind")
    if kind is None:
        return _intervals(doc) if doc["bootstrap"] == 0 else "no intervals"
    text = f"{_level(doc)} intervals ({kind} for the mean)"
    return text + ("; the std's none: no intervals (bootstrap 0)" if doc["bootstrap"] == 0
                   else "")


def _spread(m, r, doc):
    d, si = r.get("distribution"), r["units"]
    if not d:
        return []
    what = d.get("sample") or "independent points"
    lines = [f"  spread over {d['n']} {what}; {_spread_level(d, doc)}",
             f"    {'quantity':<22}{'value':>11}  interval"]
    rows = [("mean", d["mean"], d.get("mean_interval")), ("std", d["std"], d.get("std_interval"))]
    rows += [(f"{float(p) * 100:g} % quantile", v, (d.get("quantile_intervals") or {}).get(p))
             for p, v in d["quantiles"].items()]
    for name, v, iv in rows:
        iv = dp.scaled(iv, si)
        lines.append(f"    {name:<22}{dp.g(dp.scaled(v, si), 11)}  "
                     f"{_open_ends(iv, d['n'], doc) or dp.interval(iv)}")
    for e in r.get("exceedance", []):
        name = f"P(> {dp.g(dp.scaled(e['threshold'], si))}{dp.suffix(si)})"
        lines.append(f"    {name:<22}{dp.g(e['probability'], 11)}  "
                     f"{dp.interval(e.get('interval'))}  ({e['exceed']} of {e['n']})")
    return lines


def _open_ends(iv, n, doc):
    """A quantile's order-statistic interval with an end no rank of the n points gives (a 5 %
    quantile's lower end below 72 points at 95 %): the end that exists and why the other is
    missing, instead of a blank ("" when both ends exist, or there is no interval)."""
    if not iv or (iv[0] is not None and iv[1] is not None):
        return ""
    lo = "none" if iv[0] is None else dp.g(iv[0])
    hi = "none" if iv[1] is None else dp.g(iv[1])
    return f"[{lo}, {hi}]  ({n} points are too few for a {_level(doc)} interval's end)"


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


def _ranking(r, keys, doc):
    rk = r.get("ranking")
    if not rk:
        return []
    column = f"{_level(doc)} interval" if doc["bootstrap"] else "interval"
    si = r["units"] if rk["units"] != "1" else ""
    unit = f" [{dp.unit(si)[0]}]" if si else " [1]"
    width = max([len("factor")] + [len(dp.short(k)) for k in keys])
    extras = _extras(r)
    head = f"    {'rank':>4}  {'factor':<{width}}  {'value':>10}  {column:<22}"
    head += "".join(f"  {name:>{max(10, len(name))}}" for name, *_ in extras)
    lines = [f"  factors ranked by {rk['by']}{unit}"
             + ("; no intervals (bootstrap 0)" if not doc["bootstrap"] else ""), head]
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
    if "withheld" in c:
        out.append(f"  chaos: indices withheld: {c.get('validation') or c['withheld']}")
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
    for g in doc["groups"]:
        where = ", ".join(f"{k} = {v}" for k, v in g["grid"].items())
        for m, r in g["metrics"].items():
            lines.append(_header(m, r, where))
            lines += _spread(m, r, doc) + _ranking(r, keys, doc) + _notes(r)
    return "\n".join(lines).lstrip("\n")
