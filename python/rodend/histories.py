"""The histories of a study's results folder as xarray Datasets (rodend.Results.histories,
Results.case): all cases lazily over the study's dimensions, or one case read at once."""
import numpy as np

from . import naming
from .casefiles import _long_name, _units
from .lazy import CaseStack, lazy_variable

_TIME = {"units": "s", "long_name": "time", "description": "simulation time"}


def _per_case(res, key, fallback):
    """The value of `key` for every case: its summary column when it is one, else `fallback`."""
    s = res.summary
    if key in s:
        return s[key].to_numpy(float)
    return np.full(len(s), float(fallback))


def time_axis(res):
    """(time coordinate or None, samples, shared): the samples k * sample_interval up to
    time.end of the longest case; `shared` is False when the cases' sample intervals differ
    (then each case's times are a variable over dimension `sample`)."""
    s = res.summary
    ref = res._reference_rows()[0]
    with res._files.open(ref) as f:
        t = f["signals/time"][()] if "time" in f["signals"] else np.zeros(0)
    # the reference case's own samples first (t[1] is the sample interval exactly), the study
    # document's time when it stopped early
    doc = res.study.get("time", {}) if isinstance(res.study.get("time"), dict) else {}
    complete = "status" not in s or s["status"].iloc[ref] == "ok"
    end0 = t[-1] if complete and len(t) else doc.get("end", t[-1] if len(t) else 0.0)
    dt0 = t[1] - t[0] if len(t) > 1 else doc.get("sample_interval", end0 or 1.0)
    end, dt = _per_case(res, "time.end", end0), _per_case(res, "time.sample_interval", dt0)
    nt = int(np.max(np.floor(end / dt + 1e-9)) + 1) if len(s) else 0
    if len(np.unique(dt)) > 1:
        return None, nt, False
    if len(t) == nt:
        return t, nt, True
    return np.minimum(np.arange(nt) * dt[0], np.max(end)), nt, True


def lazy_histories(res):
    """Every recorded signal (or those asked for) over res.dimensions() and time; nothing is
    read until values are accessed, then only the case files selected."""
    s = res.summary
    axes = res.dimensions()
    shape, dims = tuple(a[2] for a in axes), tuple(a[0] for a in axes)
    res._files.check_present()
    recorded = res.recorded_signals()
    names = [n for n in (res._signals or recorded) if n != "time"]
    time, nt, shared = time_axis(res)
    tdim = "time" if shared else "sample"
    coords = res._axis_coords(axes)
    variables = {}
    for n in names:
        units, sentence, width = recorded[n]
        cdims = ()
        if width:
            cdim, labels = naming.components(n, width)
            cdims = (cdim,)
            coords[cdim] = (cdim, labels)
        stack = CaseStack(res._files, n, shape, nt, width, time if shared else None)
        variables[n] = lazy_variable(dims + (tdim,) + cdims, stack,
                                     naming.attrs(n, units, sentence))
    if shared:
        coords["time"] = ("time", time, dict(_TIME))
    else:
        variables["time"] = lazy_variable(dims + ("sample",),
                                          CaseStack(res._files, "time", shape, nt), dict(_TIME))
    for extra in ("status", "case_id"):
        if extra in s:
            coords[extra] = (dims, s[extra].to_numpy().reshape(shape),
                             {"long_name": extra.replace("_", " ")})
    return res._with_aliases(naming.dataset(variables, coords=coords,
                                            attrs=res._dataset_attrs()), axes)


def case_dataset(res, row, names=None):
    """Case `row` of the summary: its signals over time (components labelled), its grid
    values as scalar coordinates; read now."""
    s = res.summary
    data, coords = {}, {}
    with res._files.open(row) as f:
        g = f["signals"]
        for n in g:
            if n == "time" or (names is not None and n not in names):
                continue
            d = g[n]
            dims = ("time",)
            if d.ndim == 2:
                cdim, labels = naming.components(n, d.shape[1])
                dims += (cdim,)
                coords[cdim] = (cdim, labels)
            data[n] = (dims, d[()], naming.attrs(n, _units(d), _long_name(d)))
        if "time" in g:
            coords["time"] = ("time", g["time"][()], dict(_TIME))
    for _, keys, _ in res.dimensions():
        for key in keys:
            if key in s:
                coords.update(res._coordinate(key, (), s[key].iloc[row]))
    attrs = res._dataset_attrs()
    attrs.update({k: s[k].iloc[row] for k in ("case_id", "status", "scene") if k in s})
    return naming.dataset(data, coords=coords, attrs=attrs)
