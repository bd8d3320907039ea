"""The analysis of a designed study, behind rodend.analyze: one module per job.

run        rodend.analyze, analyze_arrays (one metric from arrays) and the command line
inputs     read a results folder with design.json: the design, the groups (grid points), the
           metric columns, thresholds
distributions  design.json's factors as OpenTURNS distributions
sobol      first-order and total Sobol indices from a Saltelli pick-freeze design (OpenTURNS)
morris     Morris elementary effects from the design's unit-space trajectories
chaos      a polynomial-chaos surrogate (OpenTURNS) with its exact leave-one-out Q² and validation
basis      the chaos's basis per factor (a lognormal through its log), its orthonormality checked
stats      a metric's distribution: mean, std, quantiles, exceedance, with intervals
bands      quantile bands of histories over time across the ok cases
figures    the analysis-*.png figures
output     analysis.json, bands.h5 and the table printed to stdout
"""
