"""The calibration's figures: the record over the posterior predictive band, the posteriors
against their priors, and the prognosis's distribution of cycles to the limit."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def fit(path, times, compare, observed, band, final, units):
    """observed, final: (columns, times); band: (3, columns, times) the 5/50/95 % of the
    posterior predictive (the surrogate at posterior draws plus the noise). Per column, the
    record over the band, and below it the same less the band's median (the band is often
    thinner than the line at the signal's scale)."""
    n = len(compare)
    fig, axes = plt.subplots(2 * n, 1, figsize=(8, 5.5 * n), squeeze=False)
    for k, c in enumerate(compare):
        for row, less in ((2 * k, 0.0), (2 * k + 1, band[1, k])):
            ax = axes[row, 0]
            ax.fill_between(times, band[0, k] - less, band[2, k] - less, color="C0",
                            alpha=0.3, label="posterior predictive 5-95 %")
            ax.plot(times, band[1, k] - less, color="C0", lw=1,
                    label="posterior predictive median")
            ax.plot(times, observed[k] - less, ".", ms=2, color="k",
                    label=f"record ({c['column']})")
            if final is not None:
                ax.plot(times, final[k] - less, color="C3", lw=0.8,
                        label="full model at the mode")
            ax.set_xlabel("time [s]")
            what = c["signal"] if row == 2 * k else c["signal"] + " less the median"
            ax.set_ylabel(f"{what} [{units[k]}]")
            ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def posteriors(path, flat, prior, keys, truth=None):
    d = len(keys)
    fig, axes = plt.subplots(1, d, figsize=(4 * d, 3.2), squeeze=False)
    for i, k in enumerate(keys):
        ax = axes[0, i]
        m = prior.getMarginal(i)
        lo, hi = m.getRange().getLowerBound()[0], m.getRange().getUpperBound()[0]
        lo = max(lo, float(m.computeQuantile(1e-4)[0]))
        hi = min(hi, float(m.computeQuantile(1 - 1e-4)[0]))
        ps = float(m.getStandardDeviation()[0])
        sd = max(flat[:, i].std(), 1e-3 * ps)  # a chain stuck on one value: still a range
        if sd < 0.2 * ps:  # zoom on a narrow posterior
            lo = max(lo, flat[:, i].min() - 2 * sd)
            hi = min(hi, flat[:, i].max() + 2 * sd)
            ax.set_title("zoomed on the posterior", fontsize=8)
        x = np.linspace(lo, hi, 400)
        ax.hist(flat[:, i], bins=60, range=(lo, hi), density=True, color="C0", alpha=0.6,
                label="posterior")
        ax.plot(x, [m.computePDF(v) for v in x], color="k", lw=1, label="prior")
        q5, q95 = np.quantile(flat[:, i], [0.05, 0.95])
        ax.axvspan(q5, q95, color="C1", alpha=0.15, label="90 % interval")
        if truth is not None:
            ax.axvline(truth[i], color="C3", label="truth")
        ax.set_xlabel(k)
        ax.locator_params(axis="x", nbins=4)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def prognosis(path, cycles, limit_text, cycle_name):
    fig, ax = plt.subplots(figsize=(6, 3.5))
    ax.hist(cycles, bins=60, density=True, color="C2", alpha=0.7)
    for q, ls in ((0.05, ":"), (0.5, "-"), (0.95, ":")):
        v = np.quantile(cycles, q)
        ax.axvline(v, color="k", ls=ls, lw=1, label=f"{q:.0%}: {v:.3g}")
    ax.set_xlabel(f"{cycle_name} until {limit_text}")
    ax.set_ylabel("density")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
