"""A polynomial-chaos surrogate of one metric (OpenTURNS) and its exact leave-one-out Q².

The basis: products of polynomials orthonormal for each factor's distribution (OpenTURNS's
StandardDistributionPolynomialFactory), enumerated by hyperbolic q-norm (q = 0.75: the
interactions of high total degree come last), each discrete factor of k values capped at
degree k - 1. The coefficients: least squares on the whole basis of total degree p
(ot.LeastSquaresStrategy). The degree p is chosen by the exact leave-one-out error: for each
p = 1, 2, ... whose basis has at most n/3 terms (and at most MAX_TERMS), the LOO residuals of
the least-squares fit are e_i / (1 - h_ii), h the hat matrix's diagonal (h_ii = |Q_i|², Q from
a QR factorisation of the design matrix); the p of the smallest PRESS wins. Q² = 1 - PRESS /
sum (y - mean y)². OpenTURNS's sparse LARS (method "lars") selects terms instead; it is exact
too (the LOO of the selected basis, computed the same way) but costs minutes at 1e4 cases, so
it is not the default.
"""
import math

import numpy as np
import openturns as ot

from .distributions import joint

Q_NORM = 0.75
MAX_DEGREE = 12
MAX_TERMS = 600


def _basis(design, dist):
    d = dist.getDimension()
    enum = ot.HyperbolicAnisotropicEnumerateFunction(d, Q_NORM)
    caps = [len(f["values"]) - 1 if f["distribution"] == "discrete" else 10 ** 6
            for f in design["factors"]]
    if min(caps) < 10 ** 6:
        enum.setUpperBound(ot.Indices(caps))
    enum = ot.EnumerateFunction(enum)
    polys = [ot.StandardDistributionPolynomialFactory(dist.getMarginal(i)) for i in range(d)]
    return ot.OrthogonalProductPolynomialFactory(polys, enum), enum


def loo(psi, y):
    """(Q², LOO predictions) of the least-squares fit of y on the columns of psi, exactly from
    the hat matrix; (nan, None) when a point has leverage 1 (the fit interpolates it)."""
    q, r = np.linalg.qr(psi)
    if np.min(np.abs(np.diag(r))) < 1e-10 * np.max(np.abs(np.diag(r))):
        return math.nan, None
    h = np.einsum("ij,ij->i", q, q)
    if np.max(h) > 1 - 1e-10:
        return math.nan, None
    resid = y - q @ (q.T @ y)
    e = resid / (1 - h)
    ss = float(np.sum((y - y.mean()) ** 2))
    return (1 - float(np.sum(e ** 2)) / ss if ss > 0 else math.nan), y - e


def _choose_degree(design, dist, x, y):
    """The total degree of the smallest exact LOO error, among the degrees whose basis fits."""
    basis, enum = _basis(design, dist)
    z = np.asarray(ot.DistributionTransformation(dist, basis.getMeasure())(ot.Sample(x)))
    limit = min(MAX_TERMS, len(y) // 3)
    sizes = [enum.getBasisSizeFromTotalDegree(p) for p in range(1, MAX_DEGREE + 1)]
    sizes = [s for s in dict.fromkeys(sizes) if s <= limit]
    if not sizes:
        return None, None
    zs = ot.Sample(z)
    psi = np.column_stack([np.asarray(basis.build(k)(zs)).ravel() for k in range(sizes[-1])])
    best, worse = None, 0
    for p, size in enumerate(sizes, start=1):
        q2, _ = loo(psi[:, :size], y)
        if math.isnan(q2):
            break
        if best is None or q2 > best[1]:
            best, worse = (size, q2), 0
        else:
            worse += 1
            if worse == 2:
                break
    return (best[0] if best else None), basis


def fit(design, x, y, method="least-squares"):
    """The chaos of y over the factors x (n, d): a dict with the basis size, degree, the exact
    LOO Q² and predictions, R², and the chaos's first-order and total Sobol indices."""
    dist = joint(design)
    xs, ys = ot.Sample(x), ot.Sample(y.reshape(-1, 1))
    if method == "lars":
        basis, enum = _basis(design, dist)
        size = min(MAX_TERMS, enum.getBasisSizeFromTotalDegree(8))
        proj = ot.LeastSquaresStrategy(ot.LeastSquaresMetaModelSelectionFactory(
            ot.LARS(), ot.CorrectedLeaveOneOut()))
    else:
        size, basis = _choose_degree(design, dist, x, y)
        if size is None:
            return {"skipped": f"{len(y)} points are too few for a basis of total degree 1 "
                               "(it needs 3 points a term)"}
        proj = ot.LeastSquaresStrategy()
    algo = ot.FunctionalChaosAlgorithm(xs, ys, dist, ot.FixedStrategy(basis, size), proj)
    algo.run()
    result = algo.getResult()
    z = result.getTransformation()(xs)
    psi = np.column_stack([np.asarray(f(z)).ravel() for f in result.getReducedBasis()])
    q2, pred = loo(psi, y)
    fitted = np.asarray(result.getMetaModel()(xs)).ravel()
    ss = float(np.sum((y - y.mean()) ** 2))
    sob = ot.FunctionalChaosSobolIndices(result)
    d = x.shape[1]
    return {"method": method, "candidate_terms": int(size), "terms": len(psi[0]),
            "degree": _degree(result),
            "q2_loo": q2, "r2": 1 - float(np.sum((y - fitted) ** 2)) / ss if ss > 0 else math.nan,
            "loo_prediction": pred, "first_order": [sob.getSobolIndex(i) for i in range(d)],
            "total": [sob.getSobolTotalIndex(i) for i in range(d)], "points": len(y)}


def _degree(result):
    enum = result.getOrthogonalBasis().getEnumerateFunction()
    return int(max(sum(enum(int(i))) for i in result.getIndices()))
