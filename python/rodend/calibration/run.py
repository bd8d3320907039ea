"""`rodend calibrate CONFIG.json`: from a measured record back to the unknowns
(docs/health-monitoring.md#calibration). One function per step; `calibrate` runs them.

Exit codes: 0 the estimate passed every check; 2 a bad input (the configuration or the record:
the message names the file and the key or column); 1 a failed diagnostic (the surrogate's
held-out error, the chains' convergence, a prior that excludes what the data allow): the
message says which, and the results folder, complete, records it."""
import os
import subprocess
import sys
import time

import numpy as np

from ..analysis import distributions
from . import config as _config
from . import figures, forward, noise, output, posterior, record
from .surrogate import Surrogate


class DiagnosticFailed(RuntimeError):
    """A check of the calibration failed (exit 1); the message says which."""


def signal_units(names):
    """{signal: unit} from the rodend executable's catalogue (`rodend signals`)."""
    r = subprocess.run([forward.rodend_executable(), "signals"], capture_output=True,
                       text=True)
    units = {}
    for line in r.stdout.splitlines():
        parts = line.split()
        if len(parts) >= 3 and parts[0] in names:
            units[parts[0]] = (parts[1].strip("[]"), parts[2].rstrip(":"))
    return units


def read_record(cfg):
    """The record, checked, and the features: the record's samples in the window (every k-th,
    at most cfg["points"]) of each compared column, flattened column by column."""
    path = cfg["record"]["path"]
    units = signal_units({c["signal"] for c in cfg["compare"]})
    for i, c in enumerate(cfg["compare"]):
        if c["signal"] not in units:
            raise _config.ConfigError(f"{cfg['file']}: compare[{i}].signal: unknown signal "
                                      f"'{c['signal']}' (rodend signals lists them)")
        if units[c["signal"]][1] != "x1":
            raise _config.ConfigError(f"{cfg['file']}: compare[{i}].signal: '{c['signal']}' "
                                      f"has {units[c['signal']][1][1:]} components; expected "
                                      "a scalar signal")
    units = {k: u for k, (u, _) in units.items()}
    cols = {c["column"]: units[c["signal"]] for c in cfg["compare"]}
    rec = record.read(path, cols, cfg["record"]["time_column"])
    w = cfg["window"]
    record.check_covers(path, rec, w["start"], w["end"], cfg["record"]["time_column"])
    t = rec["time"]
    inside = np.flatnonzero((t >= w["start"] - 1e-9) & (t <= w["end"] + 1e-9))
    stride = max(1, int(np.ceil(len(inside) / cfg["points"])))
    idx = inside[::stride]
    rec["feature_times"] = t[idx]
    rec["observed"] = np.array([rec[c["column"]][idx] for c in cfg["compare"]])
    rec["units"] = [units[c["signal"]] for c in cfg["compare"]]
    return rec


def prior_of(cfg):
    """The unknowns' priors as one OpenTURNS distribution (each its design-block marginal);
    a malformed prior is refused by rodend's own design check first (check_study)."""
    return distributions.joint({"factors": cfg["unknowns"]})


def check_study(cfg, scratch):
    """rodend's loader on the training study (dry run): a bad study, key or prior is refused
    here, with the configuration's key paths in the message."""
    doc = forward.study_document(cfg, "check", design={
        "method": cfg["surrogate"]["method"], "size": cfg["surrogate"]["cases"],
        "seed": cfg["surrogate"]["seed"]})
    try:
        forward.run_study(doc, scratch, dry_run=True)
    except forward.ForwardError as e:
        msg = str(e.args[1])
        tmp = os.path.join(scratch, "check.json")
        msg = msg.replace(tmp, cfg["file"]).replace("design.factors[", "unknowns[")
        for a, b in (("design.size", "surrogate.cases"), ("design.seed", "surrogate.seed"),
                     ("design.method", "surrogate.method")):
            msg = msg.replace(a, b)
        for k in ("parameters", "integrator", "time", "scene", "signals"):
            msg = msg.replace(f": {k}", f": study.{k}", 1) if f": {k}" in msg else msg
        raise _config.ConfigError(msg) from None


def train(cfg, rec, scratch):
    """The training and held-out designed studies, the surrogate and its held-out check."""
    s, t0 = cfg["surrogate"], time.monotonic()
    x, y, failed = forward.designed_outputs(cfg, scratch, "training", s["method"], s["cases"],
                                            s["seed"], rec["feature_times"])
    xv, yv, failed_v = forward.designed_outputs(cfg, scratch, "heldout", "monte-carlo",
                                                s["validation_cases"], s["seed"] + 7919,
                                                rec["feature_times"])
    t_runs = time.monotonic() - t0
    prior = prior_of(cfg)
    sur = Surrogate(x, y.reshape(len(y), -1), prior, int(s["degree"]))
    check = sur.validate(xv, yv.reshape(len(yv), -1))
    sigma = noise.feature_std(cfg, rec)
    ratio = float(np.sqrt(np.mean((check["rms_per_feature"] / sigma) ** 2)))
    info = {"training_cases": int(len(x)), "validation_cases": int(len(xv)),
            "failed_cases": failed + failed_v, "degree": sur.degree, "terms": sur.terms,
            "components": sur.rank, "loo_q2": sur.loo_q2, "heldout_max_abs": check["max_abs"],
            "heldout_error_over_noise": ratio, "run_seconds": t_runs,
            "fit_seconds": time.monotonic() - t0 - t_runs}
    return sur, check["rms_per_feature"], info


def infer(cfg, rec, sur, heldout_rms):
    """The posterior by MCMC on the surrogate, with its convergence diagnostics."""
    prior = prior_of(cfg)
    sigma = noise.feature_std(cfg, rec)
    lp = posterior.LogPosterior(prior, sur, rec["observed"].ravel(),
                                sigma ** 2 + heldout_rms ** 2)
    m = cfg["mcmc"]
    x_mode = posterior.mode(lp, prior, m["seed"])
    cov = posterior.laplace_covariance(lp, x_mode, prior)
    chains, rates = posterior.sample(lp, prior, x_mode, cov, m["chains"], m["samples"],
                                     m["burn_in"], m["seed"])
    diag = {"rhat": posterior.split_rhat(chains), "ess": posterior.ess(chains),
            "acceptance": rates, "log_posterior_calls": lp.calls}
    return x_mode, chains, diag, lp


def final_run(cfg, rec, x_mode, scratch):
    """The full model at the posterior mode; its residual over the noise (RMS of r_j/σ_j:
    about 1 when the model at the mode explains the record down to its noise)."""
    keys = [u["key"] for u in cfg["unknowns"]]
    y = forward.single_run(cfg, scratch, "mode", dict(zip(keys, map(float, x_mode))),
                           rec["feature_times"])
    sigma = noise.feature_std(cfg, rec)
    r = (y.ravel() - rec["observed"].ravel()) / sigma
    return y, float(np.sqrt(np.mean(r ** 2)))


def predictive_band(sur, flat, cfg, rec, draws=400, seed=0):
    """The 5/50/95 % of the posterior predictive at each feature: the surrogate at posterior
    draws plus the noise."""
    rng = np.random.default_rng(seed)
    pick = flat[rng.choice(len(flat), size=min(draws, len(flat)), replace=False)]
    y = sur(pick) + rng.normal(0.0, 1.0, (len(pick), sur.mean.size)) * noise.feature_std(cfg, rec)
    q = np.quantile(y, [0.05, 0.5, 0.95], axis=0)
    return q.reshape(3, len(cfg["compare"]), -1)


def problems(cfg, doc, flat, prior):
    """The checks of an honest answer, each failure a sentence naming what failed: a
    prior-data conflict first (it makes the others moot), then the chains, then the
    surrogate."""
    c, d, out = cfg["checks"], doc["diagnostics"], []
    keys = [u["key"] for u in cfg["unknowns"]]
    for k, side, post, pm in posterior.bound_piling(flat, prior, keys, c["bound_mass"]):
        i = keys.index(k)
        out.append(f"prior-data conflict: {post:.0%} of the posterior of {k} lies at its "
                   f"prior's {side} bound (unknowns[{i}], prior mass there {pm:.1%}): the prior"
                   " may exclude the values the data allow; widen it")
    r = doc["final_run"]["residual_over_noise"]
    if r > c["max_residual_ratio"]:
        out.append(f"prior-data conflict: the full model at the posterior mode misses the record"
                   f" by {r:.2f} times the noise std (RMS) > {c['max_residual_ratio']} "
                   "(checks.max_residual_ratio): no value within the priors explains the "
                   "record (a prior that excludes the truth, or a model or noise model that "
                   "does not fit)")
    for i, k in enumerate(keys):
        if d["rhat"][i] > c["max_rhat"]:
            out.append(f"not converged: split R-hat of {k} is {d['rhat'][i]:.3f} > "
                       f"{c['max_rhat']} (checks.max_rhat): run longer chains (mcmc.samples)")
        if d["ess"][i] < c["min_ess"]:
            out.append(f"not converged: effective sample size of {k} is {d['ess'][i]:.0f} < "
                       f"{c['min_ess']:.0f} (checks.min_ess): run longer chains "
                       "(mcmc.samples)")
    for j, a in enumerate(d["acceptance"]):
        if not c["min_acceptance"] <= a <= c["max_acceptance"]:
            out.append(f"not converged: chain {j} accepted {a:.3f} of its proposals, outside "
                       f"[{c['min_acceptance']}, {c['max_acceptance']}] (checks.min_acceptance,"
                       " checks.max_acceptance)")
    s = doc["surrogate"]["heldout_error_over_noise"]
    if s > c["max_surrogate_error"]:
        out.append(f"surrogate too coarse: its RMS error on the held-out cases is {s:.3f} times"
                   f" the noise std > {c['max_surrogate_error']} (checks.max_surrogate_error):"
                   " train on more cases (surrogate.cases) or narrow the priors")
    return out


def _document(cfg, rec, sur_info, x_mode, chains, diag, final_rms, prior):
    keys = [u["key"] for u in cfg["unknowns"]]
    flat = chains.reshape(-1, chains.shape[2])
    unknowns, corr = posterior.summary(flat, prior, keys, cfg["checks"]["prior_like_ratio"])
    return {"name": cfg["name"], "config": os.path.abspath(cfg["file"]),
            "rodend": forward.version(),
            "record": {"file": cfg["record"]["file"],
                       "path": os.path.abspath(cfg["record"]["path"]),
                       "sha256": rec["sha256"], "bytes": rec["bytes"],
                       "samples": int(len(rec["time"])), "step_s": rec["step"],
                       "features": int(rec["observed"].size), "window": cfg["window"]},
            "compare": cfg["compare"], "priors": cfg["unknowns"], "surrogate": sur_info,
            "mcmc": cfg["mcmc"], "checks": cfg["checks"],
            "posterior": {"unknowns": unknowns, "mode": dict(zip(keys, x_mode)),
                          "correlation": corr, "samples": int(len(flat))},
            "diagnostics": diag, "final_run": {"values": dict(zip(keys, x_mode)),
                                               "residual_over_noise": final_rms}}


def _write(cfg, doc, chains, rec, band, final, prior, prog):
    keys = [u["key"] for u in cfg["unknowns"]]
    flat = chains.reshape(-1, chains.shape[2])
    with output.ResultsFolder(cfg["output"]) as out:
        out.write_text("posterior.csv", output.samples_csv(keys, chains))
        figures.fit(out.path("calibration-fit.png"), rec["feature_times"], cfg["compare"],
                    rec["observed"], band, final, rec["units"])
        figures.posteriors(out.path("calibration-posterior.png"), flat, prior, keys)
        cycles = prog.pop("_cycles") if prog is not None else []
        if len(cycles):
            figures.prognosis(out.path("prognosis.png"), cycles,
                              f"{prog['limit_name']} = {prog['limit']:.4g} {prog['unit']}",
                              prog["cycle_name"])
        out.write_json("calibration.json", doc)


def calibrate(path, quiet=False):
    """Runs the calibration of the configuration file `path`; returns (exit code, document).
    Raises ConfigError / RecordError (bad input) before anything is written."""
    t0 = time.monotonic()
    cfg = _config.load(path)
    rec = read_record(cfg)
    with forward.Scratch() as scratch:
        check_study(cfg, scratch)
        prior = prior_of(cfg)
        sur, heldout, sur_info = train(cfg, rec, scratch)
        t1 = time.monotonic()
        x_mode, chains, diag, _ = infer(cfg, rec, sur, heldout)
        t2 = time.monotonic()
        final, final_rms = final_run(cfg, rec, x_mode, scratch)
        doc = _document(cfg, rec, sur_info, x_mode, chains, diag, final_rms, prior)
        flat = chains.reshape(-1, chains.shape[2])
        doc["problems"] = problems(cfg, doc, flat, prior)
        prog = None
        if cfg["prognosis"] is not None:
            from . import prognosis
            prog = prognosis.run(cfg, flat, scratch)
            doc["prognosis"] = {k: v for k, v in prog.items() if not k.startswith("_")}
            if "problem" in prog:
                doc["problems"].append("prognosis: " + prog["problem"])
    doc["status"] = "ok" if not doc["problems"] else "failed: " + doc["problems"][0]
    doc["seconds"] = {"total": time.monotonic() - t0, "mcmc": t2 - t1,
                      "training_runs": sur_info["run_seconds"]}
    band = predictive_band(sur, flat, cfg, rec)
    _write(cfg, doc, chains, rec, band, final, prior, prog)
    if not quiet:
        print(output.table(doc))
        print(f"  results in {cfg['output']} ({doc['seconds']['total']:.0f} s)")
    return (0 if not doc["problems"] else 1), doc


def main(argv=None):
    import argparse
    p = argparse.ArgumentParser(prog="rodend calibrate", description=__doc__.split("\n\n")[0])
    p.add_argument("config", help="the calibration's configuration (JSON)")
    p.add_argument("-q", "--quiet", action="store_true", help="print nothing but errors")
    a = p.parse_args(argv)
    try:
        rc, doc = calibrate(a.config, a.quiet)
    except (_config.ConfigError, record.RecordError) as e:
        print(f"rodend calibrate: error: {e}", file=sys.stderr)
        return 2
    except forward.ForwardError as e:
        print(f"rodend calibrate: error: {a.config}: the test's runs failed: {e.args[1]}",
              file=sys.stderr)
        return 1
    for m in doc["problems"]:
        print(f"rodend calibrate: {a.config}: {m}", file=sys.stderr)
    return rc
