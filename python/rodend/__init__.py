"""rodend from Python: run a case or a study, read a study's results as pandas and xarray.

    import rodend
    case = rodend.run_case("gravity-drop", {"contact.clearance": 2e-4},
                           time={"end": 0.1, "sample_interval": 1e-4})
    case.signals["eccentricity"]          # numpy array, one value per sample
    case.metrics["first_impact_peak_force"], case.metric_units["first_impact_peak_force"]

    rc, folder = rodend.run_study("studies/default.json", threads=2)
    res = rodend.open_results(folder)
    res.summary                           # pandas.DataFrame, one row per case (summary.csv)
    res.summary_dataset                   # xarray.Dataset: dims = the grid axes
    res.histories                         # xarray.Dataset, lazy: dims = the grid axes and time
    res.case(0)                           # one case's histories, its grid values as coordinates

    rodend.analyze(folder)                # a designed study: Sobol, Morris, chaos, exceedance

Everything runs through the same C++ loader and runner as the `rodend` command: a bad input
raises rodend.InputError (a ValueError) with the command line's message, naming the file, the
key path and what was expected. Nothing is written to disk unless asked (`run_case(...,
write=path)`; `run_study` writes its results folder as `rodend run` does).

The compiled part (rodend._rodend) is built by `bash scripts/main.sh` (or setup.sh) into
<repo>/build/python/; this package finds it there, or in $RODEND_BUILD_DIR/python (a build
directory of another name), or next to itself. It is loaded when first needed (running, the
catalogues, InputError, __version__): reading results (open_results, open_study, the figures
of plots/) works without it.

This module only re-exports: running is rodend/running.py, loading the compiled part
rodend/extension.py, and every reader of a results folder (open_results: pandas and xarray;
open_study: numpy; summary_rows) reads through rodend/casefiles.py.
"""
from .naming import UnknownName
from .running import (Case, load_study, parameters, run_case, run_study, scenes, schema,
                      signal_catalogue)

__all__ = ["InputError", "run_case", "run_study", "load_study", "open_results", "Case",
           "Results", "CorruptFile", "UnknownName", "schema", "scenes", "parameters",
           "signal_catalogue", "analyze", "Progress", "open_study", "Study", "NotAStudy",
           "summary_rows", "verify_checksum"]

# the names of the modules imported on first use: reading results needs h5py (pandas and xarray
# for Results), the analysis openturns and matplotlib; importing rodend needs numpy only
_LAZY = {"open_results": "results", "Results": "results", "open_study": "study",
         "Study": "study", "NotAStudy": "casefiles", "CorruptFile": "casefiles",
         "verify_checksum": "casefiles", "summary_rows": "casefiles", "Progress": "progress",
         "analyze": "analysis.run"}


def __getattr__(name):
    from . import extension
    if name in extension._FROM_EXTENSION:
        extension.get()
        return globals()[name]
    if name in _LAZY:
        import importlib
        return getattr(importlib.import_module("." + _LAZY[name], __name__), name)
    raise AttributeError(name)


def __dir__():
    return sorted(set(globals()) | set(__all__))
