"""How the analysis shows a metric's unit in its printed table, its figures and the report:
angles in mrad and lengths in mm (the sizes a rod-end's errors and clearances have), every
other unit as the summary gives it. analysis.json keeps SI values with their unit."""
import numbers

DISPLAY = {"rad": ("mrad", 1e3), "m": ("mm", 1e3)}


def unit(si):
    """(shown unit, factor from SI) of an SI unit; a product shown with a middle dot (N*m -> N·m),
    as the figures of plots/ write it."""
    return DISPLAY.get(si or "", ((si or "").replace("*", "·"), 1.0))


def scaled(value, si):
    """A value (or None, or a [lower, upper] interval) in the shown unit."""
    f = unit(si)[1]
    if value is None:
        return None
    if isinstance(value, (list, tuple)):
        return [None if v is None else v * f for v in value]
    return value * f


def suffix(si):
    """" mrad" after a value in the shown unit, nothing for a number of unit 1."""
    shown = unit(si)[0]
    return f" {shown}" if shown not in ("", "1") else ""


def g(v, width=0):
    """A number with 4 significant digits ("–" for none), right-aligned in width."""
    text = "–" if v is None or not isinstance(v, numbers.Real) or v != v else f"{v:.4g}"
    return f"{text:>{width}}"


def interval(iv):
    """"[lo, hi]" of an interval, "" for none."""
    return "" if not iv or iv[0] is None or iv[1] is None else f"[{g(iv[0])}, {g(iv[1])}]"


def short(key):
    """A factor's label: its key without "parameters." (slider_spring.stiffness and
    crank_spring.stiffness must stay two labels)."""
    return key[len("parameters."):] if key.startswith("parameters.") else key
