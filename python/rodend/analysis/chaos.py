"""A polynomial-chaos surrogate of one metric (OpenTURNS), its exact leave-one-out Q² and its
validation.

The basis (basis.py): products of polynomials orthonormal for each factor's variable (a
lognormal's standardised log, every other factor itself), each factor's degree capped where a
numerical Gram check of its polynomials passes, enumerated by hyperbolic q-norm (q = 0.75: the
interactions of high total degree come last), each discrete factor of k values capped at
degree k - 1. The coefficients: least squares on the whole basis of total degree p, from the
QR factorisation of its design matrix (numpy); the Sobol indices from the coefficients. The
degree p is chosen by the exact leave-one-out error: for each
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

The validation (_validated): the chosen terms' FOLDS-fold cross-validation Q² (each fold
predicted by the fit to the others, exactly from the QR) must reach Q2_MIN, and the chaos's
variance under the distribution (its squared coefficients: the basis is orthonormal) must
agree with its variance over the points within VARIANCE_SIGMAS standard errors; otherwise the
indices are withheld and the reason given.
"""
import json
import math

import numpy as np
import openturns as ot

from . import basis as _basis_mod

Q_NORM = 0.75
MAX_DEGREE = _basis_mod.MAX_DEGREE
MAX_TERMS = 600
LARS_DEGREE = 8     # LARS's candidates: the basis of this q-norm degree (at most MAX_TERMS)
LARS_WORK = 300000  # auto: LARS too when points × candidates <= this (about 3 s; beyond, minutes)
FOLDS = 5           # the validation: FOLDS-fold cross-validation of the chosen terms
Q2_MIN = 0.9        # ... whose Q² must reach this for the indices to be reported
VARIANCE_SIGMAS = 4.0  # the chaos's variance vs its points' variance: standard errors allowed

_BASES = {}


def _basis(design):
    """The chaos's basis over the design's factors (basis.Basis: Gram-checked families, the
    q-norm enumeration), kept for the next metric."""
    key = json.dumps(design["factors"], sort_keys=True)
    if key not in _BASES:
        _BASES.clear()
        _BASES[key] = _basis_mod.Basis(design, Q_NORM)
    return _BASES[key]


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


def _folds(n):
    """FOLDS folds of the points 0..n-1 (a fixed permutation: the same points, the same
    folds)."""
    perm = np.random.default_rng(0).permutation(n)
    return [np.sort(perm[k::FOLDS]) for k in range(FOLDS)]


def kfold(q, y, folds, grams=None):
    """(Q², predictions) of the FOLDS-fold cross-validation of the least-squares fit of y on
    the columns of q (orthonormal: the Q of the design matrix's QR): each fold predicted by the
    fit on the other points, gamma = (I - Q_F' Q_F)^-1 (Q' y - Q_F' y_F), exactly what a refit
    without the fold gives. grams: the folds' Q_F' Q_F over at least q's columns (kept across
    metrics). (nan, None) when the other points leave the basis singular."""
    k, b = q.shape[1], q.T @ y
    pred = np.empty(len(y))
    for i, f in enumerate(folds):
        g = grams[i][:k, :k] if grams is not None else q[f].T @ q[f]
        m = np.eye(k) - g
        if np.linalg.eigvalsh(m)[0] < 1e-10:
            return math.nan, None
        pred[f] = q[f] @ np.linalg.solve(m, b - q[f].T @ y[f])
    ss = float(np.sum((y - y.mean()) ** 2))
    return (1 - float(np.sum((y - pred) ** 2)) / ss if ss > 0 else math.nan), pred


def _design_matrix(design, z, limit):
    """(the sizes of total degree 1, 2, ... up to limit terms, Q, R, the folds' Q_F' Q_F) of
    the widest of those bases on the variables z; kept for the next metric on the same
    points."""
    key = (json.dumps(design["factors"], sort_keys=True), z.shape, hash(z.tobytes()), limit)
    if key in _CACHE:
        return _CACHE[key]
    basis = _basis(design)
    sizes = []
    for p in range(1, MAX_DEGREE + 1):
        size = _size(basis.enum, p)
        if size is None or size > limit:
            break
        if not sizes or size > sizes[-1]:
            sizes.append(size)
    if not sizes:
        return sizes, None, None, None
    q, r = np.linalg.qr(basis.matrix(z, sizes[-1]))
    grams = [q[f].T @ q[f] for f in _folds(len(z))]
    _CACHE.clear()
    _CACHE[key] = (sizes, q, r, grams)
    return _CACHE[key]


def _choose_degree(design, z, y):
    """The least-squares chaos of the basis of the smallest exact LOO error among the total
    degrees whose basis fits (a dict as _summary's); None when none does."""
    sizes, q, r, grams = _design_matrix(design, z, min(MAX_TERMS, len(y) // 3))
    if not sizes:
        return None
    best = None
    for size, (q2, pred) in zip(sizes, _loo_nested(q, np.abs(np.diag(r)), y, sizes)):
        if math.isnan(q2):
            break
        if best is None or q2 > best[1]:
            best = (size, q2, pred)
    if best is None:
        return None
    k = best[0]
    b = q[:, :k].T @ y
    coef = np.linalg.solve(np.triu(r[:k, :k]), b)
    return _summary("least-squares", _basis(design).multi_indices(k), coef, y, q[:, :k] @ b,
                    best[1], best[2], kfold(q[:, :k], y, _folds(len(y)), grams)[0], k)


def fit(design, x, y, method="auto"):
    """The chaos of y over the factors x (n, d): a dict with the basis size, degree, the exact
    LOO Q² and predictions, the FOLDS-fold Q², R², the per-factor Gram checks, the validation
    and, when it passed, the chaos's first-order and total Sobol indices. method:
    "least-squares", "lars" or "auto": least squares, and LARS too when points × candidate
    terms <= LARS_WORK, the one of the larger Q² kept. LARS needs every factor continuous (its
    basis is OpenTURNS's)."""
    z = _basis_mod.to_variables(design, x)
    basis = _basis(design)
    checks = basis.checks
    if min(c["degree"] for c in checks) < 1:
        bad = [c["key"] for c in checks if c["degree"] < 1]
        return {"skipped": f"no polynomial of degree 1 passes the orthonormality check for "
                           f"{', '.join(bad)}", "basis": checks}
    if method == "lars" and basis.openturns is None:
        raise ValueError("--chaos lars: a discrete factor's polynomials are rodend's own, not "
                         "OpenTURNS's, which its LARS needs; use least-squares or auto")
    if method != "auto":
        return _validated(_fit(design, z, y, method), checks)
    best = _fit(design, z, y, "least-squares")
    if basis.openturns is not None and len(y) * _lars_candidates(basis.enum) <= LARS_WORK:
        other = _fit(design, z, y, "lars")
        tried = {"least-squares": best.get("q2_loo"), "lars": other.get("q2_loo")}
        if "q2_loo" not in best or other.get("q2_loo", -math.inf) > best["q2_loo"]:
            best = other
        best["q2_loo_tried"] = tried
    return _validated(best, checks)


def _validated(r, checks):
    """r with the per-factor Gram checks and its validation; the indices removed (and the
    reason given) when the validation fails: a FOLDS-fold Q² below Q2_MIN, or the chaos's
    variance under the factors' distribution (the sum of its squared coefficients) more than
    VARIANCE_SIGMAS standard errors from its variance over the points it was fitted to (it
    then differs where no point was drawn)."""
    r["basis"] = checks
    if "skipped" in r:
        return r
    v = r.pop("_variance")
    why = []
    if not r["q2_kfold"] >= Q2_MIN:
        why.append(f"its {FOLDS}-fold Q² {r['q2_kfold']:.4g} is below {Q2_MIN}")
    if not abs(v["coefficients"] - v["points"]) <= VARIANCE_SIGMAS * v["standard_error"] + \
            1e-12 * v["points"]:
        why.append(f"its variance under the factors' distribution, {v['coefficients']:.6g}, "
                   f"is not its variance over the points, {v['points']:.6g} "
                   f"(± {v['standard_error']:.2g})")
    r["variance_check"] = v
    r["validation"] = "passed" if not why else "failed: " + "; ".join(why)
    if why:
        r["withheld"] = "the surrogate's indices are not reported: " + "; ".join(why)
        r.pop("first_order")
        r.pop("total")
    return r


def _lars_candidates(enum):
    """The terms of q-norm degree LARS_DEGREE, at most MAX_TERMS, counted degree by degree (the
    enumeration of a high degree in many dimensions takes seconds)."""
    size = 0
    for p in range(1, LARS_DEGREE + 1):
        size = _size(enum, p) or size
        if size >= MAX_TERMS:
            return MAX_TERMS
    return size


def _size(enum, p):
    """The basis size up to total degree p; None when the factors' degree caps leave no term
    of degree p (OpenTURNS then refuses to enumerate that far)."""
    try:
        return enum.getBasisSizeFromTotalDegree(p)
    except RuntimeError:
        return None


def _fit(design, z, y, method):
    """The chaos of y over the variables z: least squares (numpy, on the basis's own design
    matrix) or OpenTURNS's LARS."""
    if method != "lars":
        r = _choose_degree(design, z, y)
        return r if r is not None else {
            "skipped": f"{len(y)} points are too few for a basis of total degree 1 (it needs 3 "
                       "points a term), or they leave it singular (a factor drawn at one value "
                       "only) or interpolated"}
    basis = _basis(design)
    size = _lars_candidates(basis.enum)
    proj = ot.LeastSquaresStrategy(ot.LeastSquaresMetaModelSelectionFactory(
        ot.LARS(), ot.CorrectedLeaveOneOut()))
    u = ot.Sample(basis.to_measure(z))
    result = _run(ot.FunctionalChaosAlgorithm(u, ot.Sample(y.reshape(-1, 1)),
                                              basis.openturns.getMeasure(),
                                              ot.FixedStrategy(basis.openturns, size), proj))
    psi = np.column_stack([np.asarray(f(u)).ravel() for f in result.getReducedBasis()])
    q2, pred = loo(psi, y)
    alpha = np.array([list(basis.enum(int(i))) for i in result.getIndices()], dtype=int)
    return _summary("lars", alpha, np.asarray(result.getCoefficients()).ravel(), y,
                    np.asarray(result.getMetaModel()(u)).ravel(), q2, pred,
                    kfold(np.linalg.qr(psi)[0], y, _folds(len(y)))[0], size)


def _summary(method, alpha, coef, y, fitted, q2, pred, q2_kfold, candidates):
    """The dict of a fitted chaos: terms alpha (multi-indices) with coefficients coef on an
    orthonormal basis, so its variance is the sum of the squared coefficients but the
    constant's, a factor's first-order index the share of the terms in it alone, its total
    index that of the terms in it at all."""
    ss = float(np.sum((y - y.mean()) ** 2))
    sq = coef ** 2 * (alpha.sum(axis=1) > 0)
    v = float(sq.sum())
    d = alpha.shape[1]
    alone = [(alpha[:, i] > 0) & (alpha.sum(axis=1) == alpha[:, i]) for i in range(d)]
    return {"method": method, "candidate_terms": int(candidates), "terms": len(coef),
            "degree": int(alpha.sum(axis=1).max()), "q2_loo": q2, "q2_kfold": q2_kfold,
            "folds": FOLDS, "r2": 1 - float(np.sum((y - fitted) ** 2)) / ss if ss > 0 else
            math.nan, "loo_prediction": pred,
            "first_order": [float(sq[alone[i]].sum()) / v if v > 0 else math.nan
                            for i in range(d)],
            "total": [float(sq[alpha[:, i] > 0].sum()) / v if v > 0 else math.nan
                      for i in range(d)],
            "points": len(y), "_variance": _variances(v, fitted)}


def _variances(v_coef, fitted):
    """The chaos's variance under the factors' distribution (v_coef), its variance over the
    points, and that estimate's standard error sqrt((m4 - v²) / n)."""
    dev = fitted - fitted.mean()
    v = float(np.mean(dev ** 2))
    m4 = float(np.mean(dev ** 4))
    return {"coefficients": v_coef, "points": v,
            "standard_error": math.sqrt(max(m4 - v * v, 0.0) / len(fitted))}


def _run(algo):
    """Runs OpenTURNS's chaos algorithm (LARS) with its least squares solved by the normal
    equations (Cholesky), five times faster than OpenTURNS's default SVD at 1e4 points and well
    conditioned here: the basis is orthonormal for the factors' distribution, so the normal
    matrix is close to n times the identity."""
    key = "PenalizedLeastSquaresAlgorithm-UseNormal"
    before = ot.ResourceMap.GetAsBool(key)
    ot.ResourceMap.SetAsBool(key, True)
    try:
        algo.run()
    finally:
        ot.ResourceMap.SetAsBool(key, before)
    return algo.getResult()
