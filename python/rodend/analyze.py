"""`python3 -m rodend.analyze FOLDER [--metric M]... [--threshold M=VALUE]... [--history S]...
[--bootstrap N]`: the command line of rodend.analyze (the analysis of a study with a sampled
design; the code: rodend/analysis/, run.py first). Exit 0, or 2 with a message for bad input."""
import sys
import types

from rodend.analysis.run import analyze, main


class _CallableModule(types.ModuleType):
    """`import rodend.analyze` makes rodend.analyze this module instead of the function (the
    import system sets the package's attribute to the submodule): calling it still analyses."""

    def __call__(self, *args, **kwargs):
        return analyze(*args, **kwargs)


sys.modules[__name__].__class__ = _CallableModule

if __name__ == "__main__":
    sys.exit(main())
