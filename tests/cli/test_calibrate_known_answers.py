"""rodend calibrate's known answers (docs/health-monitoring.md#known-answer-tests): synthetic
records made by rodend itself from a hidden clearance and friction plus Gaussian noise, one
surrogate trained once (tests/cli/calibrate/known-answer.json: the free-play ground test,
64 training and 16 held-out cases) and the posterior sampled for each record.

1. Coverage: over 20 noise seeds the clearance's 90 % credible interval holds the truth in at
   least 16 (a calibrated 90 % interval holds it in 18 on average; P(fewer than 16 of 20 | p =
   0.9) = 4.3 %, the binomial tail), and so does the friction's.
2. The interval narrows as the noise falls: at noise std 3e-4 and 3e-5 rad its width is
   within 25 % of the width at 1e-4 scaled in proportion to the noise (the posterior of a
   quantity the response depends on smoothly is Gaussian with std proportional to the
   noise's; 25 % covers
   the quantile estimates' error at ESS >= 400, a few %, and the surrogate's held-out error,
   added to the noise's variance, 0.3 % of it).
3. An unknown that does not enter the response (wear.ball_coefficient with the wear model
   none: nothing reads it) keeps its prior: posterior std within 15 % of the prior's (the
   standard error of a std estimated from ESS >= 400 draws of a uniform is
   sqrt((kurtosis - 1) / (4 ESS)) = 2.2 %; 15 % is more than 6 of them) and the statement
   says "not identifiable".
"""
import os
import sys
import tempfile

import numpy as np

from common import check, finish

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "python"))
from rodend.calibration import config, forward, noise, posterior, run  # noqa: E402

TRUTH = {"parameters.contact.clearance": 2.3e-4,
         "parameters.friction.dynamic_coefficient": 0.08,
         "parameters.wear.ball_coefficient": 5e-7}
SEEDS = range(1, 21)


def setup(tmp):
    cfg = config.load(os.path.join(HERE, "calibrate", "known-answer.json"))
    end, dt = cfg["study"]["time"]["end"], cfg["study"]["time"]["sample_interval"]
    times = np.arange(int(round(end / dt)) + 1) * dt
    exact = forward.single_run(cfg, tmp, "truth", TRUTH, times)[0]
    path = os.path.join(tmp, "record.csv")
    noise.write_csv(path, times, [("surface_angle", "rad", exact)], ["exact, no noise"])
    cfg["record"]["path"] = path
    rec = run.read_record(cfg)
    sur, heldout, info = run.train(cfg, rec, tmp)
    print(f"surrogate: {info}")
    return cfg, rec, sur, heldout, np.interp(rec["feature_times"], times, exact)


def estimate(cfg, rec, sur, heldout, exact, std, seed):
    cfg["compare"][0]["noise_std"] = std
    rec["observed"] = noise.measured(exact, std, seed)[None, :]
    _, chains, diag, _ = run.infer(cfg, rec, sur, heldout)
    keys = [u["key"] for u in cfg["unknowns"]]
    out, _ = posterior.summary(chains.reshape(-1, len(keys)), run.prior_of(cfg), keys,
                               cfg["checks"]["prior_like_ratio"])
    check(max(diag["rhat"]) < 1.05 and min(diag["ess"]) >= 400,
          f"seed {seed}: chains not converged: {diag}")
    return out


def main():
    with tempfile.TemporaryDirectory() as tmp:
        cfg, rec, sur, heldout, exact = setup(tmp)
        check(np.sqrt(np.mean(heldout ** 2)) < 0.2 * 1e-4,
              f"surrogate's held-out RMS {np.sqrt(np.mean(heldout ** 2))} rad above 0.2 of the noise std (it adds its square to the noise variance: 4 %)")
        hits, widths, ratios = np.zeros(2, int), [], []
        for seed in SEEDS:
            out = estimate(cfg, rec, sur, heldout, exact, 1e-4, seed)
            for i in range(2):
                lo, hi = out[i]["interval90"]
                hits[i] += lo <= TRUTH[out[i]["key"]] <= hi
            widths.append(out[0]["q95"] - out[0]["q05"])
            ratios.append(out[2]["std_ratio"])
            check("not identifiable" in out[2]["identifiability"],
                  f"seed {seed}: {out[2]['identifiability']}")
        print(f"coverage of the 90 % intervals over {len(SEEDS)} seeds: clearance {hits[0]}, "
              f"friction {hits[1]}; clearance interval width {np.mean(widths):.3e} m; "
              f"non-entering unknown's posterior/prior std {min(ratios):.3f}-{max(ratios):.3f}")
        check(hits[0] >= 16, f"clearance's interval held the truth in {hits[0]} of 20 seeds")
        check(hits[1] >= 16, f"friction's interval held the truth in {hits[1]} of 20 seeds")
        check(all(0.85 <= r <= 1.15 for r in ratios), f"non-entering unknown's std ratios "
              f"{ratios}: expected within 15 % of its prior's")
        narrowing(cfg, rec, sur, heldout, exact, np.mean(widths))
    finish("calibrate known answers")


def narrowing(cfg, rec, sur, heldout, exact, width_1e4):
    w = {}
    for std in (3e-4, 3e-5):
        w[std] = estimate(cfg, rec, sur, heldout, exact, std, 99)[0]
        w[std] = w[std]["q95"] - w[std]["q05"]
    print(f"clearance's 90 % interval width: {w[3e-4]:.3e} m at noise 3e-4 rad, "
          f"{width_1e4:.3e} at 1e-4 (mean of 20 seeds), {w[3e-5]:.3e} at 3e-5")
    for std, wd in w.items():
        expected = width_1e4 * std / 1e-4
        check(abs(wd / expected - 1) < 0.25, f"width {wd:.3e} m at noise {std}: expected "
              f"{expected:.3e} m (proportional to the noise) within 25 %")


if __name__ == "__main__":
    main()
