"""The polynomial chaos's basis, factor by factor, with its orthonormality checked.

Each factor is expanded over a variable z of a distribution whose orthonormal polynomials are
well defined at every degree the chaos uses (an isoprobabilistic transformation, exact):
  lognormal  z = (ln x - mu) / sigma ~ N(0, 1) (mu, sigma the log's mean and std), expanded on
             Hermite polynomials. The lognormal's own moment problem is indeterminate: the
             polynomials OpenTURNS builds for it by Stieltjes's procedure lose orthonormality
             fast (max |Gram - I| = 0.0088 at degree 6 and 220 at degree 12 for a std/mean of
             0.3), and a chaos on them reports indices off by 0.06 with Q² = 1.
  otherwise  z = x, on OpenTURNS's StandardDistributionPolynomialFactory for its distribution
             (Legendre for uniform, Hermite for normal, Stieltjes's procedure for the
             truncated normal, triangular and discrete).
Then, for each factor, the Gram matrix E[P_j(z) P_k(z)], j, k <= p, is computed by a
quadrature rule of z's distribution that owes nothing to those polynomials (Gauss-Hermite for a
normal, Gauss-Legendre pieces times the density for a bounded density, the weighted points of a
discrete factor), through the same transformation the chaos applies; the factor's degree is
capped at the largest p <= MAX_DEGREE whose max |Gram - I| <= GRAM_TOLERANCE (a discrete factor
of k values also at k - 1). Measured: below 2e-13 at degree 12 for every distribution above.
"""
import math

import numpy as np
import openturns as ot

from .distributions import log_parameters, marginal

MAX_DEGREE = 12
GRAM_TOLERANCE = 1e-8


def variable(f):
    """(the distribution of the variable z factor f is expanded over, the map x -> z on an
    array of f's values)."""
    if f["distribution"] == "lognormal":
        mu, sigma = log_parameters(float(f["mean"]), float(f["std"]))

        def to_z(x):
            if np.any(~(x > 0)):
                raise ValueError(f"factor {f['key']}: a lognormal factor's value is not > 0 in "
                                 "the summary")
            return (np.log(x) - mu) / sigma
        return ot.Normal(0.0, 1.0), to_z
    return marginal(f), lambda x: x


def to_variables(design, x):
    """The factors' values x (n, d) as the variables z (n, d) the chaos is expanded over."""
    return np.column_stack([variable(f)[1](x[:, i]) for i, f in enumerate(design["factors"])])


def joint(design):
    """The independent joint distribution of the variables z."""
    dist = ot.ComposedDistribution([variable(f)[0] for f in design["factors"]])
    dist.setDescription([f["key"] for f in design["factors"]])
    return dist


def quadrature(dist):
    """(nodes, weights) of a rule integrating polynomials of degree <= 2 MAX_DEGREE + 1 against
    the 1-D distribution dist exactly (normal, uniform, triangular, discrete) or to rounding (a
    truncated normal's density over pieces of at most 0.6 std)."""
    impl = dist.getImplementation() if hasattr(dist, "getImplementation") else dist
    name = impl.getClassName()
    if name == "Normal":
        t, w = np.polynomial.hermite_e.hermegauss(64)
        m, s = dist.getMean()[0], dist.getStandardDeviation()[0]
        return m + s * t, w / w.sum()
    if name == "UserDefined":
        return np.asarray(dist.getSupport()).ravel(), \
            np.array([dist.computePDF(p) for p in dist.getSupport()])
    lo, hi = dist.getRange().getLowerBound()[0], dist.getRange().getUpperBound()[0]
    breaks = [lo, hi]
    if name == "Triangular":
        breaks.insert(1, dist.getParameter()[1])
    if name == "TruncatedNormal":
        m, s = dist.getParameter()[0], dist.getParameter()[1]
        lo, hi = max(lo, m - 40 * s), min(hi, m + 40 * s)
        breaks = list(np.linspace(lo, hi, 1 + max(1, math.ceil((hi - lo) / (0.6 * s)))))
    t, w = np.polynomial.legendre.leggauss(32)
    nodes = np.concatenate([(a + b) / 2 + (b - a) / 2 * t for a, b in zip(breaks, breaks[1:])])
    weights = np.concatenate([(b - a) / 2 * w for a, b in zip(breaks, breaks[1:])])
    return nodes, weights * np.asarray(dist.computePDF(ot.Sample(nodes[:, None]))).ravel()


def gram_errors(dist, degree):
    """[max |Gram - I| of the polynomials of degree 0..p] for p = 0..degree: the polynomials
    the chaos uses for a variable of distribution dist, through the transformation it applies."""
    factory = ot.StandardDistributionPolynomialFactory(dist)
    nodes, weights = quadrature(dist)
    z = ot.DistributionTransformation(dist, factory.getMeasure())(ot.Sample(nodes[:, None]))
    one = ot.OrthogonalProductPolynomialFactory(
        [factory], ot.EnumerateFunction(ot.HyperbolicAnisotropicEnumerateFunction(1, 1.0)))
    p = np.array([np.asarray(one.build(k)(z)).ravel() for k in range(degree + 1)])
    g = np.abs((p * weights) @ p.T - np.eye(degree + 1))
    return [float(g[:k + 1, :k + 1].max()) for k in range(degree + 1)]


def caps(design):
    """[{key, variable, degree, gram_error}] per factor: the largest degree (<= MAX_DEGREE; a
    discrete factor of k values <= k - 1) whose polynomials pass the Gram check, and the
    check's max |Gram - I| at that degree."""
    out = []
    for f in design["factors"]:
        dist = variable(f)[0]
        top = min(MAX_DEGREE, len(f["values"]) - 1) if f["distribution"] == "discrete" \
            else MAX_DEGREE
        errors = gram_errors(dist, top)
        ok = [k for k in range(top + 1) if errors[k] <= GRAM_TOLERANCE]
        degree = ok[-1] if ok else 0
        out.append({"key": f["key"], "degree": degree, "gram_error": errors[degree],
                    "variable": "(ln x - mu) / sigma ~ N(0, 1)"
                    if f["distribution"] == "lognormal" else "x"})
    return out


def product_basis(design, q_norm):
    """(the product basis, its enumeration by hyperbolic q-norm with each factor's degree
    capped, the per-factor caps of caps(design))."""
    checks = caps(design)
    d = len(checks)
    enum = ot.HyperbolicAnisotropicEnumerateFunction(d, q_norm)
    bound = [c["degree"] for c in checks]
    if min(bound) < MAX_DEGREE:
        enum.setUpperBound(ot.Indices(bound))
    enum = ot.EnumerateFunction(enum)
    dist = joint(design)
    polys = [ot.StandardDistributionPolynomialFactory(dist.getMarginal(i)) for i in range(d)]
    return ot.OrthogonalProductPolynomialFactory(polys, enum), enum, checks
