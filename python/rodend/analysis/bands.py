"""Quantile bands (5, 50, 95 %) of recorded histories over time across the ok cases.

Each case file is opened through the one verified reader (rodend.casefiles.CaseFiles: its
checksum and the case id it holds checked before HDF5 reads it; a damaged or foreign file is a
CorruptFile naming it, a missing one a FileNotFoundError), then /signals/time and the signal
are read with h5py. When every case's time
samples are a prefix of the longest case's (a study's fixed sample interval) the bands are taken
sample by sample; otherwise each case is interpolated linearly onto the longest case's time
samples. Past a case's end it is NaN, and the bands at a time are over the cases that reached
it. A vector signal (n, 3) gets bands per component. Memory: one pass over the case files
fills a (cases × time) array per signal when all of them fit in MEMORY bytes (512 MB) and the
cases share the first case's time samples; otherwise the cases are read again a block of time
samples at a time, MEMORY bytes at most (a thesis cycle of 24,001 samples over 10,000 cases is
1.9 GB a component in one piece).
"""
import numpy as np

from ..casefiles import CaseFiles, _units

LEVELS = (0.05, 0.5, 0.95)
MEMORY = 512 * 2 ** 20


def _survey(files, signals):
    """(longest time, per case: its length and whether its time is a prefix of the longest,
    {signal: units}, {signal: component shape}, {signal: stack (cases, time[, w])} or None), in
    one pass over the files that keeps only the longest time so far. The stacks are filled as
    the files are read while every case's time is a prefix of the first case's and they fit in
    MEMORY; otherwise None (the values are read again in blocks)."""
    lengths, same, longest, units, shape, stacks = [], [], None, {}, {}, {}
    case_ids = files.case_ids
    for i in range(len(case_ids)):
        path = files.path(i)
        with files.open(i) as f:
            g = f["signals"]
            t = g["time"][()]
            for sig in signals:
                if sig not in g:
                    raise ValueError(f"history {sig!r}: not recorded in {path}; recorded: "
                                     f"{', '.join(sorted(n for n in g if n != 'time'))}")
                units.setdefault(sig, _units(g[sig]))
                shape.setdefault(sig, g[sig].shape[1:])
            if i == 0:
                size = 8 * len(t) * len(case_ids) * sum(
                    int(np.prod(shape[sig], dtype=np.int64)) for sig in signals)
                stacks = {sig: np.full((len(case_ids), len(t)) + shape[sig], np.nan)
                          for sig in signals} if size <= MEMORY else None
            if stacks is not None and len(t) <= stacks[signals[0]].shape[1] and \
                    np.array_equal(t, longest[:len(t)] if longest is not None else t):
                for sig in signals:
                    stacks[sig][i, :len(t)] = g[sig][()]
            else:
                stacks = None
        if longest is not None and len(t) > len(longest):
            if not np.array_equal(longest, t[:len(longest)]):
                same = [False] * len(same)   # interpolated: exact on an equal grid anyway
            longest = None
        if longest is None:
            longest = t
        lengths.append(len(t))
        same.append(np.array_equal(t, longest[:len(t)]))
    return longest, np.array(lengths), np.array(same), units, shape, stacks


def _block(files, signal, longest, lengths, same, a, b, shape):
    """The values of every case at the longest time's samples a..b-1 (NaN past a case's end)."""
    out = np.full((len(files.case_ids), b - a) + shape, np.nan)
    for i in range(len(files.case_ids)):
        with files.open(i) as f:
            g = f["signals"]
            if same[i]:
                e = min(b, lengths[i])
                if e > a:
                    out[i, :e - a] = g[signal][a:e]
                continue
            t, v = g["time"][()], g[signal][()].reshape(lengths[i], -1)
        tt = longest[a:b]
        inside = tt <= t[-1]
        cols = [np.interp(tt[inside], t, c) for c in v.T]
        out[i, inside] = np.column_stack(cols).reshape((int(inside.sum()),) + shape)
    return out


def _quantiles(stack):
    """The LEVELS quantiles along axis 0, NaN (a case past its end) left out. (Called on blocks
    of 64 time samples: numpy's quantile copies its input.)"""
    if not np.isnan(stack).any():
        return np.quantile(stack, LEVELS, axis=0)
    return np.nanquantile(stack, LEVELS, axis=0)


def bands(folder, case_ids, signals):
    """{signal: {time, levels, quantiles (len(LEVELS), nt[, w]), cases, units, resampled}}."""
    if len(case_ids) == 0:
        raise ValueError(f"histories {', '.join(signals)}: no ok case to draw bands from")
    files = CaseFiles(folder, case_ids)
    longest, lengths, same, units, shape, stacks = _survey(files, list(signals))
    out = {}
    for sig in signals:
        b = out[sig] = {"time": longest, "levels": list(LEVELS), "cases": len(case_ids),
                        "units": units[sig], "resampled": not bool(same.all())}
        if stacks is not None:
            stack = stacks.pop(sig)
            b["quantiles"] = np.concatenate([_quantiles(stack[:, a:a + 64]) for a in
                                             range(0, len(longest), 64)], axis=1)
            del stack
            continue
        width = int(np.prod(shape[sig], dtype=np.int64)) if shape[sig] else 1
        step = max(1, MEMORY // (8 * width * len(case_ids)))
        q = np.empty((len(LEVELS), len(longest)) + shape[sig])
        for a in range(0, len(longest), step):
            e = min(len(longest), a + step)
            q[:, a:e] = _quantiles(_block(files, sig, longest, lengths, same, a, e, shape[sig]))
        b["quantiles"] = q
    return out
