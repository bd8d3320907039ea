"""`python3 -m rodend.calibrate CONFIG.json`: the command line of `rodend calibrate` (the
calibration of unknown parameters from a measured record; the code: rodend/calibration/,
run.py first). Exit 0 ok, 1 a failed diagnostic, 2 a bad input."""
import sys

from rodend.calibration.run import calibrate, main  # noqa: F401

if __name__ == "__main__":
    sys.exit(main())
