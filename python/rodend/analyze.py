"""`python3 -m rodend.analyze FOLDER [--metric M]... [--threshold M=VALUE]... [--history S]...
[--bootstrap N]`: the command line of rodend.analyze (the analysis of a study with a sampled
design; the code: rodend/analysis/, run.py first). Exit 0, or 2 with a message for bad input."""
import sys

from rodend.analysis.run import main

if __name__ == "__main__":
    sys.exit(main())
