"""The calibration of unknown parameters from a measured record, and the prognosis that
follows (docs/health-monitoring.md), behind `rodend calibrate`: one module per job.

run        the steps and the command line (python3 -m rodend.calibrate)
config     the configuration file, read and checked
record     the measured record (CSV or HDF5, the profile readers' rules)
noise      the noise model, and the synthetic records made from it
forward    the test run by rodend: designed studies, single runs, signals at feature times
surrogate  principal components of the features, a polynomial chaos each, held-out check
posterior  the priors, the likelihood, OpenTURNS's Metropolis-Hastings and its diagnostics
prognosis  the posterior through the wear evolution: cycles to a limit
figures    the figures
output     the results folder, written atomically
"""
