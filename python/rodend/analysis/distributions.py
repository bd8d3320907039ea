"""The factors' distributions of design.json as OpenTURNS distributions."""
import math

import openturns as ot


def log_parameters(mean, std):
    """(mu, sigma): the mean and std of ln X for a lognormal X of this mean and std."""
    var_log = math.log1p((std / mean) ** 2)
    return math.log(mean) - var_log / 2, math.sqrt(var_log)


def marginal(f):
    """One factor {key, distribution, parameters...} as an ot.Distribution."""
    kind = f["distribution"]
    try:
        if kind == "uniform":
            return ot.Uniform(float(f["lower"]), float(f["upper"]))
        if kind == "normal":
            return ot.Normal(float(f["mean"]), float(f["std"]))
        if kind == "truncated-normal":
            # design.json gives the parent normal's parameters as parent_mean, parent_std and
            # the moments as mean, std; before it did, mean and std were the parent's
            return ot.TruncatedNormal(float(f.get("parent_mean", f["mean"])),
                                      float(f.get("parent_std", f["std"])), float(f["lower"]),
                                      float(f["upper"]))
        if kind == "lognormal":
            return ot.LogNormal(*log_parameters(float(f["mean"]), float(f["std"])))
        if kind == "triangular":
            return ot.Triangular(float(f["lower"]), float(f["mode"]), float(f["upper"]))
        if kind == "discrete":
            values = ot.Sample([[float(v)] for v in f["values"]])
            return ot.UserDefined(values, ot.Point([float(w) for w in f["weights"]]))
    except KeyError as e:
        raise ValueError(f"design.json: factor {f.get('key')}: {kind} needs {e.args[0]!r}") \
            from None
    raise ValueError(f"design.json: factor {f.get('key')}: unknown distribution {kind!r}: "
                     "expected uniform, normal, truncated-normal, lognormal, triangular or "
                     "discrete")


def joint(design):
    """The independent joint distribution of the design's factors, in their order."""
    margs = [marginal(f) for f in design["factors"]]
    dist = ot.ComposedDistribution(margs)
    dist.setDescription([f["key"] for f in design["factors"]])
    return dist
