"""The calibration's configuration file (docs/health-monitoring.md#calibration), read and
checked: every error names the file and the key path and says what was expected."""
import json
import math
import os

TOP_KEYS = ("name", "description", "record", "study", "compare", "window", "points",
            "unknowns", "surrogate", "mcmc", "checks", "prognosis", "output")
DEFAULTS = {
    "points": 200,
    "surrogate": {"method": "latin-hypercube", "cases": 48, "validation_cases": 16, "seed": 1,
                  "degree": 0, "threads": 2},
    "mcmc": {"chains": 4, "samples": 4000, "burn_in": 1000, "seed": 1},
    # the convergence and honesty checks (why each value: docs/health-monitoring.md)
    "checks": {"max_rhat": 1.05, "min_ess": 400, "min_acceptance": 0.1, "max_acceptance": 0.9,
               "max_surrogate_error": 0.5, "max_residual_ratio": 1.5, "bound_mass": 0.05,
               "prior_like_ratio": 0.8},
}


class ConfigError(ValueError):
    """A bad configuration: the message names the file and the key path."""


def _fail(path, key, what):
    raise ConfigError(f"{path}: {key}: {what}")


def _number(path, key, v, lo=None, integer=False, positive=False):
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        _fail(path, key, f"expected a finite number, got {json.dumps(v)}")
    if integer and v != int(v):
        _fail(path, key, f"expected an integer, got {v}")
    if positive and not v > 0:
        _fail(path, key, f"expected a value > 0, got {v}")
    if lo is not None and v < lo:
        _fail(path, key, f"expected a value >= {lo}, got {v}")
    return int(v) if integer else float(v)


def _object(path, key, v, allowed):
    if not isinstance(v, dict):
        _fail(path, key, f"expected an object, got {type(v).__name__}")
    for k in v:
        if k not in allowed:
            _fail(path, f"{key}.{k}" if key else k,
                  "unknown key; expected one of " + ", ".join(f'"{a}"' for a in allowed))
    return v


def _merged(path, cfg, name, minimums):
    out = dict(DEFAULTS[name])
    given = _object(path, name, cfg.get(name, {}), list(out))
    for k, v in given.items():
        if isinstance(DEFAULTS[name][k], str):
            continue  # a choice, checked by the caller
        lo = minimums.get(k)
        out[k] = _number(path, f"{name}.{k}", v, lo=lo,
                         integer=isinstance(DEFAULTS[name][k], int))
    return out


def _record(path, cfg, folder):
    rec = _object(path, "record", cfg.get("record"), ["file", "time_column"]) \
        if "record" in cfg else _fail(path, "record", "missing: {\"file\": a CSV or HDF5 file}")
    f = rec.get("file")
    if not isinstance(f, str) or not f:
        _fail(path, "record.file", "expected the record's file name (CSV or HDF5)")
    tc = rec.get("time_column", "time")
    if not isinstance(tc, str) or not tc:
        _fail(path, "record.time_column", "expected a column name")
    return {"file": f, "path": f if os.path.isabs(f) else os.path.join(folder, f),
            "time_column": tc}


def _compare(path, cfg):
    cs = cfg.get("compare")
    if not isinstance(cs, list) or not cs:
        _fail(path, "compare", "expected a non-empty list of {\"column\", \"signal\", "
                               "\"noise_std\"}")
    out = []
    for i, c in enumerate(cs):
        key = f"compare[{i}]"
        _object(path, key, c, ["column", "signal", "noise_std"])
        for k in ("column", "signal"):
            if not isinstance(c.get(k), str) or not c[k]:
                _fail(path, f"{key}.{k}", "expected a name")
        if "noise_std" not in c:
            _fail(path, f"{key}.noise_std", "missing: the noise's standard deviation, in the "
                                            "signal's unit")
        out.append({"column": c["column"], "signal": c["signal"],
                    "noise_std": _number(path, f"{key}.noise_std", c["noise_std"],
                                         positive=True)})
    return out


def _unknowns(path, cfg):
    us = cfg.get("unknowns")
    if not isinstance(us, list) or not us:
        _fail(path, "unknowns", "expected a non-empty list of factors {\"key\", "
                                "\"distribution\", its parameters} (a design block's factors)")
    for i, u in enumerate(us):
        if not isinstance(u, dict) or not isinstance(u.get("key"), str):
            _fail(path, f"unknowns[{i}]", "expected {\"key\": a parameter key path, "
                                          "\"distribution\": ..., its parameters}")
        if u.get("distribution") == "discrete":
            _fail(path, f"unknowns[{i}].distribution", "a discrete prior is not supported; "
                  "expected uniform, normal, truncated-normal, lognormal or triangular")
    return us


def _study(path, cfg):
    s = _object(path, "study", cfg.get("study"), ["scene", "parameters", "integrator", "time",
                                                  "signals", "health", "metrics"]) \
        if "study" in cfg else _fail(path, "study", "missing: {\"scene\", \"parameters\", "
                                                    "\"time\", ...} of the test")
    if "time" not in s or not isinstance(s["time"], dict) or "end" not in s["time"]:
        _fail(path, "study.time", "missing: {\"end\": s, \"sample_interval\": s}")
    return s


def _window(path, cfg):
    w = _object(path, "window", cfg.get("window", {}), ["start", "end"])
    end = cfg["study"]["time"]["end"]
    start = _number(path, "window.start", w.get("start", 0.0), lo=0.0)
    stop = _number(path, "window.end", w.get("end", end), positive=True)
    if stop <= start:
        _fail(path, "window.end", f"expected an end after window.start ({start} s)")
    if isinstance(end, (int, float)) and stop > end:
        _fail(path, "window.end", f"expected a time within the test's run (study.time.end = "
                                  f"{end} s)")
    return {"start": start, "end": stop}


def load(path):
    """The configuration as a dict with every default filled in; raises ConfigError."""
    try:
        with open(path, encoding="utf-8") as fh:
            cfg = json.load(fh)
    except OSError as e:
        raise ConfigError(f"{path}: cannot read the configuration ({e.strerror})") from None
    except (json.JSONDecodeError, UnicodeDecodeError) as e:
        raise ConfigError(f"{path}: : JSON syntax error: {e}") from None
    _object(path, "", cfg, TOP_KEYS)
    folder = os.path.dirname(os.path.abspath(path))
    name = cfg.get("name", os.path.splitext(os.path.basename(path))[0])
    if not isinstance(name, str) or not name or "/" in name:
        _fail(path, "name", "expected a name without '/'")
    out = {"file": path, "folder": folder, "name": name,
           "description": cfg.get("description", ""), "record": _record(path, cfg, folder),
           "study": _study(path, cfg), "compare": _compare(path, cfg),
           "unknowns": _unknowns(path, cfg)}
    out["window"] = _window(path, cfg)
    out["points"] = _number(path, "points", cfg.get("points", DEFAULTS["points"]), lo=2,
                            integer=True)
    out["surrogate"] = _merged(path, cfg, "surrogate",
                               {"cases": 4, "validation_cases": 2, "seed": 0, "degree": 0,
                                "threads": 1})
    if cfg.get("surrogate", {}).get("method") is not None:
        m = cfg["surrogate"]["method"]
        if m not in ("latin-hypercube", "sobol", "monte-carlo"):
            _fail(path, "surrogate.method", f"unknown '{m}'; expected \"latin-hypercube\", "
                                            "\"sobol\" or \"monte-carlo\"")
    out["mcmc"] = _merged(path, cfg, "mcmc", {"chains": 2, "samples": 10, "burn_in": 0,
                                              "seed": 0})
    out["checks"] = _merged(path, cfg, "checks", {})
    out["prognosis"] = cfg.get("prognosis")
    if out["prognosis"] is not None:
        from .prognosis import check
        check(path, out["prognosis"], [u["key"] for u in out["unknowns"]])
    o = cfg.get("output", os.path.join("results", "calibrate-" + name))
    if not isinstance(o, str) or not o:
        _fail(path, "output", "expected a folder name")
    out["output"] = o
    return out
