"""One signal of every case of a study as a lazily indexed array (xarray's own lazy backend,
as xarray.open_dataset uses for a file): shape (grid dims..., time[, component]); indexing it
reads only the case files it selects, one at a time, so memory is bounded by what is accessed.
No dask is needed (and none is used)."""
import itertools

import numpy as np
from xarray.backends import BackendArray
from xarray.core import indexing


class CaseStack(BackendArray):
    """Signal `name` of the cases of `files` (rodend.casefiles.CaseFiles) laid out over
    `grid_shape` (case k at the k-th position in C order), `nt` samples (a case that stopped
    early is NaN past its end) and `width` components (None for a scalar). With `time`, each
    case read must be sampled at a prefix of it (checked)."""

    def __init__(self, files, name, grid_shape, nt, width=None, time=None):
        self.files, self.name, self.time = files, name, time
        self.grid_shape = tuple(grid_shape)
        self.shape = self.grid_shape + (nt,) + ((width,) if width else ())
        self.dtype = np.dtype(np.float64)

    def __getitem__(self, key):
        return indexing.explicit_indexing_adapter(key, self.shape,
                                                  indexing.IndexingSupport.OUTER, self._read)

    def _read(self, key):
        key = tuple(key)
        picks = [np.atleast_1d(np.arange(n)[k]) for n, k in zip(self.shape, key)]
        ng = len(self.grid_shape)
        out = np.full([len(p) for p in picks], np.nan)
        for pos in itertools.product(*(range(len(p)) for p in picks[:ng])):
            case = int(np.ravel_multi_index(tuple(p[j] for p, j in zip(picks, pos)),
                                            self.grid_shape))
            values = self._case(case)
            if values is None:
                continue
            rows = picks[ng]
            inside = rows < len(values)
            got = values[rows[inside]]
            if len(picks) > ng + 1:
                got = got[:, picks[ng + 1]]
            out[pos][inside] = got
        # an integer in the key drops its dimension
        return out[tuple(0 if isinstance(k, (int, np.integer)) else slice(None) for k in key)]

    def _case(self, case):
        """Case `case`'s values of the signal (None when it does not record it)."""
        with self.files.open(case) as f:
            g = f["signals"]
            if self.name not in g:
                return None
            values = g[self.name][()]
            if self.time is not None and "time" in g:
                t = g["time"][()]
                if len(t) > len(self.time) or not np.array_equal(t, self.time[:len(t)]):
                    raise ValueError(
                        f"{self.files.path(case)}: sampled at other times than the study's "
                        "time coordinate; read it alone with Results.case()")
        return values


def lazy_variable(dims, stack, attrs):
    """An xarray.Variable over `dims` whose values are read from `stack` on access."""
    import xarray as xr
    return xr.Variable(dims, indexing.LazilyIndexedArray(stack), attrs)
