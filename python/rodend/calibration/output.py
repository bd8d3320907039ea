"""The calibration's results folder, written whole or not at all: every file goes into a
fresh temporary folder beside the target (created exclusively: `mkdir` fails on anything
already there, a planted link included), each text file opened with O_CREAT | O_EXCL |
O_NOFOLLOW (the figures are written by matplotlib inside that private folder);
the folder is renamed into place at the end (an earlier result of the same name is moved
aside first and removed after). An error on the way removes the temporary folder."""
import json
import os
import secrets
import shutil
import socket

from ..analysis.output import plain


def _temp_name(target):
    parent, name = os.path.split(os.path.abspath(target))
    return os.path.join(parent, f".{name}.tmp.{socket.gethostname()}.{os.getpid()}."
                                f"{secrets.randbits(64)}")


class ResultsFolder:
    """with ResultsFolder(path) as out: out.write_text(name, text); out.path(name) for
    writers that need a path (figures: written to a name inside the private folder)."""

    def __init__(self, target):
        self.target = os.path.abspath(target)

    def __enter__(self):
        os.makedirs(os.path.dirname(self.target), exist_ok=True)
        self.tmp = _temp_name(self.target)
        os.mkdir(self.tmp, 0o755)
        return self

    def path(self, name):
        return os.path.join(self.tmp, name)

    def write_text(self, name, text):
        fd = os.open(self.path(name), os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW,
                     0o644)
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text)
            fh.flush()
            os.fsync(fh.fileno())

    def write_json(self, name, doc):
        self.write_text(name, json.dumps(plain(doc), indent=1, allow_nan=False) + "\n")

    def __exit__(self, kind, error, tb):
        if kind is not None:
            shutil.rmtree(self.tmp, ignore_errors=True)
            return False
        old = None
        if os.path.lexists(self.target):
            old = _temp_name(self.target).replace(".tmp.", ".old.")
            os.rename(self.target, old)
        os.rename(self.tmp, self.target)
        if old:
            if os.path.isdir(old) and not os.path.islink(old):
                shutil.rmtree(old, ignore_errors=True)
            else:
                os.unlink(old)
        return False


def samples_csv(keys, chains):
    lines = ["chain,draw," + ",".join(keys)]
    for c, ch in enumerate(chains):
        for i, row in enumerate(ch):
            lines.append(f"{c},{i}," + ",".join(f"{v:.10g}" for v in row))
    return "\n".join(lines) + "\n"


def table(doc):
    """The estimate as lines of text."""
    lines = [f"calibration {doc['name']}: {doc['status']}"]
    for u in doc["posterior"]["unknowns"]:
        lines.append(f"  {u['key']}: mean {u['mean']:.6g}, 90 % interval "
                     f"[{u['q05']:.6g}, {u['q95']:.6g}] (median {u['q50']:.6g}); "
                     f"{u['identifiability']}")
    keys = [u["key"] for u in doc["posterior"]["unknowns"]]
    corr = doc["posterior"]["correlation"]
    for i in range(len(keys)):
        for j in range(i + 1, len(keys)):
            lines.append(f"  correlation {keys[i]} / {keys[j]}: {corr[i][j]:+.3f}")
    d = doc["diagnostics"]
    lines.append(f"  chains: R-hat max {max(d['rhat']):.4f}, ESS min {min(d['ess']):.0f}, "
                 f"acceptance {min(d['acceptance']):.2f}-{max(d['acceptance']):.2f}")
    s = doc["surrogate"]
    lines.append(f"  surrogate: {s['training_cases']} training + {s['validation_cases']} "
                 f"held-out cases, degree {s['degree']}, held-out RMS error "
                 f"{s['heldout_error_over_noise']:.3f} x noise std; final full-model run "
                 f"residual {doc['final_run']['residual_over_noise']:.3f} x noise std")
    for m in doc.get("problems", []):
        lines.append("  PROBLEM: " + m)
    p = doc.get("prognosis")
    if p:
        q = p["cycles_to_limit"]
        lines.append(f"  prognosis: {p['limit_name']} reaches {p['limit']:.6g} {p['unit']} after "
                     f"{q['q05']:.3g} / {q['q50']:.3g} / {q['q95']:.3g} {p['cycle_name']} "
                     "(5/50/95 %)")
    return "\n".join(lines)
