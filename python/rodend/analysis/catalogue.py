"""The catalogues of the Python analysis, generated from sweep/design_methods.def,
sweep/distributions.def and sweep/case_record.def by scripts/analysis-catalogue.py
(`bash scripts/gen-docs.sh`); a test keeps it in step. Do not edit."""

# design.method -> sample: an independent sample of the distributions (a saltelli base,
# accepts design.correlation); distributions: the factors are distributions (not a file's
# points); points per grid point: size * (per_factor * factors + extra); the first
# iid_blocks * size points are an independent sample of the factors
DESIGN_METHODS = {
    "monte-carlo": {"distributions": True, "sample": True, "per_factor": 0, "extra": 1, "iid_blocks": 1,
        "description": 'independent random points'},
    "latin-hypercube": {"distributions": True, "sample": True, "per_factor": 0, "extra": 1, "iid_blocks": 1,
        "description": 'one point in each of N equal-probability strata of every factor'},
    "sobol": {"distributions": True, "sample": True, "per_factor": 0, "extra": 1, "iid_blocks": 1,
        "description": "Sobol' low-discrepancy points, randomly shifted by the seed"},
    "saltelli": {"distributions": True, "sample": False, "per_factor": 1, "extra": 2, "iid_blocks": 2,
        "description": "pick-freeze blocks A, B and A with column i from B: Sobol' indices, N (d + 2) points"},
    "morris": {"distributions": True, "sample": False, "per_factor": 1, "extra": 1, "iid_blocks": 0,
        "description": 'Morris trajectories on a p-level grid: elementary effects, N (d + 1) points'},
    "file": {"distributions": False, "sample": False, "per_factor": 0, "extra": 1, "iid_blocks": 1,
        "description": 'the points of a CSV file (design.file), one case per row, one column per factor named by its key path'},
}

# design.factors[i].distribution -> its parameters (design.json's keys) and whether its
# support is finite
DISTRIBUTIONS = {
    "uniform": {"keys": ('lower', 'upper'), "bounded": True, "description": 'uniform on [lower, upper]'},
    "normal": {"keys": ('mean', 'std'), "bounded": False, "description": 'normal (Gaussian)'},
    "truncated-normal": {"keys": ('mean', 'std', 'lower', 'upper'), "bounded": True, "description": 'normal of mean and std restricted to [lower, upper]'},
    "lognormal": {"keys": ('mean', 'std'), "bounded": False, "description": 'lognormal with this mean and std of the variable itself (> 0)'},
    "triangular": {"keys": ('lower', 'mode', 'upper'), "bounded": True, "description": 'triangular on [lower, upper] peaking at mode'},
    "discrete": {"keys": ('values', 'weights'), "bounded": True, "description": 'the listed values with their weights (equal weights if none are given)'},
}

# the summary columns of the case record (its fields but those of the case file only):
# neither grid coordinates nor metrics
RECORD_COLUMNS = (
    "case_id",
    "case_index",
    "scene",
    "status",
    "message",
    "t_reached_s",
    "wall_time_s",
    "steps_accepted",
    "steps_rejected",
    "rhs_calls",
    "friction_switches",
    "started_utc",
    "finished_utc",
)
