"""A polynomial-chaos surrogate of one metric (OpenTURNS) and its exact leave-one-out Q².

The basis: products of polynomials orthonormal for each factor's distribution (OpenTURNS's
StandardDistributionPolynomialFactory), enumerated by hyperbolic q-norm (q = 0.75: the
interactions of high total degree come last), each discrete factor of k values capped at
degree k - 1. The coefficients: least squares on the whole basis of total degree p
(ot.LeastSquaresStrategy). The degree p is chosen by the exact leave-one-out error: for each
p = 1, 2, ... whose basis has at most n/3 terms (and at most MAX_TERMS), the LOO residuals of
the least-squares fit are e_i / (1 - h_ii), h the hat matrix's diagonal (h_ii = |Q_i|², Q from
a QR factorisation of the design matrix: one QR of the widest basis serves every p, the first
k columns of Q spanning the first k basis terms); the p of the smallest PRESS wins.
Q² = 1 - PRESS / sum (y - mean y)², for the chosen basis; chosen on the same points, it is
slightly optimistic.

OpenTURNS's sparse LARS (method "lars": LeastSquaresMetaModelSelectionFactory with LARS and
corrected leave-one-out) selects terms among the basis of degree LARS_DEGREE instead; its Q² is
the exact LOO of the selected terms, computed the same way (more optimistic: more was chosen
on the same points). Sparse fits need far fewer points (8 factors, 1000 points: Q² 0.986
against 0.715 for least squares) but LARS's cost grows fast (15 s there, 90 s at 2000
points). "auto" (the default) fits least squares, and LARS too when it is cheap (points ×
candidate terms <= LARS_WORK), and keeps the larger Q².
"""
import json
import math

import numpy as np
import openturns as ot

from .distributions import joint

Q_NORM = 0.75
MAX_DEGREE = 12
MAX_TERMS = 600
LARS_DEGREE = 8     # LARS's candidates: the basis of this q-norm degree (at most MAX_TERMS)
LARS_WORK = 300000  # auto: LARS too when points × candidates <= this (about 3 s; beyond, minutes)


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
    return _loo_nested(q, np.abs(np.diag(r)), y, [psi.shape[1]])[0]


def _loo_nested(q, rdiag, y, sizes):
    """[(Q², LOO predictions)] of the fits on the first k columns, k in sizes, from one QR
    factorisation of the widest (its first k columns are the QR of the first k columns)."""
    out, h, fitted, done = [], np.zeros(len(y)), np.zeros(len(y)), 0
    b = q.T @ y
    ss = float(np.sum((y - y.mean()) ** 2))
    for k in sizes:
        h += np.einsum("ij,ij->i", q[:, done:k], q[:, done:k])
        fitted += q[:, done:k] @ b[done:k]
        done = k
        if np.min(rdiag[:k]) < 1e-10 * np.max(rdiag[:k]) or np.max(h) > 1 - 1e-10 or ss == 0:
            out.append((math.nan, None))
            continue
        e = (y - fitted) / (1 - h)
        out.append((1 - float(np.sum(e ** 2)) / ss, y - e))
    return out


_CACHE = {}


def _design_matrix(design, dist, x, limit):
    """(basis, the sizes of total degree 1, 2, ... up to limit terms, Q, |diag R|) of the
    widest of those bases on x; kept for the next metric on the same points."""
    key = (json.dumps(design["factors"], sort_keys=True), x.shape, hash(x.tobytes()), limit)
    if key in _CACHE:
        return _CACHE[key]
    basis, enum = _basis(design, dist)
    sizes = []
    for p in range(1, MAX_DEGREE + 1):
        size = enum.getBasisSizeFromTotalDegree(p)
        if size > limit:
            break
        if not sizes or size > sizes[-1]:
            sizes.append(size)
    if not sizes:
        return basis, sizes, None, None
    zs = ot.DistributionTransformation(dist, basis.getMeasure())(ot.Sample(x))
    psi = np.column_stack([np.asarray(basis.build(k)(zs)).ravel() for k in range(sizes[-1])])
    q, r = np.linalg.qr(psi)
    _CACHE.clear()
    _CACHE[key] = (basis, sizes, q, np.abs(np.diag(r)))
    return _CACHE[key]


def _choose_degree(design, dist, x, y):
    """(size, basis, Q², LOO predictions) of the basis of the smallest exact LOO error among
    the total degrees whose basis fits; size None when none does."""
    basis, sizes, q, rdiag = _design_matrix(design, dist, x, min(MAX_TERMS, len(y) // 3))
    if not sizes:
        return None, basis, math.nan, None
    best = None
    for size, (q2, pred) in zip(sizes, _loo_nested(q, rdiag, y, sizes)):
        if math.isnan(q2):
            break
        if best is None or q2 > best[2]:
            best = (size, basis, q2, pred)
    return best or (None, basis, math.nan, None)


def fit(design, x, y, method="auto"):
    """The chaos of y over the factors x (n, d): a dict with the basis size, degree, the exact
    LOO Q² and predictions, R², and the chaos's first-order and total Sobol indices. method:
    "least-squares", "lars" or "auto": least squares, and LARS too when points × candidate
    terms <= LARS_WORK, the one of the larger Q² kept."""
    if method != "auto":
        return _fit(design, x, y, method)
    best = _fit(design, x, y, "least-squares")
    if len(y) * _lars_candidates(_basis(design, joint(design))[1]) <= LARS_WORK:
        other = _fit(design, x, y, "lars")
        tried = {"least-squares": best.get("q2_loo"), "lars": other.get("q2_loo")}
        if "q2_loo" not in best or other.get("q2_loo", -math.inf) > best["q2_loo"]:
            best = other
        best["q2_loo_tried"] = tried
    return best


def _lars_candidates(enum):
    """The terms of q-norm degree LARS_DEGREE, at most MAX_TERMS, counted degree by degree (the
    enumeration of a high degree in many dimensions takes seconds)."""
    size = 0
    for p in range(1, LARS_DEGREE + 1):
        size = enum.getBasisSizeFromTotalDegree(p)
        if size >= MAX_TERMS:
            return MAX_TERMS
    return size


def _fit(design, x, y, method):
    dist = joint(design)
    xs, ys = ot.Sample(x), ot.Sample(y.reshape(-1, 1))
    if method == "lars":
        basis, enum = _basis(design, dist)
        size = _lars_candidates(enum)
        proj = ot.LeastSquaresStrategy(ot.LeastSquaresMetaModelSelectionFactory(
            ot.LARS(), ot.CorrectedLeaveOneOut()))
    else:
        size, basis, q2, pred = _choose_degree(design, dist, x, y)
        if size is None:
            return {"skipped": f"{len(y)} points are too few for a basis of total degree 1 "
                               "(it needs 3 points a term) or every basis interpolates"}
        proj = ot.LeastSquaresStrategy()
    result = _run(ot.FunctionalChaosAlgorithm(xs, ys, dist, ot.FixedStrategy(basis, size), proj))
    if method == "lars":
        z = result.getTransformation()(xs)
        q2, pred = loo(np.column_stack([np.asarray(f(z)).ravel()
                                        for f in result.getReducedBasis()]), y)
    fitted = np.asarray(result.getMetaModel()(xs)).ravel()
    ss = float(np.sum((y - y.mean()) ** 2))
    sob = ot.FunctionalChaosSobolIndices(result)
    d = x.shape[1]
    return {"method": method, "candidate_terms": int(size),
            "terms": int(result.getIndices().getSize()), "degree": _degree(result),
            "q2_loo": q2, "r2": 1 - float(np.sum((y - fitted) ** 2)) / ss if ss > 0 else math.nan,
            "loo_prediction": pred, "first_order": [sob.getSobolIndex(i) for i in range(d)],
            "total": [sob.getSobolTotalIndex(i) for i in range(d)], "points": len(y)}


def _run(algo):
    """Runs a chaos algorithm with its least squares solved by the normal equations (Cholesky),
    five times faster than OpenTURNS's default SVD at 1e4 points and well conditioned here:
    the basis is orthonormal for the factors' distribution, so the normal matrix is close to
    n times the identity."""
    key = "PenalizedLeastSquaresAlgorithm-UseNormal"
    before = ot.ResourceMap.GetAsBool(key)
    ot.ResourceMap.SetAsBool(key, True)
    try:
        algo.run()
    finally:
        ot.ResourceMap.SetAsBool(key, before)
    return algo.getResult()


def _degree(result):
    enum = result.getOrthogonalBasis().getEnumerateFunction()
    return int(max(sum(enum(int(i))) for i in result.getIndices()))
