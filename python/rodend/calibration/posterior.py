"""The posterior of the unknowns: the priors (the design block's distributions, as OpenTURNS
distributions) times a Gaussian likelihood of the record's features given the surrogate,
sampled by OpenTURNS's RandomWalkMetropolisHastings in several chains, with the checks that
make it honest: split R-hat, effective sample size, acceptance rate."""
import math

import numpy as np
import openturns as ot
from scipy import optimize


class LogPosterior:
    """log p(θ | data) up to a constant: the prior's log-density plus
    −½ Σ_j (y_j − f_j(θ))² / v_j, v_j the noise variance plus the surrogate's held-out error
    variance at feature j."""

    def __init__(self, prior, surrogate, observed, variance):
        self.prior, self.f = prior, surrogate
        self.y, self.v = observed, variance
        self.calls = 0
        rng = prior.getRange()
        self.lo = np.array(rng.getLowerBound())
        self.hi = np.array(rng.getUpperBound())

    def loglik(self, x):
        r = self.f(x) - self.y
        return -0.5 * np.sum(r * r / self.v, axis=1)

    def __call__(self, x):
        x = np.atleast_2d(x)
        lp = np.array(self.prior.computeLogPDF(ot.Sample(x))).ravel()
        out = np.full(len(x), -np.inf)
        # outside the support OpenTURNS gives the lowest double, not -inf
        ok = np.isfinite(lp) & (lp > -1e300) & np.all((x >= self.lo) & (x <= self.hi), axis=1)
        if ok.any():
            out[ok] = lp[ok] + self.loglik(x[ok])
        self.calls += len(x)
        return out


def mode(logpost, prior, seed, starts=4000):
    """The posterior mode (on the surrogate): the best of `starts` prior draws, polished by
    Nelder-Mead in coordinates scaled by the prior's standard deviations."""
    ot.RandomGenerator.SetSeed(int(seed))
    draws = np.array(prior.getSample(starts))
    lp = logpost(draws)
    scale = np.array(prior.getStandardDeviation())
    best = None
    for x0 in draws[np.argsort(-lp)[:3]]:
        r = optimize.minimize(lambda u: -logpost(u * scale)[0], x0 / scale,
                              method="Nelder-Mead",
                              options={"xatol": 1e-6, "fatol": 1e-6, "maxiter": 4000})
        if best is None or r.fun < best.fun:
            best = r
    return best.x * scale


def _hessian(logpost, x, h, f0, hess):
    d = len(x)
    for i in range(d):
        for j in range(i, d):
            ei, ej = np.eye(d)[i] * h[i], np.eye(d)[j] * h[j]
            if i == j:
                v = (logpost(x + ei)[0] - 2 * f0 + logpost(x - ei)[0]) / h[i] ** 2
            else:
                v = (logpost(x + ei + ej)[0] - logpost(x + ei - ej)[0] -
                     logpost(x - ei + ej)[0] + logpost(x - ei - ej)[0]) / (4 * h[i] * h[j])
            hess[i, j] = hess[j, i] = v


def laplace_covariance(logpost, x, prior):
    """The covariance of a Gaussian approximation at the mode: (−H + P)⁻¹, H the Hessian of
    log p by central differences, P the prior's precision (1/variance of each marginal). P
    keeps an unknown the data do not constrain (H ≈ 0 along it) at its prior's spread instead
    of an infinite or arbitrary one; it is only the proposal's shape, never the answer."""
    ps = np.array(prior.getStandardDeviation())
    h = ps * 1e-3
    f0 = logpost(x)[0]
    hess = np.zeros((len(x), len(x)))
    with np.errstate(invalid="ignore", over="ignore"):  # a step beyond the support: -inf
        _hessian(logpost, x, h, f0, hess)
    try:
        a = np.where(np.isfinite(-hess), -hess, 0.0) + np.diag(1.0 / ps ** 2)
        w, v = np.linalg.eigh(a)
        w = np.maximum(w, 1.0 / np.max(ps ** 2))  # a saddle's negative curvature: the prior's
        return (v / w) @ v.T
    except np.linalg.LinAlgError:
        return np.diag((ps / 10) ** 2)


def _limit_to_prior(cov, prior):
    """No proposal wider than the prior itself (an unidentified unknown's Laplace variance is
    huge or undefined)."""
    s = np.sqrt(np.diag(cov))
    cap = np.minimum(s, np.array(prior.getStandardDeviation()))
    corr = cov / np.outer(s, s)
    return corr * np.outer(cap, cap)


def _chain(logpost, prior, x0, cov, samples, burn_in, seed):
    d = len(x0)
    proposal = ot.Normal([0.0] * d, ot.CovarianceMatrix((2.38 ** 2 / d * cov).tolist()))
    density = ot.PythonFunction(d, 1, lambda x: [float(logpost(np.array(x))[0])])
    ot.RandomGenerator.SetSeed(int(seed))
    mh = ot.RandomWalkMetropolisHastings(density, prior.getRange(), list(x0), proposal)
    mh.setBurnIn(int(burn_in))
    out = np.array(mh.getSample(int(samples)))
    rate = mh.getAcceptanceRate()
    return out, float(rate[0] if hasattr(rate, "__getitem__") else rate)


def _start(logpost, start, cov, rng):
    """A start displaced from the mode by a draw of twice the proposal's scale, inside the
    prior's support."""
    for _ in range(100):
        trial = start + rng.multivariate_normal(np.zeros(len(start)), 4 * cov)
        if np.isfinite(logpost(trial)[0]):
            return trial
    return start.copy()


def sample(logpost, prior, start, cov, chains, samples, burn_in, seed):
    """`chains` random-walk Metropolis-Hastings chains (OpenTURNS) with a Gaussian proposal of
    covariance 2.38²/d Σ (Gelman, Roberts & Gilks 1996). Σ: the covariance of a pilot chain
    (as long as the burn-in, at least 1000 steps, started at the mode with the Laplace
    covariance), then fixed, so the chains proper are plain Metropolis-Hastings. Each chain
    starts at a draw around the mode and discards its own burn-in. Returns (chains, samples,
    d) and each chain's acceptance rate."""
    d = len(start)
    cov = _limit_to_prior(cov, prior)
    pilot, _ = _chain(logpost, prior, start, cov, max(1000, int(burn_in)), 0, seed * 1000 + 999)
    pc = np.cov(pilot.T).reshape(d, d)
    if np.all(np.isfinite(pc)) and np.all(np.linalg.eigvalsh(pc) > 0):
        cov = _limit_to_prior(pc, prior)
    rng = np.random.default_rng(int(seed))
    out, rates = [], []
    for c in range(int(chains)):
        x, rate = _chain(logpost, prior, _start(logpost, start, cov, rng), cov, samples,
                         burn_in, int(seed) * 1000 + c)
        out.append(x)
        rates.append(rate)
    return np.array(out), rates


def split_rhat(chains):
    """Gelman-Rubin's potential scale reduction on split chains (Gelman et al., Bayesian Data
    Analysis, 3rd ed., §11.4), per unknown."""
    c, n, d = chains.shape
    half = n // 2
    parts = np.concatenate([chains[:, :half], chains[:, half:2 * half]], axis=0)
    m = parts.shape[1]
    means = parts.mean(axis=1)
    w = parts.var(axis=1, ddof=1).mean(axis=0)
    b = m * means.var(axis=0, ddof=1)
    var = (m - 1) / m * w + b / m
    return np.sqrt(var / np.maximum(w, 1e-300))


def ess(chains):
    """Effective sample size per unknown over all chains (BDA3 §11.5: autocorrelations from
    the between- and within-chain variances, summed in pairs until a pair's sum is negative,
    Geyer's initial positive sequence)."""
    c, n, d = chains.shape
    out = []
    for k in range(d):
        x = chains[:, :, k] - chains[:, :, k].mean(axis=1, keepdims=True)
        w = x.var(axis=1, ddof=1).mean()
        varp = (n - 1) / n * w + chains[:, :, k].mean(axis=1).var(ddof=1) if c > 1 else w
        if varp <= 0:
            out.append(float(c * n))
            continue
        f = np.fft.rfft(x, n=2 * n, axis=1)
        acov = np.fft.irfft(f * np.conj(f), axis=1)[:, :n] / n
        rho = 1.0 - (w - acov.mean(axis=0)) / varp
        s, t = 0.0, 1
        while t + 1 < n:
            pair = rho[t] + rho[t + 1]
            if pair < 0:
                break
            s += pair
            t += 2
        out.append(float(c * n / (1.0 + 2.0 * s)) if s > -0.5 else float(c * n))
    return np.array(out)


def summary(flat, prior, keys, like_ratio):
    """Mean, std, 5/50/95 %, the 90 % interval, the prior's std and the identifiability
    statement of each unknown, and the correlation matrix."""
    out = []
    for i, k in enumerate(keys):
        v = flat[:, i]
        q5, q50, q95 = np.quantile(v, [0.05, 0.5, 0.95])
        ps = float(prior.getMarginal(i).getStandardDeviation()[0])
        ratio = float(v.std(ddof=1)) / ps
        if ratio > like_ratio:
            say = (f"not identifiable from this record: its posterior std is {ratio:.0%} of "
                   "its prior's; the data hardly constrain it, the posterior is close to the "
                   "prior")
        elif ratio > 0.3:
            say = f"partly identified: posterior std {ratio:.0%} of the prior's"
        else:
            say = f"identified: posterior std {ratio:.1%} of the prior's"
        out.append({"key": k, "mean": float(v.mean()), "std": float(v.std(ddof=1)),
                    "q05": float(q5), "q50": float(q50), "q95": float(q95),
                    "interval90": [float(q5), float(q95)], "prior_std": ps,
                    "std_ratio": ratio, "identifiability": say})
    corr = np.corrcoef(flat.T) if flat.shape[1] > 1 else np.ones((1, 1))
    return out, np.atleast_2d(corr)


def bound_piling(flat, prior, keys, share):
    """Unknowns whose posterior piles at a bound of a bounded prior: more than `share` of the
    samples within 2 % of the prior's range of a bound, and at least 5 times the prior's mass
    there. Returns [(key, 'lower'|'upper', posterior mass, prior mass)]."""
    out = []
    rng = prior.getRange()
    lo, hi = np.array(rng.getLowerBound()), np.array(rng.getUpperBound())
    for i, k in enumerate(keys):
        m = prior.getMarginal(i)
        if not (math.isfinite(lo[i]) and math.isfinite(hi[i])):
            continue
        delta = 0.02 * (hi[i] - lo[i])
        for side, near, pmass in (
                ("lower", flat[:, i] < lo[i] + delta, m.computeCDF(lo[i] + delta)),
                ("upper", flat[:, i] > hi[i] - delta, 1.0 - m.computeCDF(hi[i] - delta))):
            post = float(np.mean(near))
            if post > share and post > 5 * pmass:
                out.append((k, side, post, float(pmass)))
    return out
