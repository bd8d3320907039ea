"""The factors' distributions of design.json as OpenTURNS distributions: one constructor per
distribution of the catalogue (sweep/distributions.def, python/rodend/analysis/catalogue.py),
given the parameters the catalogue names."""
import math

import openturns as ot

from .catalogue import DISTRIBUTIONS


def log_parameters(mean, std):
    """(mu, sigma): the mean and std of ln X for a lognormal X of this mean and std."""
    var_log = math.log1p((std / mean) ** 2)
    return math.log(mean) - var_log / 2, math.sqrt(var_log)


def _discrete(p):
    values = ot.Sample([[float(v)] for v in p["values"]])
    return ot.UserDefined(values, ot.Point([float(w) for w in p["weights"]]))


# name -> the OpenTURNS distribution of its catalogue parameters p (numbers, or lists for
# values and weights); a truncated normal's mean and std are its parent normal's
OPENTURNS = {
    "uniform": lambda p: ot.Uniform(p["lower"], p["upper"]),
    "normal": lambda p: ot.Normal(p["mean"], p["std"]),
    "truncated-normal": lambda p: ot.TruncatedNormal(p["mean"], p["std"], p["lower"], p["upper"]),
    "lognormal": lambda p: ot.LogNormal(*log_parameters(p["mean"], p["std"])),
    "triangular": lambda p: ot.Triangular(p["lower"], p["mode"], p["upper"]),
    "discrete": _discrete,
}


def _parameter(f, kind, key):
    # design.json gives a truncated normal's parent parameters as parent_mean, parent_std and its
    # moments as mean, std; before it did, mean and std were the parent's
    if kind == "truncated-normal" and key in ("mean", "std"):
        return f.get("parent_" + key, f[key])
    return f[key]


def marginal(f):
    """One factor {key, distribution, parameters...} as an ot.Distribution."""
    kind = f["distribution"]
    if kind not in DISTRIBUTIONS or kind not in OPENTURNS:
        raise ValueError(f"design.json: factor {f.get('key')}: unknown distribution {kind!r}: "
                         f"expected {', '.join(DISTRIBUTIONS)}")
    p = {}
    for key in DISTRIBUTIONS[kind]["keys"]:
        try:
            v = _parameter(f, kind, key)
        except KeyError:
            raise ValueError(f"design.json: factor {f.get('key')}: {kind} needs {key!r}") \
                from None
        p[key] = [float(x) for x in v] if isinstance(v, list) else float(v)
    return OPENTURNS[kind](p)


def joint(design):
    """The independent joint distribution of the design's factors, in their order."""
    margs = [marginal(f) for f in design["factors"]]
    dist = ot.ComposedDistribution(margs)
    dist.setDescription([f["key"] for f in design["factors"]])
    return dist
