"""The surrogate of the forward model: the compared signals at the feature times, reduced to
their principal components, each component a polynomial chaos in the unknowns (OpenTURNS
FunctionalChaosAlgorithm on the basis orthonormal for each prior marginal, reached by the
isoprobabilistic transformation OpenTURNS builds from the prior; coefficients by least squares,
the degree by the exact leave-one-out error). Its accuracy is then measured on held-out cases
(a second design the fit never saw): the RMS error per feature enters the likelihood."""
import numpy as np
import openturns as ot

MAX_DEGREE = 8
# principal components kept: those above this share of the training outputs' variance (the
# discarded rest is part of the held-out error, which the likelihood carries)
PCA_SHARE = 1e-9


def _basis(prior):
    factories = [ot.StandardDistributionPolynomialFactory(prior.getMarginal(i))
                 for i in range(prior.getDimension())]
    return ot.OrthogonalProductPolynomialFactory(
        factories, ot.LinearEnumerateFunction(prior.getDimension()))


def _fit(x, z, prior, degree):
    basis = _basis(prior)
    p = basis.getEnumerateFunction().getStrataCumulatedCardinal(degree)
    algo = ot.FunctionalChaosAlgorithm(ot.Sample(x), ot.Sample(z), prior,
                                       ot.FixedStrategy(basis, p), ot.LeastSquaresStrategy())
    algo.run()
    return algo.getResult(), p


def _loo(result, x, z):
    """The exact leave-one-out residuals of a least-squares chaos (hat matrix by QR)."""
    u = np.array(result.getTransformation()(ot.Sample(x)))
    funcs = result.getReducedBasis()
    psi = np.column_stack([np.array(f(ot.Sample(u))).ravel() for f in funcs])
    q, _ = np.linalg.qr(psi)
    h = np.sum(q * q, axis=1)
    fit = np.array(result.getMetaModel()(ot.Sample(x)))
    return (z - fit) / np.maximum(1.0 - h, 1e-12)[:, None]


class Surrogate:
    """y(x) ≈ mean + chaos(x) @ components, for y the flattened compared features."""

    def __init__(self, x, y, prior, max_degree=0):
        n = len(x)
        self.mean = y.mean(axis=0)
        u, s, vt = np.linalg.svd(y - self.mean, full_matrices=False)
        share = s ** 2 / max(np.sum(s ** 2), 1e-300)
        r = max(1, int(np.sum(share > PCA_SHARE)))
        self.components = vt[:r]
        z = (y - self.mean) @ self.components.T
        best = None
        top = max_degree or MAX_DEGREE
        for degree in range(1, top + 1):
            result, p = _fit(x, z, prior, degree)
            if p > 0.75 * n:
                break
            err = float(np.sum(_loo(result, x, z) ** 2))
            if best is None or err < best[0]:
                best = (err, degree, result, p)
        _, self.degree, self.result, self.terms = best
        self.model = self.result.getMetaModel()
        self.loo_q2 = 1.0 - best[0] / max(float(np.sum((z - z.mean(axis=0)) ** 2)), 1e-300)
        self.rank = r

    def __call__(self, x):
        x = np.atleast_2d(x)
        z = np.array(self.model(ot.Sample(x)))
        return self.mean + z @ self.components

    def validate(self, x, y):
        """Held-out check: the error per feature on cases the fit never saw."""
        e = self(x) - y
        return {"rms_per_feature": np.sqrt(np.mean(e ** 2, axis=0)),
                "max_abs": float(np.max(np.abs(e))), "cases": int(len(x))}
