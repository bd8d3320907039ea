"""Messages and progress of rodend.run_study where a Python user looks.

The runner's messages (cases already complete, temporary files removed, a summary repaired, a
case file moved aside, the resume command after an interrupt) go to the logger "rodend":
warnings at WARNING (shown under a notebook cell, or on sys.stderr, even with logging not
configured), the others at INFO. Progress, with `progress=True`: a tqdm bar (tqdm.auto: a
widget in a notebook with ipywidgets, else tqdm's text bar, on sys.stderr) when tqdm is
installed (Debian: python3-tqdm), else the command line's progress line written to
sys.stderr (an updating line on a terminal, a line every 10 s and at the end otherwise);
`progress=callable`: called with a Progress after each case. Both go through Python's
sys.stderr, not the process's file descriptor 2, so a notebook shows them under the cell and
contextlib.redirect_stderr captures them.

The callbacks are called from the run's worker threads, one at a time, with the interpreter lock
held; an exception raised in one stops the calls and run_study raises it after the run.
"""
import collections
import logging
import sys
import warnings

logger = logging.getLogger("rodend")

Progress = collections.namedtuple("Progress", "done total failed elapsed_s eta_s")
Progress.__doc__ = ("One case more complete: `done` of `total` cases complete (those of earlier "
                    "runs included), `failed` of them failed; seconds since the start and the "
                    "estimated seconds left.")


def log_message(text):
    """A runner message to the logger "rodend" (WARNING for warnings and stops, else INFO)."""
    warn = text.startswith("warning: ") or text.startswith("stopped by ")
    logger.log(logging.WARNING if warn else logging.INFO, "%s", text)


def _duration(s):
    s = int(round(s))
    return f"{s // 3600}h{s // 60 % 60:02d}m{s % 60:02d}s" if s >= 3600 else \
        f"{s // 60}m{s % 60:02d}s" if s >= 60 else f"{s}s"


class TextLine:
    """The command line's progress line, on Python's sys.stderr."""

    def __init__(self):
        self.last = None
        self.open = False  # an updating line without its newline is on the terminal

    def __call__(self, p):
        out = sys.stderr
        text = (f"[{p.done}/{p.total}] {p.failed} failed, elapsed {_duration(p.elapsed_s)}, "
                f"ETA {_duration(p.eta_s)}")
        if getattr(out, "isatty", lambda: False)():
            out.write("\r" + text + "   " + ("\n" if p.done == p.total else ""))
            self.open = p.done != p.total
        elif p.done == p.total or self.last is None or p.elapsed_s - self.last >= 10.0:
            self.last = p.elapsed_s
            out.write(f"rodend: {p.done}/{p.total} cases done, {p.failed} failed, elapsed "
                      f"{_duration(p.elapsed_s)}, ETA {_duration(p.eta_s)}\n")
        out.flush()

    def break_line(self):
        """Ends the updating line, so that a message starts on a line of its own."""
        if self.open:
            sys.stderr.write("\n")
            sys.stderr.flush()
            self.open = False

    def close(self):
        self.break_line()


class Bar:
    """A tqdm bar over the cases (tqdm.auto: a notebook widget where ipywidgets are)."""

    def __init__(self, tqdm):
        self.tqdm, self.bar = tqdm, None

    def __call__(self, p):
        if self.bar is None:
            self.bar = self.tqdm(total=p.total, initial=p.done - 1, unit="case", smoothing=0,
                                 desc="rodend", file=sys.stderr)
        # the bar's clock is the run's: its rate is the cases done in this run over the run's
        # time, as the ETA (not one case over the microseconds since the bar was made)
        self.bar.start_t = self.bar._time() - p.elapsed_s
        self.bar.n = p.done
        self.bar.set_postfix_str(f"{p.failed} failed", refresh=False)
        self.bar.refresh()

    def break_line(self):
        """Closes the bar (left as it is) so that a message starts on a line of its own; the
        next case opens another."""
        self.close()

    def close(self):
        if self.bar is not None:
            self.bar.close()
            self.bar = None


def display(progress):
    """What shows progress=True: a tqdm bar when tqdm imports, else the text line."""
    if progress is not True:
        return None
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # tqdm's "IProgress not found" without ipywidgets
            from tqdm.auto import tqdm
    except ImportError:
        return TextLine()
    return Bar(tqdm)


class Reporter:
    """The on_message and on_progress of one run: logging, the display, the user's callback."""

    def __init__(self, progress):
        if not (isinstance(progress, bool) or callable(progress)):
            raise TypeError(f"progress: expected True, False or a callable taking a "
                            f"rodend.Progress, got {type(progress).__name__} {progress!r}")
        self.callback = progress if callable(progress) and not isinstance(progress, bool) \
            else None
        self.shown = display(progress)
        self.rename = None  # (temporary study file, what names it for the user)

    def message(self, text):
        if self.rename:
            text = text.replace(*self.rename)
        if self.shown is not None:
            self.shown.break_line()
        log_message(text)

    def progress(self, done, total, failed, elapsed_s, eta_s):
        p = Progress(done, total, failed, elapsed_s, eta_s)
        logger.debug("%d/%d cases done, %d failed", done, total, failed)
        for f in (self.shown, self.callback):
            if f is not None:
                f(p)

    def close(self):
        if self.shown is not None:
            self.shown.close()
